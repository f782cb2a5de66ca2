"""Trim planes (op_comp "Trim Planes", attr_trim, op_trim): comp(f) with ':' puts a plane bisecting
the angle at each edge a face shares with another; inserted primitives and assets are cut to the
enabled ones, vertical by default, horizontal after set(trim.horizontal, true). Volumes are
closed-form: a box on the 12 m side of a 12 x 8 x 10 m mass, widened to 1.4 x 12 m and 2 m
deep, cut by the 45-degree planes at the corners keeps the trapezoid of widths 12 and 16 m."""

from __future__ import annotations

import math

import numpy as np
import pytest

import shapegen
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.trim import face_trim_planes, trimmed

UP = np.array([0.0, 1.0, 0.0])


def _build(tmp_path, text, suffix=".cga"):
    path = tmp_path / f"trim{suffix}"
    path.write_text(text)
    return shapegen.load_grammar(path).build(lot=(12, 8))


def _volume(model):
    """The volume the statics judge: the blocks, and the solids of the leaves drawn open (an
    insert cut at trim planes)."""
    solids = [s.solid.local for s in model.surfaces if s.solid is not None]
    return sum(b.volume for b in model.blocks) + sum(m.volume() for m in solids)


def _drawn(model) -> list[np.ndarray]:
    """Every drawn face of the model's leaves, as its corners (world, m)."""
    return [
        np.asarray(leaf.vertices)[list(face)]
        for leaf in [*model.blocks, *model.surfaces]
        for face in leaf.faces
    ]


# ------------------------------------------------------------------------- geometry
def test_a_box_face_has_four_planes_at_45_degrees_two_of_them_horizontal():
    box = Mesh.box((12.0, 10.0, 8.0))
    planes = face_trim_planes(box.vertices, box.faces, UP)
    assert all(len(p) == 4 for p in planes)  # every edge of a box is shared
    for k, face_planes in enumerate(planes):
        normal = box.face_normal(k)
        for plane in face_planes:
            # the bisector of a right angle: 45 degrees from the face's own normal
            assert float(np.dot(plane.normal, normal)) == pytest.approx(math.sqrt(0.5))
            # the face's own corners stay on the kept side
            corners = box.vertices[list(box.faces[k])]
            assert (corners @ np.asarray(plane.normal) >= plane.offset - 1e-9).all()
        is_wall = abs(normal[1]) < 0.5
        horizontal = sorted(p.horizontal for p in face_planes)
        # a wall's top and bottom edges are horizontal; the roof's and floor's edges all are
        assert horizontal == ([False, False, True, True] if is_wall else [True] * 4)


def test_coplanar_neighbours_make_no_plane():
    # two unit squares side by side in y = 0, sharing the edge x = 1: no angle to bisect. In
    # PyPRT's candler on an L-shaped lot the roof's inside face (coplanar with the offset's
    # border) cuts nothing: the boxes at the inner L's far corners stay whole
    vertices = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 0, 1], [1, 0, 1], [0, 0, 1.0]])
    faces = [(0, 5, 4, 1), (1, 4, 3, 2)]  # counter-clockwise seen from +y
    assert face_trim_planes(vertices, faces, UP) == [(), ()]
    # a third face folded up at x = 2 still makes its plane with the second square
    vertices = np.vstack([vertices, [[2, 1, 1], [2, 1, 0]]])
    faces.append((2, 3, 6, 7))
    left, right, wall = face_trim_planes(vertices, faces, UP)
    assert left == () and len(right) == 1 and len(wall) == 1


def test_trimmed_keeps_an_uncut_mesh_and_drops_one_wholly_outside():
    cube = Mesh.box((1.0, 1.0, 1.0))
    box = Mesh.box((12.0, 10.0, 8.0))
    planes = face_trim_planes(box.vertices, box.faces, UP)[2]
    inside = trimmed(cube, np.array([5.0, 5.0, 8.0]), np.eye(3), planes)
    assert inside is cube
    outside = trimmed(cube, np.array([-5.0, 5.0, 8.0]), np.eye(3), planes)
    assert outside is None


# ------------------------------------------------------------------------- rule files
_MASS = "@StartRule\nLot --> extrude(10) comp(f) { 2 : Facade }\n"


