"""Barrel and groin vaults: exact volumes against closed forms, convex voussoirs, shared faces."""

from __future__ import annotations

import math

import manifold3d
import numpy as np
import pytest
from stereotomy_checks import ROTATED, assert_convex, interface_counts, local_bounds

from shapegen.errors import GeometryError
from shapegen.model.scope import Scope
from shapegen.primitives import insert


def groin_volume(outer: float, inner: float) -> float:
    """Closed form of a groin vault of two semicircular barrels over a square of side 2 * outer.

    Below the extrados: the two half-cylinders of radius R over the square, 2 pi R^3 minus their
    common half Steinmetz solid 8/3 R^3; the void below the intrados: two half-cylinders of
    radius r and length 2R, 2 pi r^2 R, minus their common half Steinmetz solid 8/3 r^3.
    """
    below_extrados = 2 * math.pi * outer**3 - 8 / 3 * outer**3
    below_intrados = 2 * math.pi * inner**2 * outer - 8 / 3 * inner**3
    return below_extrados - below_intrados


@pytest.mark.parametrize(
    "scope, thickness",
    [
        (Scope.axis_aligned((0, 0, 0), (4.0, 2.0, 3.0)), 0.3),
        (Scope.axis_aligned((1, 2, 3), (10.0, 1.0, 0.5)), 2.0),
        (ROTATED, 0.5),
    ],
)
@pytest.mark.parametrize("courses, running_bond", [(1, False), (3, False), (3, True)])
def test_barrel_vault_volume_is_the_half_annulus_times_the_length(
    scope, thickness, courses, running_bond
):
    blocks = insert(
        "barrel_vault",
        scope,
        thickness=thickness,
        segments=64,
        courses=courses,
        running_bond=running_bond,
    )
    outer = scope.sx / 2
    exact = math.pi * (outer**2 - (outer - thickness) ** 2) / 2 * scope.sz
    assert len(blocks) == 64 * courses + (courses // 2 if running_bond else 0)
    assert sum(b.volume for b in blocks) == pytest.approx(exact, rel=5e-3)


def test_barrel_vault_fills_its_span_and_rises_half_of_it():
    blocks = insert("barrel_vault", ROTATED, thickness=0.4, segments=8, courses=2)
    lower, upper = local_bounds(blocks, ROTATED)
    np.testing.assert_allclose(lower, [0.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(upper, [ROTATED.sx, ROTATED.sx / 2, ROTATED.sz], atol=1e-12)
    assert_convex(blocks)


@pytest.mark.parametrize("segments, courses", [(2, 1), (7, 1), (12, 1), (6, 3), (5, 4)])
def test_barrel_vault_interfaces(segments, courses):
    blocks = insert("barrel_vault", ROTATED, thickness=0.3, segments=segments, courses=courses)
    internal, ground = interface_counts(blocks)
    # Radial joints inside each course, course joints between rings, two springings per course.
    assert internal == (segments - 1) * courses + segments * (courses - 1)
    assert ground == 2 * courses


@pytest.mark.parametrize("segments, courses", [(2, 2), (7, 3), (6, 4)])
def test_barrel_vault_in_running_bond_interfaces(segments, courses):
    blocks = insert(
        "barrel_vault", ROTATED, thickness=0.3, segments=segments, courses=courses,
        running_bond=True,
    )  # fmt: skip
    shifted = courses // 2  # the second, fourth... courses: segments + 1 voussoirs, half at ends
    assert len(blocks) == segments * courses + shifted
    assert_convex(blocks)
    internal, ground = interface_counts(blocks)
    # Each whole voussoir of a course overlaps two voussoirs of a shifted neighbour.
    within = (segments - 1) * (courses - shifted) + segments * shifted
    assert internal == within + 2 * segments * (courses - 1)
    assert ground == 2 * courses


def test_barrel_vault_joints_are_radial_and_facets_are_chords():
    scope = Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 1.0))
    segments, outer, inner = 9, 2.0, 1.5
    blocks = insert("barrel_vault", scope, thickness=outer - inner, segments=segments)
    half_angle = math.pi / (2 * segments)
    # Distance from the vault's axis to a side plane: 0 for a joint (it contains the axis), the
    # chord's distance for the intrados and extrados facets.
    allowed = np.array([0.0, inner * math.cos(half_angle), outer * math.cos(half_angle)])
    for block in blocks:
        sides = np.abs(block.face_normals[:, 2]) < 0.5
        distance = np.abs(block.face_normals[sides, :2] @ [outer, 0.0] - block.face_offsets[sides])
        assert np.abs(distance[:, None] - allowed[None, :]).min(axis=1).max() < 1e-12
        assert sides.sum() == 4


@pytest.mark.parametrize("depth", [4.0, 2.5, 7.0])
def test_groin_vault_volume_closed_form(depth):
    side, thickness = 4.0, 0.4
    scope = Scope.axis_aligned((0, 0, 0), (side, 3.0, depth))
    blocks = insert("groin_vault", scope, thickness=thickness, segments=64)
    exact = groin_volume(side / 2, side / 2 - thickness) * depth / side
    assert sum(b.volume for b in blocks) == pytest.approx(exact, rel=5e-3)


def _barrel_solid(radius: float, segments: int, side: float, along_x: bool) -> manifold3d.Manifold:
    """Polygonal half-cylinder (chords of ``segments``) of ``radius`` over the square plan."""
    angles = np.linspace(0.0, math.pi, segments + 1)
    section = np.column_stack([side / 2 + radius * np.cos(angles), radius * np.sin(angles)])
    prism = np.vstack([np.column_stack([section, np.full(len(section), z)]) for z in (0.0, side)])
    if along_x:
        prism = prism[:, [2, 1, 0]]
    return manifold3d.Manifold.hull_points(prism)


@pytest.mark.parametrize("segments", [4, 9, 16])
def test_groin_vault_is_the_boolean_of_two_barrels(segments):
    # The pieces must fill exactly (extrados A u extrados B) - (intrados A u intrados B).
    side, thickness = 4.0, 0.5
    outer, inner = side / 2, side / 2 - thickness
    scope = Scope.axis_aligned((0, 0, 0), (side, 3.0, side))
    blocks = insert("groin_vault", scope, thickness=thickness, segments=segments)
    extrados = _barrel_solid(outer, segments, side, False) + _barrel_solid(
        outer, segments, side, True
    )
    intrados = _barrel_solid(inner, segments, side, False) + _barrel_solid(
        inner, segments, side, True
    )
    assert sum(b.volume for b in blocks) == pytest.approx((extrados - intrados).volume(), rel=1e-9)
    assert_convex(blocks)


@pytest.mark.parametrize("segments", [2, 3, 6, 7])
def test_groin_vault_interfaces(segments):
    scope = Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 4.0))
    blocks = insert("groin_vault", scope, thickness=0.4, segments=segments)
    assert len(blocks) == 4 * segments
    internal, ground = interface_counts(blocks)
    # Along each of the four barrel ends: segments - 1 radial joints. On each of the four groins
    # (half diagonals) the voussoirs of one half of the semicircle meet their twins; a voussoir
    # across the crown (odd segments) meets its twin on both of its groins.
    per_groin = (segments + 1) // 2
    assert internal == 4 * (segments - 1) + 4 * per_groin
    assert ground == 8


