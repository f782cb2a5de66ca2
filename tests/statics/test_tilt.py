"""Tilted gravity (the tilting-table test): the loads turned, the options that ask for it.

A tilt of theta towards azimuth phi turns every load about the horizontal axis d x y, d the unit
vector of phi in the ground plane (from +x towards +z): gravity -g y becomes
g (sin(theta) d - cos(theta) y). Turning the loads must give the same analysis as a model built
with its gravity (and point loads) turned by hand.
"""

import math

import numpy as np
import pytest

from shapegen.errors import OptionError
from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.statics import StaticsOptions, analyze
from shapegen.statics.tilt import (
    direction,
    lateral_map,
    load_direction_problem,
    normalized_azimuth,
    rotation,
)


@pytest.mark.parametrize("tilt", [0.0, 10.0, 45.0, 80.0])
@pytest.mark.parametrize("azimuth", [0.0, 30.0, 90.0, 200.0, 315.0])
def test_gravity_turns_towards_the_azimuth(tilt, azimuth):
    turned = rotation(tilt, azimuth)
    np.testing.assert_allclose(turned @ turned.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(turned) == pytest.approx(1.0)
    a, t = math.radians(azimuth), math.radians(tilt)
    expected = 9.81 * np.array([math.sin(t) * math.cos(a), -math.cos(t), math.sin(t) * math.sin(a)])
    np.testing.assert_allclose(turned @ [0.0, -9.81, 0.0], expected, atol=1e-12)


@pytest.mark.parametrize("azimuth", [0.0, 90.0, 123.0])
def test_the_lateral_load_of_a_weight_is_horizontal_towards_the_azimuth(azimuth):
    np.testing.assert_allclose(lateral_map(azimuth) @ [0.0, -2.0, 0.0], 2 * direction(azimuth))
    # and it is the rate of change of the turned load at tilt 0
    h = 1e-6
    slope = (rotation(math.degrees(h), azimuth) - np.eye(3)) / h
    np.testing.assert_allclose(slope, lateral_map(azimuth), atol=1e-5)


@pytest.mark.parametrize("value, expected", [(-90, 270), (720, 0), (359.99999, 359.99999), (0, 0)])
def test_azimuths_are_normalised(value, expected):
    assert normalized_azimuth(value) == pytest.approx(expected)
    assert StaticsOptions(tilt=5, azimuth=value).azimuth == pytest.approx(expected)


@pytest.mark.parametrize(
    "settings, message",
    [
        ({"tilt": 90}, "below 90"),
        ({"tilt": 95.0}, "below 90"),
        ({"tilt": -1}, "at least 0"),
        ({"tilt": float("nan")}, "tilt"),
        ({"tilt": "steep"}, "tilt"),
        ({"tilt": True}, "tilt"),
        ({"tilt": 5, "azimuth": float("inf")}, "azimuth"),
        ({"tilt": 5, "azimuth": "north"}, "azimuth"),
    ],
)
def test_bad_tilts_are_refused(settings, message):
    with pytest.raises(OptionError, match=message):
        StaticsOptions(**settings)


def leaning_model(gravity=(0.0, -9.81, 0.0), loads=()):
    """A slender pier of three blocks and a lintel block resting on it off-centre."""
    blocks = [
        Block.box([0, 0, 0], [0.4, 0.5, 0.6], id="a"),
        Block.box([0, 0.5, 0], [0.4, 1.0, 0.6], id="b"),
        Block.box([0, 1.0, 0], [0.4, 1.5, 0.6], id="c"),
        Block.box([0.0, 1.5, 0], [0.7, 1.7, 0.6], id="lintel"),
    ]
    return Model(blocks, gravity=np.array(gravity), loads=list(loads), friction=0.6)


@pytest.mark.parametrize("tilt, azimuth", [(3.0, 0.0), (12.0, 0.0), (8.0, 180.0), (10.0, 60.0)])
@pytest.mark.parametrize("pyramid", ["4", "cone"])
def test_a_tilt_is_the_model_with_its_loads_turned(tilt, azimuth, pyramid):
    load = PointLoad("c", np.array([0.0, -300.0, 0.0]), np.array([0.3, 1.5, 0.3]))
    turned = rotation(tilt, azimuth)
    by_hand = leaning_model(
        gravity=turned @ [0.0, -9.81, 0.0],
        loads=[PointLoad("c", turned @ load.force, load.point)],
    )
    expected = analyze(by_hand, pyramid=pyramid)
    tilted = analyze(leaning_model(loads=[load]), pyramid=pyramid, tilt=tilt, azimuth=azimuth)
    assert tilted.feasible is expected.feasible
    assert tilted.infeasibility_normalized == pytest.approx(
        expected.infeasibility_normalized, rel=1e-4, abs=1e-9
    )
    assert tilted.to_report()["tilt"] == {
        "tilt_deg": tilt,
        "azimuth_deg": azimuth,
        "load_multiplier": pytest.approx(math.tan(math.radians(tilt))),
        "azimuth": "given",
    }


def test_the_verdict_changes_with_the_tilt():
    # the lintel's centroid is 0.05 m inside the pier's edge, 0.1 m above the joint: it tips
    # towards +x at atan(0.05 / 0.1) = 26.6 deg, if the pier itself did not go first
    model = leaning_model()
    assert analyze(model).feasible
    assert not analyze(model, tilt=30.0, azimuth=0.0).feasible
    upright = analyze(model, tilt=0.0)
    assert upright.to_report().get("tilt") is None


def test_without_an_azimuth_the_tilt_is_towards_the_worst_direction():
    # A 0.3 x 1 x 0.6 m block tips at atan(0.3) = 16.7 deg across its narrow side (x) and at
    # 31 deg across its wide side (z): tilted by 20 deg, it stands towards z, falls towards x.
    model = Model([Block.box([0, 0, 0], [0.3, 1.0, 0.6])], friction=5.0)
    assert analyze(model, tilt=20.0, azimuth=90.0).feasible
    worst = analyze(model, tilt=20.0)
    assert not worst.feasible
    report = worst.to_report()["tilt"]
    assert report["azimuth"] == "worst" and report["azimuth_deg"] in (0.0, 180.0)
    assert "directions" in worst.timings
    assert analyze(model, tilt=15.0).feasible


def test_loads_that_are_not_vertical_are_named():
    assert load_direction_problem(leaning_model()) is None
    sideways = leaning_model(gravity=(1.0, -9.81, 0.0))
    assert "gravity" in load_direction_problem(sideways)
    pushed = leaning_model(loads=[PointLoad("b", np.array([50.0, 0, 0]), np.array([0, 1, 0.3]))])
    assert "'b'" in load_direction_problem(pushed)


def test_the_adjoint_gradient_keeps_the_tilt():
    # A 0.3 m wide pier falls at 20 deg towards +x; widening it by h lowers y/W^2 as the
    # tilted analyses of the two piers say (the envelope theorem, with the loads turned).
    from shapegen.statics.sensitivity import infeasibility_change

    options = StaticsOptions(tilt=20.0, azimuth=0.0, friction=5.0)

    def pier(width):
        return Model([Block.box([0, 0, 0], [width, 1.0, 0.8])], friction=5.0)

    base = analyze(pier(0.3), options)
    assert not base.feasible
    h = 1e-5
    change = infeasibility_change(base, pier(0.3 + h), options)
    difference = analyze(pier(0.3 + h), options).infeasibility_normalized
    difference -= base.infeasibility_normalized
    assert change is not None and change < 0
    assert change == pytest.approx(difference, rel=1e-2)
    upright = infeasibility_change(analyze(pier(0.3), friction=5.0), pier(0.3 + h), options)
    assert upright == 0.0  # it stands upright: nothing to change
