"""Domes: exact volume against the closed form, convex voussoirs, joints through the centre."""

from __future__ import annotations

import math

import numpy as np
import pytest
from stereotomy_checks import ROTATED, assert_convex, interface_counts, local_bounds

from shapegen.errors import GeometryError
from shapegen.model.scope import Scope
from shapegen.primitives import insert

SQUARE = Scope.axis_aligned((1.0, 0.5, -1.0), (4.0, 3.0, 4.0))


def shell_volume(outer: float, inner: float, oculus_degrees: float) -> float:
    """Hemispherical shell minus the cone of half-angle ``oculus`` about the vertical axis."""
    return 2 / 3 * math.pi * (outer**3 - inner**3) * math.cos(math.radians(oculus_degrees))


@pytest.mark.parametrize(
    "scope, oculus", [(SQUARE, 0.0), (ROTATED, 0.0), (ROTATED, 20.0), (SQUARE, 50.0)]
)
def test_dome_volume_closed_form(scope, oculus):
    thickness = 0.3
    blocks = insert("dome", scope, thickness=thickness, rings=28, meridians=56, oculus=oculus)
    outer = min(scope.sx, scope.sz) / 2
    exact = shell_volume(outer, outer - thickness, oculus)
    assert sum(b.volume for b in blocks) == pytest.approx(exact, rel=5e-3)


@pytest.mark.parametrize("oculus", [0.0, 30.0])
def test_dome_is_centred_on_the_plan_and_springs_from_the_bottom(oculus):
    blocks = insert("dome", ROTATED, thickness=0.4, rings=5, meridians=12, oculus=oculus)
    assert_convex(blocks)
    lower, upper = local_bounds(blocks, ROTATED)
    outer = min(ROTATED.sx, ROTATED.sz) / 2
    centre = np.array([ROTATED.sx / 2, 0.0, ROTATED.sz / 2])
    top = outer * math.cos(math.radians(oculus))
    # 12 meridians include the four axis directions, where the extrados reaches the full radius.
    np.testing.assert_allclose(lower, centre - [outer, 0.0, outer], atol=1e-12)
    np.testing.assert_allclose(upper, centre + [outer, top, outer], atol=1e-12)


def test_every_joint_plane_passes_through_the_centre():
    scope = SQUARE
    blocks = insert("dome", scope, thickness=0.5, rings=4, meridians=7)
    centre = scope.to_world(np.array([[2.0, 0.0, 2.0]]))[0]
    for block in blocks:
        distance = np.abs(block.face_normals @ centre - block.face_offsets)
        through_centre = int((distance < 1e-12).sum())
        # Two meridian joints and two ring joints; a keystone wedge has no upper ring joint.
        assert through_centre == (3 if "keystone" in block.tags else 4)
        assert len(block.faces) == (5 if "keystone" in block.tags else 6)


@pytest.mark.parametrize("rings, meridians", [(1, 3), (3, 8), (5, 11)])
@pytest.mark.parametrize("oculus", [0.0, 25.0])
def test_dome_interfaces(rings, meridians, oculus):
    blocks = insert("dome", SQUARE, thickness=0.3, rings=rings, meridians=meridians, oculus=oculus)
    assert len(blocks) == rings * meridians
    internal, ground = interface_counts(blocks, ground=SQUARE.origin[1])
    # Every ring is closed (meridians joints), rings - 1 ring joints of meridians blocks each.
    assert internal == rings * meridians + (rings - 1) * meridians
    assert ground == meridians


BAD_PARAMETERS = [
    ({"thickness": 2.0}, "'thickness'.*smaller than the extrados radius"),
    ({"thickness": -0.1}, "'thickness' must be positive"),
    ({"rings": 0}, "'rings' must be at least 1"),
    ({"meridians": 2}, "'meridians' must be at least 3"),
    ({"oculus": 90.0}, "'oculus' must be in \\[0, 90\\)"),
    ({"oculus": -5.0}, "'oculus' must be in \\[0, 90\\)"),
    ({"oculus": "wide"}, "'oculus' must be a number"),
]


@pytest.mark.parametrize("params, message", BAD_PARAMETERS)
def test_impossible_parameters_are_reported(params, message):
    with pytest.raises(GeometryError, match=f"primitive 'dome'.*{message}"):
        insert("dome", SQUARE, **params)


# Heyman's minimum thickness of a hemispherical dome under self-weight (compression-only hoops):
# t / R = 0.042 (R the mid-surface radius). Bracket it by a factor of two on each side.
@pytest.mark.parametrize("ratio, stands", [(0.021, False), (0.084, True)])
def test_dome_stands_above_the_minimum_thickness(ratio, stands):
    from shapegen.model.model import Model
    from shapegen.statics import analyze

    outer = 2.0
    thickness = ratio * outer / (1 + ratio / 2)  # t = ratio * (outer - t / 2)
    blocks = insert("dome", SQUARE, thickness=thickness, rings=10, meridians=16)
    assert analyze(Model(blocks, ground=SQUARE.origin[1])).feasible is stands
