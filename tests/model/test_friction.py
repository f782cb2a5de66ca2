"""The friction coefficient's one check (shapegen.model.friction), and the statics' friction
model and joint scale (checked_pyramid, checked_kern): each place that takes one says the same
line, in its own words for the place."""

from __future__ import annotations

import math

import pytest

from shapegen.cli import main
from shapegen.errors import GeometryError, InputFormatError, OptionError, ShapegenError
from shapegen.model.block import Block
from shapegen.model.friction import checked_friction
from shapegen.model.model import Model
from shapegen.readers.blocks_json import model_from_dict
from shapegen.simulation.settings import SimulationSettings
from shapegen.statics.assembly import assemble, friction_cone
from shapegen.statics.statics_options import StaticsOptions, checked_kern, checked_pyramid

CUBE = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
LINE = "friction must be a finite number >= 0; got -0.5"


@pytest.mark.parametrize("value", [0, 0.7, 2, 1e3])
def test_a_coefficient_is_a_finite_number_at_least_zero(value):
    assert checked_friction(value) == float(value)


@pytest.mark.parametrize("value", [-0.5, math.nan, math.inf, True, "much", None, 10**400])
def test_anything_else_is_one_option_error_naming_friction(value):
    with pytest.raises(OptionError) as caught:
        checked_friction(value)
    assert caught.value.option == "friction"
    assert str(caught.value) == f"friction must be a finite number >= 0; got {value!r}"


def test_every_place_that_takes_a_coefficient_says_the_one_line(capsys):
    with pytest.raises(OptionError, match=f"^{LINE}$"):
        StaticsOptions(friction=-0.5)
    model = Model([Block.box([0, 0, 0], [1, 1, 1])])
    with pytest.raises(OptionError, match=f"^{LINE}$"):
        assemble(model, [], friction=-0.5)
    with pytest.raises(GeometryError, match=f"^{LINE}$"):
        Model([Block.box([0, 0, 0], [1, 1, 1])], friction=-0.5).validate()
    document = {"format": "shapegen-blocks", "version": 1, "friction": -0.5,
                "blocks": [{"id": "b0", "vertices": CUBE}]}  # fmt: skip
    with pytest.raises(InputFormatError, match=f'^"friction": {LINE}$'):
        model_from_dict(document)
    with pytest.raises(ShapegenError, match=f"^simulation: {LINE}$"):
        SimulationSettings(friction=-0.5).check()
    assert main(["build", "wall_windows.grammar", "--analyze", "--friction", "-0.5"]) == 2
    assert capsys.readouterr().err.strip().splitlines()[-1].endswith(f"--friction: {LINE}")


def test_the_friction_model_and_the_joint_scale_are_checked_once():
    assert checked_pyramid("4r") == "4r" and checked_kern(1 / 3) == pytest.approx(1 / 3)
    for check in (
        lambda: checked_pyramid("6"),
        lambda: StaticsOptions(pyramid="6"),
        lambda: friction_cone("6", 0.7),
        lambda: assemble(Model([Block.box([0, 0, 0], [1, 1, 1])]), [], pyramid="6"),
    ):
        with pytest.raises(OptionError, match=r"^pyramid must be one of cone, 4, 4r, 8; got '6'$"):
            check()
    for check in (lambda: checked_kern(0), lambda: StaticsOptions(kern=0)):
        with pytest.raises(OptionError, match=r"^kern must be a number in \(0, 1\]; got 0$"):
            check()
