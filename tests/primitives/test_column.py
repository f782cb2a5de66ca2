"""Columns: square and round sections in courses, fitted to the scope."""

import math

import numpy as np
import pytest
from stereotomy_checks import interface_counts

from shapegen.errors import GeometryError
from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives import insert
from shapegen.statics.contacts import find_interfaces


def test_square_column_fills_the_scope():
    blocks = insert("column", Scope.axis_aligned((1, 0, 1), (0.6, 4.0, 0.5)), courses=4)
    assert len(blocks) == 4
    assert sum(b.volume for b in blocks) == pytest.approx(0.6 * 4.0 * 0.5)
    assert all(b.volume == pytest.approx(0.3) for b in blocks)


@pytest.mark.parametrize("sides", [64, 96])
def test_round_column_volume_tends_to_the_cylinder(sides):
    width, height, depth = 0.8, 3.0, 1.0
    scope = Scope.axis_aligned((0, 0, 0), (width, height, depth))
    blocks = insert("column", scope, shape="round", sides=sides, courses=3)
    radius = min(width, depth) / 2
    volume = sum(b.volume for b in blocks)
    assert volume == pytest.approx(math.pi * radius**2 * height, rel=5e-3)
    # The inscribed polygon: sides / 2 * r^2 * sin(2 pi / sides) per unit height.
    assert volume == pytest.approx(sides / 2 * radius**2 * math.sin(2 * math.pi / sides) * height)
    for block in blocks:
        r = np.hypot(block.vertices[:, 0] - width / 2, block.vertices[:, 2] - depth / 2)
        np.testing.assert_allclose(r, radius)


@pytest.mark.parametrize(
    "height, course_height, courses",
    [(3.0, 0.5, 6), (3.0, 0.7, 4), (3.0, 5.0, 1), (1.0, 0.3, 3)],
)
def test_course_height_gives_a_whole_number_of_courses(height, course_height, courses):
    blocks = insert(
        "column", Scope.axis_aligned((0, 0, 0), (0.5, height, 0.5)), course_height=course_height
    )
    assert len(blocks) == courses
    for block in blocks:
        assert np.ptp(block.vertices[:, 1]) == pytest.approx(height / courses)


@pytest.mark.parametrize("shape", ["square", "round"])
def test_courses_share_beds(shape):
    blocks = insert(
        "column", Scope.axis_aligned((0, 0, 0), (0.5, 3.0, 0.5)), shape=shape, courses=5
    )
    assert interface_counts(blocks) == (4, 1)
    interfaces = find_interfaces(Model(blocks, ground=0.0))
    for interface in interfaces:
        assert abs(interface.normal[1]) == pytest.approx(1.0)


@pytest.mark.parametrize(
    "params, message",
    [
        ({"courses": 0}, "primitive 'column': parameter 'courses' must be at least 1, got 0"),
        (
            {"course_height": -0.5},
            "primitive 'column': parameter 'course_height' must be positive (or 0 to use "
            "'courses'), got -0.5 m",
        ),
        (
            {"shape": "round", "sides": 2},
            "primitive 'column': parameter 'sides' must be at least 3",
        ),
        ({"shape": "hexagonal"}, "parameter 'shape' must be one of 'square', 'round'"),
    ],
)
def test_impossible_parameters_are_named(params, message):
    with pytest.raises(GeometryError) as error:
        insert("column", Scope.axis_aligned((0, 0, 0), (0.5, 2.0, 0.5)), **params)
    assert message in str(error.value)
