"""Lateral capacity against closed forms: the largest tilt at which an assembly still stands.

A block of base b and height h on a rough table tilted by theta slides when tan(theta) exceeds
the friction it can mobilise along the slope (mu with the exact cone, mu / sqrt(2) with the
4-sided pyramid whose side faces the slope) and tips when the weight's line of action leaves the
base, tan(theta) > b / h: it falls at whichever angle comes first. The capacity is computed by
the load-multiplier program and must agree with the closed form to the reported resolution, and
with the verdict of the analysis on either side of it.
"""

import math

import numpy as np
import pytest

from shapegen.errors import OptionError, StaticsError
from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.primitives.arch import semicircular_arch
from shapegen.statics import StaticsOptions, analyze, assemble, find_interfaces
from shapegen.statics.capacity import lateral_capacity
from shapegen.statics.multiplier import load_multiplier, worst_direction
from shapegen.tolerances import TILT_RESOLUTION_DEG

HALF = TILT_RESOLUTION_DEG / 2


def block(base: float, height: float, depth: float = 0.5, friction: float = 0.7) -> Model:
    return Model([Block.box([0, 0, 0], [base, height, depth], id="b")], friction=friction)


def degrees_of(ratio: float) -> float:
    return math.degrees(math.atan(ratio))


@pytest.mark.parametrize("friction", [0.3, 0.5, 0.7, 1.2])
@pytest.mark.parametrize("base, height", [(1.0, 0.25), (0.2, 1.0), (0.35, 1.0), (0.5, 0.8)])
def test_a_block_slides_or_tips_whichever_comes_first(friction, base, height):
    model = block(base, height, friction=friction)
    capacity = lateral_capacity(model, StaticsOptions(pyramid="cone"), azimuths=[0.0])
    expected = min(degrees_of(friction), degrees_of(base / height))
    assert capacity.tilt == pytest.approx(expected, abs=HALF)
    assert capacity.multiplier == pytest.approx(math.tan(math.radians(capacity.tilt)))
    (entry,) = capacity.directions
    assert entry.checked and entry.method == "lp"
    # the verdict agrees on either side of the closed form
    assert analyze(model, pyramid="cone", tilt=expected - 0.1, azimuth=0.0).feasible
    assert not analyze(model, pyramid="cone", tilt=expected + 0.1, azimuth=0.0).feasible


@pytest.mark.parametrize("friction", [0.4, 0.7])
def test_the_four_sided_pyramid_slides_at_its_own_friction_angle(friction):
    # its side faces the slope along x: friction mu / sqrt(2); towards 45 degrees a corner of
    # the square faces the slope, and the pyramid reaches the cone there: friction mu
    model = block(1.0, 0.2, friction=friction)
    capacity = lateral_capacity(model, StaticsOptions(pyramid="4"), azimuths=[0.0, 45.0])
    along_side, along_corner = capacity.directions
    assert along_side.tilt == pytest.approx(degrees_of(friction / math.sqrt(2)), abs=HALF)
    assert along_corner.tilt == pytest.approx(degrees_of(friction), abs=HALF)
    assert capacity.worst is along_side


@pytest.mark.parametrize("turn", [0.0, 30.0, 70.0])
def test_the_worst_direction_is_across_the_narrow_side(turn):
    # a 0.3 x 1 x 0.8 m block turned by `turn` about y: it tips first across its 0.3 m side,
    # towards azimuth -turn (mod 180) in the x-z plane, at atan(0.3 / 1.0)
    corners = np.array([[x, y, z] for x in (0, 0.3) for y in (0, 1.0) for z in (0, 0.8)])
    a = math.radians(turn)
    # azimuth phi is (cos phi, 0, sin phi); turning the block's x side to phi = turn
    spin = np.array([[math.cos(a), 0, -math.sin(a)], [0, 1, 0], [math.sin(a), 0, math.cos(a)]])
    model = Model([Block.from_hull(corners @ spin.T)], friction=5.0)
    capacity = lateral_capacity(model)
    assert capacity.swept and len(capacity.directions) >= 16
    assert capacity.tilt == pytest.approx(degrees_of(0.3), abs=HALF)
    across = {round(turn % 180, 6), round((turn + 180) % 360, 6)}
    assert min(abs(capacity.worst.azimuth - a) for a in across) < 0.5
    assert capacity.worst.checked


