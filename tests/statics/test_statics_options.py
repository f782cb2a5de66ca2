"""Statics options: one frozen object, checked once; a misspelt or bad option is a clear error."""

import dataclasses

import pytest

from shapegen.errors import OptionError
from shapegen.model import Block, Model
from shapegen.statics import StaticsOptions, analyze
from shapegen.statics.statics_options import Tilt


def _stack() -> Model:
    return Model([Block.box((0, 0, 0), (1, 1, 1)), Block.box((0, 1, 0), (1, 2, 1))])


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        ({"frcition": 0.5}, "unknown statics option 'frcition' (did you mean 'friction'?)"),
        ({"pyramid": "6"}, "pyramid must be one of cone, 4, 4r, 8"),
        ({"kern": 0.0}, "kern must be a number in (0, 1]"),
        ({"kern": "a third"}, "kern must be a number in (0, 1]"),
        ({"solver": "mosek"}, "solver must be one of auto"),
        ({"friction": -0.1}, "friction must be a finite number >= 0"),
        ({"friction": float("nan")}, "friction must be a finite number >= 0"),
        ({"friction": True}, "friction must be a finite number >= 0"),
    ],
)
def test_bad_options_are_one_clear_error(settings, message):
    with pytest.raises(OptionError) as caught:
        analyze(_stack(), **settings)
    assert message in str(caught.value)


def test_options_are_frozen_and_the_keyword_form_is_the_same_analysis():
    options = StaticsOptions(friction=0.4, kern=0.5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.kern = 1.0  # type: ignore[misc]
    by_object = analyze(_stack(), options)
    by_keywords = analyze(_stack(), friction=0.4, kern=0.5)
    assert by_object.feasible == by_keywords.feasible
    assert by_object.infeasibility == pytest.approx(by_keywords.infeasibility, abs=1e-12)
    with pytest.raises(OptionError, match="not both"):
        analyze(_stack(), options, kern=0.5)


def test_a_margin_shrinks_the_kern():
    assert StaticsOptions(kern=0.5).shrunk(0.2).kern == pytest.approx(0.4)
    assert StaticsOptions().to_report() == {
        "friction": None,
        "pyramid": "cone",
        "kern": 1.0,
        "solver": "auto",
        "tilt": 0.0,
        "azimuth": None,
    }
    # a margin shrinks the joints and keeps the tilt
    tilted = StaticsOptions(tilt=10.0, azimuth=90.0).shrunk(0.1)
    assert (tilted.tilt, tilted.azimuth, tilted.kern) == (10.0, 90.0, pytest.approx(0.9))


# ------------------------------------------------------------------ the tilt, one type
@pytest.mark.parametrize(
    ("text", "tilt"),
    [
        ("20", Tilt(20.0)),
        ("20@90", Tilt(20.0, 90.0)),
        ("20@-90", Tilt(20, 270)),
        ("0@450", Tilt(0, 90)),
    ],
)
def test_a_tilt_is_read_and_checked_by_its_type(text, tilt):
    assert Tilt.parse(text) == tilt
    options = StaticsOptions(tilt=tilt.degrees, azimuth=tilt.azimuth)
    assert (options.tilt, options.azimuth) == (tilt.degrees, tilt.azimuth)


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ({"degrees": 90}, "tilt must be a number of degrees, at least 0 and below 90; got 90"),
        ({"degrees": -5}, "got -5; to tilt the other way add 180 to the azimuth (5@180)"),
        ({"degrees": True}, "tilt must be a number of degrees"),
        ({"degrees": 5, "azimuth": float("nan")}, "azimuth must be a finite number of degrees"),
    ],
)
def test_a_tilt_that_cannot_be_is_the_same_line_from_the_type_and_the_options(value, message):
    with pytest.raises(OptionError) as alone:
        Tilt(**value)
    with pytest.raises(OptionError) as within:
        StaticsOptions(tilt=value["degrees"], azimuth=value.get("azimuth"))
    assert str(alone.value) == str(within.value) and message in str(alone.value)
    assert alone.value.option == within.value.option
