"""Walls: courses fill the scope exactly; running bond; shared bed and head joints."""

import numpy as np
import pytest
from rotations import about_y

from shapegen.errors import GeometryError
from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives import insert
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.interface import GROUND


@pytest.mark.parametrize(
    "size, block_length, block_height, running_bond, per_course, courses",
    [
        ((3.0, 2.0, 0.4), 0.5, 0.25, True, 6, 8),
        ((3.0, 2.0, 0.4), 0.5, 0.25, False, 6, 8),
        ((2.9, 1.1, 0.3), 0.6, 0.3, True, 5, 4),  # nominal sizes rounded to whole counts
        ((0.4, 0.5, 0.3), 1.0, 1.0, True, 1, 1),
        ((0.4, 1.0, 0.3), 1.0, 0.5, True, 1, 2),
    ],
)
def test_courses_fill_the_scope(
    size, block_length, block_height, running_bond, per_course, courses
):
    scope = Scope.axis_aligned((1.0, 0.0, -2.0), size)
    blocks = insert(
        "wall",
        scope,
        block_length=block_length,
        block_height=block_height,
        running_bond=running_bond,
    )
    length, height, thickness = size
    offset_courses = courses // 2 if running_bond else 0
    assert len(blocks) == per_course * courses + offset_courses
    assert sum(b.volume for b in blocks) == pytest.approx(length * height * thickness, rel=1e-12)
    for block in blocks:
        local = scope.to_local(block.vertices)
        assert np.ptp(local[:, 2]) == pytest.approx(thickness)
        assert np.ptp(local[:, 1]) == pytest.approx(height / courses)
    # Every second course starts with a half block when bonded.
    second = [
        b for b in blocks if np.isclose(scope.to_local(b.vertices)[:, 1].min(), height / courses)
    ]
    shortest = min(np.ptp(scope.to_local(b.vertices)[:, 0]) for b in second) if second else None
    if second:
        expected = length / per_course / (2 if running_bond else 1)
        assert shortest == pytest.approx(expected)


@pytest.mark.parametrize("running_bond", [True, False])
def test_joints_are_shared(running_bond):
    per_course, courses = 5, 4
    blocks = insert(
        "wall",
        Scope.axis_aligned((0, 0, 0), (2.5, 1.0, 0.3)),
        block_length=0.5,
        block_height=0.25,
        running_bond=running_bond,
    )
    interfaces = find_interfaces(Model(blocks, ground=0.0))
    bonded = courses // 2 if running_bond else 0
    head = courses * (per_course - 1) + bonded
    # Between a course of n blocks and an offset course of n + 1, each block meets two.
    bed = (courses - 1) * (2 * per_course if running_bond else per_course)
    assert sum(i.second != GROUND for i in interfaces) == head + bed
    ground = [i for i in interfaces if i.second == GROUND]
    assert len(ground) == per_course
    assert sum(i.area for i in ground) == pytest.approx(2.5 * 0.3)


def test_rotated_wall_keeps_its_volume():
    rotation = about_y(30)
    scope = Scope(np.array([2.0, 0.0, 1.0]), rotation, np.array([3.0, 2.0, 0.4]))
    blocks = insert("wall", scope)
    assert sum(b.volume for b in blocks) == pytest.approx(2.4)
    assert len(find_interfaces(Model(blocks))) > len(blocks)


@pytest.mark.parametrize(
    "size, params, message",
    [
        ((3, 2, 1), {"block_length": 0.0}, "'wall': parameter 'block_length' must be positive"),
        ((3, 2, 1), {"block_height": -1.0}, "'block_height' must be positive, got -1 m"),
        ((3, 2, 0), {}, "primitive 'wall': parameter 'scope' needs a positive size"),
        ((3, 2, 1), {"running_bond": 1}, "parameter 'running_bond' must be true or false"),
    ],
)
def test_impossible_parameters_are_named(size, params, message):
    with pytest.raises(GeometryError) as error:
        insert("wall", Scope.axis_aligned((0, 0, 0), size), **params)
    assert message in str(error.value)