def test_a_carried_weight_tilts_with_the_table():
    # A vertical point load P on top of the block is a weight: the table turns it too, so the
    # block tips when (W + P) b / 2 = tan(theta) (W h / 2 + P h).
    base, height = 0.4, 1.0
    model = block(base, height, friction=5.0)
    weight = model.total_weight
    carried = 0.3 * weight
    model.loads.append(
        PointLoad("b", np.array([0.0, -carried, 0.0]), np.array([base / 2, height, 0.25]))
    )
    expected = degrees_of((weight + carried) * base / 2 / (weight * height / 2 + carried * height))
    capacity = lateral_capacity(model, azimuths=[0.0])
    assert capacity.tilt == pytest.approx(expected, abs=HALF)
    assert analyze(model, tilt=expected - 0.1, azimuth=0.0).feasible
    assert not analyze(model, tilt=expected + 0.1, azimuth=0.0).feasible


def test_loads_that_are_not_vertical_are_refused_in_one_line():
    model = block(0.4, 1.0)
    model.loads.append(PointLoad("b", np.array([30.0, -10.0, 0.0]), np.array([0.2, 1.0, 0.25])))
    with pytest.raises(StaticsError, match="not vertical") as caught:
        lateral_capacity(model, azimuths=[0.0])
    assert "\n" not in str(caught.value)
    # a tilt towards a given direction is still well defined: every load turns
    assert analyze(model, tilt=5.0, azimuth=0.0).feasible in (True, False)


@pytest.mark.parametrize("azimuth", [math.nan, math.inf, "east"])
def test_a_direction_that_is_no_number_is_refused_by_the_library_call(azimuth):
    # the library's lateral_capacity checks each azimuth as --capacity does (checked_azimuth)
    with pytest.raises(OptionError, match="azimuth must be a finite number of degrees"):
        lateral_capacity(block(0.4, 1.0), azimuths=[0.0, azimuth])


def test_an_azimuth_is_taken_modulo_a_turn():
    worst = lateral_capacity(block(0.4, 1.0), azimuths=[450.0]).directions
    assert [d.azimuth for d in worst] == [90.0]


def test_an_assembly_that_does_not_stand_upright_has_no_capacity():
    support = Block.box([-2.0, -0.5, -0.5], [0.0, 0.0, 1.0], fixed=True)
    over = Block.box([-0.3, 0.0, 0.0], [0.7, 0.4, 0.5])  # centroid beyond the support's edge
    capacity = lateral_capacity(Model([support, over], ground=None), azimuths=[0.0, 180.0])
    assert not capacity.stands_upright
    assert capacity.tilt is None and capacity.worst is None
    assert all(d.tilt is None for d in capacity.directions)
    report = capacity.to_report()
    assert report["tilt_deg"] is None and report["stands_upright"] is False


def test_a_block_wedged_between_supports_stands_at_any_tilt():
    left = Block.box([-1, 0, 0], [0, 1, 1], fixed=True)
    right = Block.box([1, 0, 0], [2, 1, 1], fixed=True)
    wedged = Block.box([0, 0.2, 0], [1, 0.8, 1])
    capacity = lateral_capacity(Model([left, wedged, right], ground=None), azimuths=[0, 90])
    assert capacity.tilt == 90.0
    assert all(d.status == "unbounded" and d.checked for d in capacity.directions)
    assert capacity.to_report()["load_multiplier"] is None  # infinite


@pytest.mark.parametrize("pyramid", ["4", "cone"])
def test_clarabel_and_the_cvxpy_reference_agree(pyramid):
    model = Model(semicircular_arch(1.0, 0.2, 24, depth=0.5), friction=0.6)
    problem = assemble(model, find_interfaces(model), pyramid=pyramid)
    for azimuth in (0.0, 90.0, 200.0):
        direct = load_multiplier(model, problem, azimuth)
        reference = load_multiplier(model, problem, azimuth, solver="cvxpy")
        assert direct.status == reference.status == "limit"
        assert direct.multiplier == pytest.approx(reference.multiplier, rel=1e-6)


def test_the_sweep_is_even_and_the_worst_is_refined():
    model = block(0.3, 1.0, depth=0.6, friction=5.0)
    problem = assemble(model, find_interfaces(model))
    worst, sweep = worst_direction(model, problem, directions=8)
    assert [d.azimuth for d in sweep] == [0, 45, 90, 135, 180, 225, 270, 315]
    assert worst.azimuth == 0.0  # 0 and 180 tie: the least azimuth
    assert worst.tilt == pytest.approx(degrees_of(0.3), abs=1e-6)


def test_the_capacity_ignores_the_tilt_of_the_options():
    model = block(0.3, 1.0, friction=5.0)
    plain = lateral_capacity(model, azimuths=[0.0])
    tilted = lateral_capacity(model, StaticsOptions(tilt=40.0, azimuth=90.0), azimuths=[0.0])
    assert tilted.tilt == pytest.approx(plain.tilt)
    # the kern shrinks every joint: the base is 0.3 K wide
    kern = lateral_capacity(model, StaticsOptions(kern=0.5), azimuths=[0.0])
    assert kern.tilt == pytest.approx(degrees_of(0.5 * 0.3), abs=HALF)
