"""Texture coordinates carried onto derived faces by where they lie: on an initial corner its
coordinates, between corners the initial face's affine map (closed forms below), over an initial
face (an extrusion's top and sides) those of the point below, off the initial faces none."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.geometry.texture_transfer import carried_uvs

# a 4 x 2 m wall in the plane x = 3, facing +x, its coordinates (z / 4, y / 2) plus a shift
WALL = np.array([[3, 0, 0], [3, 0, 4], [3, 2, 4], [3, 2, 0.0]])
WALL_UV = np.array([[0.5, 0], [1.5, 0], [1.5, 1], [0.5, 1.0]])


def wall_uv(points: np.ndarray) -> np.ndarray:
    return np.column_stack([points[:, 2] / 4 + 0.5, points[:, 1] / 2])


def test_a_piece_of_a_face_takes_the_coordinates_of_where_its_corners_lie():
    piece = np.array([[3, 0.5, 1], [3, 0.5, 3.5], [3, 2, 3.5], [3, 2, 1.0]])
    ((k, uv),) = carried_uvs(piece, [(0, 1, 2, 3)], [WALL], [WALL_UV])
    assert k == 0
    assert uv == pytest.approx(wall_uv(piece), abs=1e-12)


def test_a_face_on_an_initial_corner_takes_its_coordinates_exactly():
    # a triangle's texture coordinates need not be an affine map of a quad's: a corner that
    # is an initial corner takes that corner's, whatever the map gives
    uv = WALL_UV.copy()
    uv[2] = (9.0, 9.0)
    ((_, found),) = carried_uvs(WALL, [(0, 1, 2)], [WALL], [uv])
    assert found.tolist() == uv[:3].tolist()


@pytest.mark.parametrize(
    "moved",
    [
        WALL + (0.001, 3, 0),  # off the plane by 1 mm, beyond the face
        WALL + (0, 3, 0),  # in the plane, beyond the face
        WALL[:, [2, 1, 0]],  # turned to face +z, standing inside the wall, not on its edge
    ],
)
def test_a_face_off_the_initial_faces_finds_none(moved):
    assert carried_uvs(moved, [(0, 1, 2, 3)], [WALL], [WALL_UV]) == [None]


def test_a_face_over_an_initial_face_takes_the_coordinates_below_it():
    # the wall extruded 1.5 m along +x: its top, and a side standing on its bottom edge
    top = WALL + (1.5, 0, 0)
    side = np.array([[3, 0, 0], [4.5, 0, 0], [4.5, 0, 4], [3, 0, 4.0]])
    (k, uv), (j, side_uv) = carried_uvs(
        np.concatenate([top, side]), [(0, 1, 2, 3), (4, 5, 6, 7)], [WALL], [WALL_UV]
    )
    assert k == j == 0
    assert uv == pytest.approx(WALL_UV, abs=1e-12)
    assert side_uv == pytest.approx(wall_uv(side), abs=1e-12)  # (z / 4 + 0.5, 0)


def test_the_initial_face_a_face_lies_on_is_the_one_whose_coordinates_it_takes():
    floor = np.array([[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0.0]])
    floor_uv = np.array([[0, 0], [0, 1], [1, 1], [1, 0.0]])
    faces = [(0, 1, 2, 3), (4, 5, 6, 7)]
    points = np.concatenate([WALL, floor])
    found = carried_uvs(points, faces, [floor, WALL], [floor_uv, WALL_UV])
    assert [k for k, _ in found] == [1, 0]
    assert found[1][1].tolist() == floor_uv.tolist()
