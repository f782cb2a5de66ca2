"""Assembly of the equilibrium matrix, loads, friction pyramids and kern scaling."""

from __future__ import annotations

import math

import numpy as np
import pytest
from statics_cases import horizontal_interface, polygon_interface

from shapegen.errors import OptionError
from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.statics.assembly import assemble, friction_cone, polygon_centroids
from shapegen.statics.interface import GROUND


def pyramid_vertices(cone):
    """Corners of the friction polygon for c = 1 (intersections of neighbouring sides)."""
    sides = cone[:-1]
    corners = []
    for k in range(len(sides)):
        a = sides[[k, (k + 1) % len(sides)], 1:]
        b = -sides[[k, (k + 1) % len(sides)], 0]
        corners.append(np.linalg.solve(a, b))
    return np.array(corners)


@pytest.mark.parametrize(
    "pyramid, sides, corner_on_axis",
    [("4", 4, False), ("4r", 4, True), ("8", 8, False)],
)
def test_pyramid_is_inscribed_in_the_coulomb_circle(pyramid, sides, corner_on_axis):
    mu = 0.7
    cone = friction_cone(pyramid, mu)
    assert cone.shape == (sides + 1, 3)
    np.testing.assert_allclose(cone[-1], (-1, 0, 0))  # c >= 0
    corners = pyramid_vertices(cone)
    np.testing.assert_allclose(np.linalg.norm(corners, axis=1), mu, rtol=1e-12)
    on_axis = np.any(np.isclose(np.abs(corners), mu).any(axis=1))
    assert on_axis == corner_on_axis


@pytest.mark.parametrize(
    "pyramid, direction_deg, limit",
    [
        ("4", 0.0, 0.7 / math.sqrt(2)),  # |u| <= mu / sqrt 2
        ("4", 45.0, 0.7),  # the square's corner
        ("4r", 0.0, 0.7),  # |u| + |t| <= mu
        ("4r", 45.0, 0.7 / math.sqrt(2)),
        ("8", 0.0, 0.7 * math.cos(math.pi / 8)),
    ],
)
def test_pyramid_capacity_along_a_direction(pyramid, direction_deg, limit):
    cone = friction_cone(pyramid, 0.7)
    d = np.array([math.cos(math.radians(direction_deg)), math.sin(math.radians(direction_deg))])
    # largest friction along d with c = 1: min over sides of capacity / projection
    projection = cone[:-1, 1:] @ d
    capacity = -cone[:-1, 0]
    assert np.min(capacity[projection > 1e-12] / projection[projection > 1e-12]) == pytest.approx(
        limit
    )


def test_equality_rows_are_force_and_torque_about_the_centroids():
    rng = np.random.default_rng(3)
    lower = Block.box((0, 0, 0), (2, 1, 1))
    upper = Block.box((0.5, 1, 0), (1.5, 3, 1))
    model = Model([lower, upper])
    interfaces = [
        horizontal_interface(0, GROUND, 0.0, (0, 2), (0, 1), up=False),
        horizontal_interface(0, 1, 1.0, (0.5, 1.5), (0, 1), up=True),
    ]
    problem = assemble(model, interfaces)
    m = problem.n_vertices
    x = rng.normal(size=4 * m)
    got = problem.equality @ x
    expected = np.zeros(12)
    c, s, u, t = x.reshape(4, m)
    for v in range(m):
        interface = problem.interfaces[problem.vertex_interface[v]]
        force = (
            (c[v] - s[v]) * interface.normal + u[v] * interface.tangent1 + t[v] * interface.tangent2
        )
        p = problem.vertex_points[v]
        for block, sign in ((interface.first, -1.0), (interface.second, 1.0)):
            if block == GROUND:
                continue
            row = 6 * problem.free_index[block]
            centroid = model.blocks[block].centroid
            expected[row : row + 3] += sign * force
            expected[row + 3 : row + 6] += sign * np.cross(p - centroid, force) / problem.length
    np.testing.assert_allclose(got, expected, atol=1e-12)


def test_load_vector_holds_weights_and_point_loads():
    block = Block.box((0, 0, 0), (1, 2, 1), id="tall")
    push = np.array([100.0, 0.0, -50.0])
    point = np.array([0.5, 2.0, 0.25])
    model = Model([block], loads=[PointLoad("tall", push, point)])
    interfaces = [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)]
    problem = assemble(model, interfaces)
    weight = block.mass * 9.81
    assert problem.weight == pytest.approx(weight)
    force = problem.load[:3] * problem.weight
    torque = problem.load[3:] * problem.weight * problem.length
    np.testing.assert_allclose(force, push + (0, -weight, 0))
    np.testing.assert_allclose(torque, np.cross(point - block.centroid, push))


