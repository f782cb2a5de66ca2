"""The statics flags are made from StaticsOptions: each field is offered with its own help and
choices, and a value the options type refuses is one line naming the flag."""

from __future__ import annotations

import argparse

import pytest

from shapegen.cli.common_options import (
    CommandLineError,
    Parser,
    add_statics_options,
    statics_options,
)
from shapegen.cli.lateral_options import add_lateral_options
from shapegen.errors import OptionError
from shapegen.statics.statics_options import StaticsOptions, Tilt, statics_fields


def _parser() -> argparse.ArgumentParser:
    parser = Parser(prog="test")
    add_statics_options(parser)
    add_lateral_options(parser)
    return parser


def test_every_field_is_a_flag_with_the_fields_help():
    actions = {a.dest: a for a in _parser()._actions}
    for field in statics_fields():
        dest = "tilt" if field.name == "azimuth" else field.name  # DEG@AZIMUTH
        assert dest in actions, field.name
        if field.name != "azimuth":
            assert actions[dest].help == field.metadata["help"]
            assert tuple(actions[dest].choices or ()) == tuple(field.metadata.get("choices", ()))


def test_the_flags_make_the_options_type():
    args = _parser().parse_args(["--kern", "0.5", "--pyramid", "4", "--tilt", "10@450"])
    assert statics_options(args) == StaticsOptions(kern=0.5, pyramid="4", tilt=10, azimuth=90)
    assert statics_options(_parser().parse_args([])) is None


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--kern", "1.5"], "--kern: kern must be a number in (0, 1]"),
        (["--friction", "-0.1"], "--friction: friction must be a finite number >= 0"),
        (["--solver", "cvxpy", "--pyramid", "cone"], None),  # every back-end takes the cone
    ],
)
def test_a_refused_value_names_its_flag(argv, message):
    args = _parser().parse_args(argv)
    if message is None:
        assert statics_options(args).solver == "cvxpy"
        return
    with pytest.raises(CommandLineError) as raised:
        statics_options(args)
    assert str(raised.value).startswith(message)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--tilt=-10@0"], "tilt must be a number of degrees, at least 0 and below 90; got -10.0"),
        (["--tilt", "10@inf"], "azimuth must be a finite number of degrees; got inf"),
        (["--tilt", "ten"], "expected DEG or DEG@AZIMUTH (degrees), got 'ten'"),
    ],
)
def test_a_refused_tilt_is_the_tilt_types_line_when_read(argv, message):
    # --tilt is read into a Tilt (statics.statics_options), which checks it: its line names the flag
    with pytest.raises(CommandLineError) as raised:
        _parser().parse_args(argv)
    assert str(raised.value).startswith(f"argument --tilt: {message}")
    with pytest.raises(OptionError) as same:
        Tilt.parse(argv[-1].removeprefix("--tilt="))
    assert str(raised.value) == f"argument --tilt: {same.value}"