def test_an_inserted_cube_is_cut_by_the_vertical_planes(tmp_path):
    model = _build(tmp_path, _MASS + "Facade --> s('1.4, '1, 2) center(x) primitiveCube()\n")
    # trapezoid of widths 12 (at the wall) and 16 (2 m out), 10 m high
    assert _volume(model) == pytest.approx((12 + 16) / 2 * 2 * 10)
    corners = np.concatenate(_drawn(model))
    assert np.ptp(corners[:, 0]) == pytest.approx(16.0)


def test_the_cut_is_drawn_open_and_judged_closed(tmp_path):
    # CityEngine's runtime leaves an insert's cut open: PyPRT's candler has no face on any
    # trim plane. The statics judge the solid the caps close (the trapezoid prism above).
    model = _build(tmp_path, _MASS + "Facade --> s('1.4, '1, 2) center(x) primitiveCube()\n")
    faces = _drawn(model)
    assert len(faces) == 4  # the cube's front, back, top and bottom; its ends cut away
    for corners in faces:  # none lies on a 45-degree plane at the mass's corners
        normal = np.cross(corners[1] - corners[0], corners[2] - corners[0])
        normal /= np.linalg.norm(normal)
        assert abs(normal[1]) > 0.5 or abs(abs(normal[0]) - abs(normal[2])) > 0.5
    assert _volume(model) == pytest.approx((12 + 16) / 2 * 2 * 10)


def test_the_scope_is_fitted_to_the_cut(tmp_path):
    # the cube, 16.8 m wide, keeps 16 m at its outer side after the corners' 45-degree cuts:
    # the scope is the cut's bounding box, as a split after the insert measures it (PyPRT's
    # parthenon lays its simas over the cut cube's length)
    rules = _MASS + (
        "Facade --> s('1.4, '1, 2) center(x) primitiveCube() report(\"sx\", scope.sx) "
        'split(x) { ~5 : Piece }*\nPiece --> report("piece", scope.sx)\n'
    )
    reports = _build(tmp_path, rules).metadata["reports"]
    assert reports["sx"] == pytest.approx(16.0)
    assert reports["piece"] == pytest.approx([16 / 3] * 3)


def test_horizontal_planes_cut_only_when_enabled(tmp_path):
    insert = "Facade --> s('1.4, '1.2, 2) center(x) primitiveCube()\n"
    vertical_only = _build(tmp_path, _MASS + insert)
    assert _volume(vertical_only) == pytest.approx(28 * 12)
    both = _build(tmp_path, _MASS.replace("extrude", "set(trim.horizontal, true) extrude") + insert)
    # width 12 + 2d and height min(12, 10 + d) at depth d: integral over d from 0 to 2
    assert _volume(both) == pytest.approx(240 + 64 + 16 / 3)


def test_trim_vertical_false_and_the_merge_operator_leave_the_insert_whole(tmp_path):
    insert = "Facade --> s('1.4, '1, 2) center(x) primitiveCube()\n"
    whole = 1.4 * 12 * 10 * 2
    off = _build(tmp_path, _MASS.replace("extrude", "set(trim.vertical, false) extrude") + insert)
    assert _volume(off) == pytest.approx(whole)
    merged = _build(tmp_path, _MASS.replace("2 : Facade", "2 = Facade") + insert)
    assert _volume(merged) == pytest.approx(whole)


def test_trim_planes_pass_through_splits_and_apply_to_the_trim_operation(tmp_path):
    rules = _MASS + (
        "Facade --> split(y) { ~4 : Floor }*\nFloor --> s('1.4, '1, 2) center(x) primitiveCube()\n"
    )
    split = _build(tmp_path, rules)
    judged = len(split.blocks) + sum(1 for s in split.surfaces if s.solid is not None)
    assert judged > 1  # floors, each a trapezoid prism
    assert _volume(split) == pytest.approx(28 * 10)
    by_hand = _build(tmp_path, _MASS + "Facade --> extrude(2) s('1.4, '1, '1) center(x) trim()\n")
    assert _volume(by_hand) == pytest.approx(28 * 10)
    untouched = _build(tmp_path, _MASS + "Facade --> extrude(2) s('1.4, '1, '1) center(x)\n")
    assert _volume(untouched) == pytest.approx(1.4 * 12 * 10 * 2)


def test_rule_files_in_the_grammar_dialect_make_no_trim_planes(tmp_path):
    insert = "Facade --> s('1.4, '1, 2) center(x) primitiveCube()\n"
    model = _build(tmp_path, _MASS + insert, suffix=".grammar")
    assert _volume(model) == pytest.approx(1.4 * 12 * 10 * 2)
