"""The verdict's criterion on given motions: each block judged relative to its own smallest width,
and whether its motion has stopped (no simulator needed)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from shapegen.model.block import Block
from shapegen.primitives.arch import semicircular_arch
from shapegen.simulation import SimulationSettings, smallest_width
from shapegen.simulation.verdict import BlockShapes, Checkpoints, MotionTrack, judge
from shapegen.tolerances import (
    SIMULATION_DECAY_RATIO,
    SIMULATION_FALL_REL,
    SIMULATION_MOVING_REL,
)


def _still(n: int) -> tuple[np.ndarray, np.ndarray]:
    return np.repeat(np.eye(3)[None], n, axis=0), np.zeros((n, 3))


def _shifted(n: int, shift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    rotations, _ = _still(n)
    return rotations, np.asarray(shift, float).reshape(n, 3)


def _judge(blocks, before_tail, tail, final, settings=None):
    n = len(blocks)
    track = MotionTrack(np.array([0.0, 1.0]), np.zeros((2, n)), np.zeros((2, n)))
    checkpoints = Checkpoints(settled=_still(n), before_tail=before_tail, tail=tail, final=final)
    return judge(
        blocks, BlockShapes.of(blocks), checkpoints, track, settings or SimulationSettings()
    )


def test_smallest_width_of_a_box_is_its_shortest_side_in_any_orientation():
    box = Block.box([0, 0, 0], [1.0, 0.2, 0.5])
    assert smallest_width(box) == pytest.approx(0.2)
    turned = box.transformed(Rotation.from_euler("xyz", [0.3, 1.1, -0.4]).as_matrix(), [5, 2, 1])
    assert smallest_width(turned) == pytest.approx(0.2)


def test_smallest_width_of_a_voussoir_is_across_its_joints():
    # 40 voussoirs of R = 1 m, t = 0.12 m: the joint faces are 4.5 degrees apart, so the width
    # along a joint's normal is the extrados chord's projection, R_e sin(4.5 deg) = 1.06 * 0.0785.
    voussoir = semicircular_arch(1.0, 0.12, 40, depth=0.5)[5]
    assert smallest_width(voussoir) == pytest.approx(1.06 * np.sin(np.pi / 40), rel=1e-9)


@pytest.mark.parametrize(("fraction", "fell"), [(0.5, False), (0.99, False), (1.01, True)])
def test_a_block_fell_when_it_moved_the_fall_bar_of_its_own_width(fraction, fell):
    # Two blocks of different sizes moved by the same fraction of their own width: same verdict.
    small = Block.box([0, 0, 0], [0.1, 0.1, 0.1], id="small")
    large = Block.box([2, 0, 0], [4, 3, 2], id="large")
    shift = fraction * SIMULATION_FALL_REL * np.array([[0.1, 0, 0], [2.0, 0, 0]])
    moved = _shifted(2, shift)
    motions = _judge([small, large], moved, moved, moved)  # moved during settling, then still
    assert [m.fell for m in motions] == [fell, fell]
    assert [m.relative_displacement for m in motions] == pytest.approx(
        [fraction * SIMULATION_FALL_REL] * 2
    )
    assert not any(m.still_moving for m in motions)


@pytest.mark.parametrize(
    ("earlier", "last", "moving"),
    [
        (0.0, 2.0, True),  # began to move in the last quarter
        (2.0, 2.0, True),  # steady
        (2.0, 1.01 * SIMULATION_DECAY_RATIO * 2.0, True),  # slowing, but not by half
        (2.0, 0.99 * SIMULATION_DECAY_RATIO * 2.0, False),  # dying out
        (0.0, 0.99, False),  # below the floor
    ],
)
def test_a_block_is_still_moving_when_its_late_motion_does_not_die_out(earlier, last, moving):
    # Motions in units of the floor, SIMULATION_MOVING_REL of the block's 0.2 m width.
    unit = SIMULATION_MOVING_REL * 0.2
    block = Block.box([0, 0, 0], [1.0, 0.2, 0.5], id="s")
    before_tail = _still(1)
    tail = _shifted(1, [[earlier * unit, 0, 0]])
    final = _shifted(1, [[(earlier + last) * unit, 0, 0]])
    (motion,) = _judge([block], before_tail, tail, final)
    assert motion.still_moving == moving
    assert motion.moved == moving and not motion.fell
    assert motion.tail_motion == pytest.approx(last * unit)
    assert motion.earlier_motion == pytest.approx(earlier * unit)


def test_a_turn_moves_the_far_vertices_most():
    block = Block.box([0, 0, 0], [1.0, 0.2, 0.5], id="s")
    angle = 0.05  # rad, about the z axis through the origin (a corner)
    rotations = Rotation.from_euler("z", angle).as_matrix().reshape(1, 3, 3)
    (motion,) = _judge([block], _still(1), _still(1), (rotations, np.zeros((1, 3))))
    farthest = np.hypot(1.0, 0.2)  # the corner opposite the pivot, in the x-y plane
    assert motion.relative_displacement * 0.2 == pytest.approx(2 * farthest * np.sin(angle / 2))
    assert motion.rotation == pytest.approx(angle)


def test_a_fixed_tolerance_judges_by_that_distance_after_settling():
    block = Block.box([0, 0, 0], [1.0, 0.2, 0.5], id="s")
    moved = _shifted(1, [[2e-3, 0, 0]])  # 1 % of the width: far below the relative bar
    settings = SimulationSettings(tolerance=1e-3)
    (motion,) = _judge([block], _still(1), _still(1), moved, settings)
    assert motion.fell and motion.max_displacement == pytest.approx(2e-3)
    (relative,) = _judge([block], _still(1), _still(1), moved)
    assert not relative.fell


def test_fixed_blocks_never_move():
    support = Block.box([0, 0, 0], [1, 1, 1], id="support", fixed=True)
    far = _shifted(1, [[5.0, 0, 0]])
    (motion,) = _judge([support], _still(1), _still(1), far)
    assert not motion.moved and motion.relative_displacement == pytest.approx(5.0)
