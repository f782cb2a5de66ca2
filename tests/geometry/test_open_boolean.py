"""Booleans of open surfaces (op_boolOp, "Open and closed operands"), checked where the
reference's reading gives the result in closed form: a plane through a 12 x 4 x 8 m box keeps
"below the plane" as its inside, so subtracting it leaves the box's upper half as a closed
solid (the lower half when the plane faces down); a box with one face removed counts as closed
while that opening stays outside the other operand, and an opening that crosses it is said."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.geometry.mesh import Mesh
from shapegen.geometry.open_boolean import open_boolean

BOX = Mesh.box((12.0, 4.0, 8.0))  # x 0..12, y 0..4, z 0..8
# a 20 x 20 m plane at y = 2 across the box, facing up (its corners anticlockwise seen from +y)
UP = Mesh(np.array([[-4, 2, -6], [-4, 2, 14], [16, 2, 14], [16, 2, -6]], float), [(0, 1, 2, 3)])
DOWN = Mesh(UP.vertices, [(3, 2, 1, 0)])


def _solid(kind: str, a: Mesh, b: Mesh) -> tuple[Mesh, bool]:
    points, triangles, crossed = open_boolean(kind, a, b)
    return Mesh(points, [tuple(t) for t in triangles]), crossed


def _volume(mesh: Mesh) -> float:
    """The volume the triangles enclose (divergence theorem; a surface left open, or wound
    the wrong way, gives another figure)."""
    a, b, c = (mesh.vertices[[f[k] for f in mesh.faces]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0


@pytest.mark.parametrize(
    ("kind", "plane", "low", "high"),
    [
        ("subtract", UP, 2.0, 4.0),  # the inside, below the plane, is taken away
        ("intersect", UP, 0.0, 2.0),
        ("subtract", DOWN, 0.0, 2.0),  # facing down, its inside is above it
        ("intersect", DOWN, 2.0, 4.0),
    ],
)
def test_a_plane_through_a_box_keeps_one_half_closed(kind, plane, low, high):
    mesh, crossed = _solid(kind, BOX, plane)
    assert not crossed
    assert _volume(mesh) == pytest.approx(12 * 2 * 8)
    assert mesh.vertices[:, 1].min() == pytest.approx(low)
    assert mesh.vertices[:, 1].max() == pytest.approx(high)


def test_a_union_with_a_plane_drops_what_lies_below_it():
    # the box's upper half (top 96 m2, sides 80 m2) and the plane outside it (400 - 96 m2)
    mesh, crossed = _solid("union", BOX, UP)
    assert not crossed and mesh.vertices[:, 1].min() == pytest.approx(2.0)
    assert mesh.area() == pytest.approx(96 + 2 * (12 * 2 + 8 * 2) + 400 - 96)


def _open_box(removed_normal) -> Mesh:
    moved = Mesh(BOX.vertices + (6.0, 2.0, 4.0), BOX.faces)  # overlaps BOX on 6 x 2 x 4
    faces = [
        f
        for k, f in enumerate(moved.faces)
        if not np.allclose(moved.face_normal(k), removed_normal)
    ]
    return Mesh(moved.vertices, faces)


@pytest.mark.parametrize(("kind", "volume"), [("subtract", 384 - 48), ("intersect", 48)])
def test_an_open_box_whose_opening_lies_outside_counts_as_closed(kind, volume):
    mesh, crossed = _solid(kind, BOX, _open_box((0, 0, 1)))  # its far face (z = 12) removed
    assert not crossed
    assert _volume(mesh) == pytest.approx(volume)


def test_an_opening_that_crosses_the_other_operand_is_said():
    _, crossed = _solid("subtract", BOX, _open_box((0, 0, -1)))  # its near face, z = 4, inside
    assert crossed


def test_only_the_three_operations():
    with pytest.raises(ValueError, match="unknown Boolean operation"):
        open_boolean("xor", BOX, UP)


def test_a_boundary_lying_on_the_other_surface_only_touches_it():
    # the plane exactly as wide as the box (x 0..12): its edges at x = 0 and 12 lie on the
    # box's sides, through the corners of its front and back faces, without crossing them
    plane = Mesh(
        np.array([[0, 2, -6], [0, 2, 14], [12, 2, 14], [12, 2, -6]], float), [(0, 1, 2, 3)]
    )
    mesh, crossed = _solid("subtract", BOX, plane)
    assert not crossed
    assert _volume(mesh) == pytest.approx(12 * 2 * 8)


@pytest.mark.parametrize(("kind", "volume"), [("subtract", 8.0), ("intersect", 0.0)])
def test_what_lies_in_front_of_an_opening_is_outside(kind, volume):
    # a 2 m cube 1 m in front of the open box's opening (z = 12), within its outline: the box
    # counts as closed, its opening capped, so the cube is outside it (the nearest faces, the
    # open box's sides, would have put it behind them)
    cube = Mesh(Mesh.box((2.0, 2.0, 2.0)).vertices + (9.0, 3.0, 13.0), Mesh.box((2, 2, 2)).faces)
    mesh, crossed = _solid(kind, cube, _open_box((0, 0, 1)))
    assert not crossed
    assert _volume(mesh) == pytest.approx(volume)