def test_groin_vault_on_a_rectangle_keeps_its_rise():
    scope = Scope.axis_aligned((0, 0, 0), (3.0, 2.0, 5.0))
    blocks = insert("groin_vault", scope, thickness=0.3, segments=10)
    lower, upper = local_bounds(blocks, scope)
    np.testing.assert_allclose(lower, [0, 0, 0], atol=1e-9)
    np.testing.assert_allclose(upper, [3.0, 1.5, 5.0], atol=1e-9)


BAD_PARAMETERS = [
    ("barrel_vault", {"thickness": 2.0}, "'thickness'.*smaller than the extrados radius"),
    ("barrel_vault", {"thickness": 0.0}, "'thickness' must be positive"),
    ("barrel_vault", {"segments": 1}, "'segments' must be at least 2"),
    ("barrel_vault", {"courses": 0}, "'courses' must be at least 1"),
    ("barrel_vault", {"segments": 2.5}, "'segments' must be a whole number"),
    ("barrel_vault", {"thikness": 0.2}, "no parameter 'thikness'.*did you mean 'thickness'"),
    ("groin_vault", {"thickness": 2.5}, "'thickness'.*smaller than the extrados radius"),
    ("groin_vault", {"segments": 0}, "'segments' must be at least 2"),
]


@pytest.mark.parametrize("name, params, message", BAD_PARAMETERS)
def test_impossible_parameters_are_reported(name, params, message):
    with pytest.raises(GeometryError, match=f"primitive '{name}'.*{message}"):
        insert(name, Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 4.0)), **params)


@pytest.mark.parametrize("name", ["barrel_vault", "groin_vault"])
def test_flat_scope_is_reported(name):
    with pytest.raises(GeometryError, match=f"primitive '{name}'.*scope"):
        insert(name, Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 0.0)))


# Heyman's minimum thickness of a semicircular arch under self-weight: t / R = 0.1075 (R the
# centreline radius). A barrel vault is that arch extruded: well below it, it cannot stand;
# well above it, it does.
@pytest.mark.parametrize("ratio, stands", [(0.06, False), (0.16, True)])
@pytest.mark.parametrize("running_bond", [False, True])
def test_barrel_vault_stands_above_the_minimum_thickness(ratio, stands, running_bond):
    from shapegen.model.model import Model
    from shapegen.statics import analyze

    width = 4.0
    thickness = ratio * width / 2 / (1 + ratio / 2)  # t = ratio * (width / 2 - t / 2)
    scope = Scope.axis_aligned((0, 0, 0), (width, 2.0, 1.0))
    blocks = insert(
        "barrel_vault",
        scope,
        thickness=thickness,
        segments=24,
        courses=2,
        running_bond=running_bond,
    )
    assert analyze(Model(blocks)).feasible is stands


def test_thick_groin_vault_stands_on_its_four_springings():
    from shapegen.model.model import Model
    from shapegen.statics import analyze

    blocks = insert("groin_vault", Scope.axis_aligned((0, 0, 0), (4.0, 2.0, 4.0)), thickness=0.4)
    assert analyze(Model(blocks)).feasible
