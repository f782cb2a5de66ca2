"""The reserve a search judges with holds against sliding as well as hinging: the friction
coefficient is lowered with the joints (statics/reserve.py), and the forces that stood with the
reserve still certify the design without it."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from shapegen.errors import OptionError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.search.search_options import SearchOptions
from shapegen.statics import StaticsOptions, analyze
from shapegen.statics.reserve import widened_forces, with_reserve
from shapegen.statics.statics_options import Reserve
from shapegen.structures import Design
from shapegen.structures.blocks import BlockStatics


def squat_block_on_slope(slope: float, friction: float = 0.7) -> Model:
    """A 1 x 0.25 x 0.5 m block on the ground, gravity tilted by ``slope`` degrees along x: it
    slides at atan(mu) long before it tips (atan(1 / 0.25))."""
    a = math.radians(slope)
    gravity = (9.81 * math.sin(a), -9.81 * math.cos(a), 0.0)
    return Model([Block.box((0, 0, 0), (1, 0.25, 0.5))], gravity=gravity, friction=friction)


def test_the_reserve_shrinks_the_joints_and_lowers_the_friction():
    reserved = with_reserve(StaticsOptions(), 0.1, friction=0.7)
    assert reserved.kern == pytest.approx(0.9) and reserved.friction == pytest.approx(0.63)
    given = with_reserve(StaticsOptions(friction=0.5, kern=0.5), 0.2, friction=0.7)
    assert given.kern == pytest.approx(0.4) and given.friction == pytest.approx(0.4)
    assert with_reserve(StaticsOptions(), 0.0, friction=0.7) == StaticsOptions()
    with pytest.raises(OptionError):
        with_reserve(StaticsOptions(), 1.0, friction=0.7)


def test_a_margin_becomes_a_reserve_once_on_its_way_in():
    reserve = SearchOptions(margin=0.2).margin  # the command line's and the library's edge
    assert type(reserve) is Reserve and reserve == 0.2
    assert Reserve.of(reserve) is reserve  # passed on as it is, not checked again
    assert SearchOptions(margin=reserve).margin is reserve
    copy = pickle.loads(pickle.dumps(reserve))  # to a city's workers
    assert type(copy) is Reserve and copy == reserve
    with pytest.raises(OptionError, match="margin must be at least 0 and below 1; got 1.5"):
        Reserve.of(1.5)
    with pytest.raises(OptionError, match="margin must be a number in"):
        SearchOptions(margin="0.1")


@pytest.mark.parametrize("pyramid", ["cone", "4"])
def test_a_block_on_the_edge_of_sliding_has_no_reserve(pyramid):
    # mu' = 0.7 for the cone, 0.7 / sqrt(2) along a side of the 4-sided pyramid
    mu = 0.7 if pyramid == "cone" else 0.7 / math.sqrt(2)
    slope = math.degrees(math.atan(0.95 * mu))  # slides with a 10 % reserve, not without
    design = Design(model=squat_block_on_slope(slope))
    structure = BlockStatics(StaticsOptions(pyramid=pyramid))
    assert structure.assess(design, margin=0.0).stands
    assert not structure.assess(design, margin=0.1).stands
    # shrinking the joint alone keeps it standing: the kern is no reserve against sliding
    assert analyze(design.model, StaticsOptions(pyramid=pyramid).shrunk(0.1)).feasible
    safer = Design(model=squat_block_on_slope(math.degrees(math.atan(0.85 * mu))))
    assert structure.assess(safer, margin=0.1).stands


def test_forces_that_stood_with_less_friction_certify_the_full_joints():
    model = squat_block_on_slope(20.0)
    narrow = analyze(model, with_reserve(StaticsOptions(), 0.2, friction=model.friction))
    assert narrow.feasible and narrow.problem.friction == pytest.approx(0.56)
    wide = analyze(model, StaticsOptions(), stood=narrow)
    assert wide.feasible and wide.timings["solve"] == 0.0
    x = (narrow.forces / narrow.problem.weight).T.ravel()
    assert widened_forces(narrow.problem, wide.problem, x) is not None
    assert widened_forces(wide.problem, narrow.problem, x) is None  # more friction: refused
    np.testing.assert_allclose(wide.resultant_forces, narrow.resultant_forces, atol=1e-9)