def test_supports_and_non_structural_blocks_have_no_rows():
    model = Model(
        [
            Block.box((0, 0, 0), (1, 1, 1), fixed=True),
            Block.box((0, 1, 0), (1, 2, 1)),
            Block.box((0, 2, 0), (1, 3, 1), structural=False),
        ]
    )
    interfaces = [
        horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False),  # support on support
        horizontal_interface(0, 1, 1.0, (0, 1), (0, 1), up=True),
        horizontal_interface(1, 2, 2.0, (0, 1), (0, 1), up=True),  # touches a roof: dropped
    ]
    problem = assemble(model, interfaces)
    assert problem.equality.shape == (6, 16)
    assert len(problem.interfaces) == 1
    np.testing.assert_array_equal(problem.free_index, (-1, 0, -1))


def test_kern_scales_each_polygon_about_its_centroid():
    triangle = polygon_interface(0, GROUND, (0, -1, 0), [(0, 0, 0), (3, 0, 0), (0, 0, 3)])
    square = horizontal_interface(0, GROUND, 0.0, (1, 2), (1, 2), up=False)
    model = Model([Block.box((0, 0, 0), (3, 1, 3))])
    problem = assemble(model, [triangle, square], kern=1 / 3)
    np.testing.assert_allclose(problem.interfaces[0].centroid, (1, 0, 1), atol=1e-12)
    for original, scaled in zip([triangle, square], problem.interfaces, strict=True):
        np.testing.assert_allclose(scaled.area, original.area / 9)
        np.testing.assert_allclose(scaled.vertices, original.scaled(1 / 3).vertices, atol=1e-12)


def test_polygon_centroids_match_the_interface_centroid():
    rng = np.random.default_rng(5)
    polygons = []
    for _ in range(5):
        angles = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 8)))
        corners = np.stack([np.cos(angles), np.zeros_like(angles), np.sin(angles)], axis=1)
        polygons.append(polygon_interface(0, GROUND, (0, 1, 0), corners * rng.uniform(1, 3)))
    points = np.concatenate([p.vertices for p in polygons])
    starts = np.cumsum([0] + [len(p.vertices) for p in polygons])
    normals = np.array([p.normal for p in polygons])
    got = polygon_centroids(points, normals, starts)
    np.testing.assert_allclose(got, [p.centroid for p in polygons], atol=1e-12)


def test_inequality_matrix_matches_the_cone():
    model = Model([Block.box((0, 0, 0), (1, 1, 1))])
    problem = assemble(
        model, [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)], pyramid="8"
    )
    g = problem.inequality_matrix().toarray()
    m = problem.n_vertices
    x = np.random.default_rng(1).normal(size=4 * m)
    c, s, u, t = x.reshape(4, m)
    expected = np.concatenate(
        [np.concatenate([problem.cone @ (c[v], u[v], t[v]), [-s[v]]]) for v in range(m)]
    )
    np.testing.assert_allclose(g @ x, expected)


@pytest.mark.parametrize(
    "options, message",
    [
        ({"pyramid": "6"}, "pyramid must be one of cone, 4, 4r, 8"),
        ({"kern": 0.0}, "kern must be a number in (0, 1]"),
        ({"kern": 1.5}, "kern must be a number in (0, 1]"),
        ({"friction": -0.1}, "friction must be a finite number >= 0"),
        ({"objective": "tension"}, "objective must be one of tension_squared, tension_sum"),
    ],
)
def test_bad_options_raise(options, message):
    model = Model([Block.box((0, 0, 0), (1, 1, 1))])
    with pytest.raises(OptionError, match=message.replace("(", r"\(").replace("]", r"\]")):
        assemble(model, [], **options)


def test_products_with_the_equality_matrix_match_the_sparse_matrix():
    from statics_cases import running_bond_wall

    from shapegen.statics.contacts import find_interfaces

    model = running_bond_wall(courses=3, per_course=4)
    model.blocks[0].fixed = True  # a support side among the vertices
    problem = assemble(model, find_interfaces(model))
    rng = np.random.default_rng(4)
    x = rng.normal(size=problem.n_variables)
    lam = rng.normal(size=6 * problem.n_free)
    np.testing.assert_allclose(problem.product(x), problem.equality @ x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        problem.transposed_product(lam), problem.equality.T @ lam, rtol=0, atol=1e-12
    )
    np.testing.assert_allclose(problem.residual(x), problem.equality @ x + problem.load)
