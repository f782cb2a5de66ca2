"""Trim planes of a component split: the whole-array form against the face-by-face rule."""

import math

import numpy as np
import pytest

from shapegen.geometry.extrude import prism
from shapegen.geometry.mesh import Mesh, unit_face_normals
from shapegen.geometry.scope_frames import lot_polygon
from shapegen.geometry.trim import (
    TrimPlane,
    _face_trim_planes_by_face,
    face_trim_planes,
    trimmed,
    trimmed_solid,
)
from shapegen.model.lot import Lot

L_LOT = [(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)]


def _l_prism():
    _, face = lot_polygon(Lot.polygon(L_LOT))
    return prism(face.vertices, (0, 3.0, 0))


@pytest.mark.parametrize("mesh", [Mesh.box((2.0, 3.0, 4.0)), _l_prism()], ids=["box", "L prism"])
@pytest.mark.parametrize("per_face_up", [False, True])
def test_planes_are_those_of_the_face_by_face_rule(mesh, per_face_up):
    turn = np.array([[0.8, 0.0, 0.6], [0.0, 1.0, 0.0], [-0.6, 0.0, 0.8]])
    vertices = mesh.vertices @ turn.T + [10.0, 2.0, -5.0]
    faces = mesh.faces
    up = np.tile([0.0, 1.0, 0.0], (len(faces), 1)) if per_face_up else np.array([0.0, 1.0, 0.0])
    ups = np.broadcast_to(up, (len(faces), 3))
    expected = _face_trim_planes_by_face(vertices, faces, unit_face_normals(vertices, faces), ups)
    got = face_trim_planes(vertices, faces, up)
    assert [len(p) for p in got] == [len(p) for p in expected]
    for planes, reference in zip(got, expected, strict=True):
        for plane, other in zip(planes, reference, strict=True):
            assert plane.normal == pytest.approx(other.normal, abs=1e-12)
            assert plane.offset == pytest.approx(other.offset, abs=1e-9)
            assert plane.horizontal == other.horizontal


def test_a_box_face_has_a_plane_at_each_edge_halfway_between_its_faces():
    planes = face_trim_planes(
        Mesh.box((2.0, 2.0, 2.0)).vertices, Mesh.box((2, 2, 2)).faces, [0, 1, 0]
    )
    assert all(len(p) == 4 for p in planes)
    top = planes[1]  # faces +y; its edges are horizontal, its planes lean 45 degrees
    assert all(p.horizontal for p in top)
    assert all(abs(abs(p.normal[1]) - np.sqrt(0.5)) < 1e-12 for p in top)


def test_an_edge_of_three_faces_takes_the_face_by_face_rule():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], float)
    faces = [(0, 1, 2), (1, 0, 3), (0, 1, 4)]
    planes = face_trim_planes(vertices, faces, np.array([0.0, 1.0, 0.0]))
    assert [len(p) for p in planes] == [1, 1, 1]


def test_a_cut_is_kept_only_for_the_same_mesh_and_planes():
    box = Mesh.box((2.0, 2.0, 2.0))
    plane = TrimPlane((1.0, 0.0, 0.0), 1.0, False)  # keep x >= 1 (world)
    first = trimmed(box, np.zeros(3), np.eye(3), [plane])
    again = trimmed(box, np.zeros(3), np.eye(3), [plane])
    # drawn open at the cut (5 faces), as CityEngine draws it; the solid it bounds is kept
    assert again is first and first.n_faces == 5 and not first.is_closed
    assert trimmed_solid(first).volume() == pytest.approx(4.0)
    moved = trimmed(box, np.array([0.5, 0.0, 0.0]), np.eye(3), [plane])  # x >= 0.5 locally
    assert trimmed_solid(moved).volume() == pytest.approx(6.0)
    other = Mesh(box.vertices, tuple(tuple(f) for f in box.faces))  # same numbers, new faces
    cut = trimmed(other, np.zeros(3), np.eye(3), [plane])
    assert trimmed_solid(cut).volume() == pytest.approx(4.0)
    assert trimmed(box, np.zeros(3), np.eye(3), []) is box


def test_a_corner_within_a_millimetre_of_the_plane_is_on_it():
    # PyPRT's parthenon: an abacus whose opposite corners lie 0.71 mm inside its corner's
    # 45-degree plane is cut from corner to corner, with no sliver beside the cut
    box = Mesh.box((2.112, 0.462, 2.112))
    plane = TrimPlane((math.sqrt(0.5), 0.0, -math.sqrt(0.5)), 0.0, False)  # keeps x >= z
    # placed 1 mm down z: the corners (0, -0.001) and (2.112, 2.111) are 0.71 mm inside
    cut = trimmed(box, np.array([0.0, 0.0, -0.001]), np.eye(3), [plane])
    solid = trimmed_solid(cut)
    assert len(cut.vertices) == 6  # a triangular prism's corners, none added
    assert solid.volume() == pytest.approx(2.112**2 / 2 * 0.462)


def test_a_trim_keeps_a_faces_corners_along_the_cut():
    # PyPRT's parthenon: a sima's face ending on the ridge's plane keeps the corner in the
    # middle of its edge there; a face running beyond the plane is cut back to it
    vertices = [(0, 0, 0), (2, 0, 0), (2, 0, 1), (1, 0, 1), (0, 0, 1), (-1, 0, 2)]
    face = Mesh(vertices, [(0, 5, 4, 3, 2, 1)])  # turned to face -y; crosses z = 1 at its spike
    plane = TrimPlane((0.0, 0.0, -1.0), -1.0, False)  # keeps z <= 1
    cut = trimmed(face, np.zeros(3), np.eye(3), [plane])
    (kept,) = cut.faces
    corners = {tuple(np.round(cut.vertices[i], 9)) for i in kept}
    assert corners == {(0, 0, 0), (2, 0, 0), (2, 0, 1), (1, 0, 1), (0, 0, 1), (-0.5, 0, 1)}
