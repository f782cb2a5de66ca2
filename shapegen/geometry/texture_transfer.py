"""Texture coordinates carried from an initial shape's faces onto the faces derived on them.

CityEngine's runtime keeps a face's texture coordinates through the derivation: a shape passed
on unchanged, a component taken by ``comp``, a piece cut by ``split`` or ``offset`` keeps the
coordinates of the initial face it lies on (a cut's new corners interpolated). shapegen's
shapes carry no texture coordinates, so they are carried afterwards, by where each leaf face
lies: a face whose corners lie on an initial face (within
:data:`~shapegen.tolerances.TEXTURE_FACE_M` of its plane and of its outline) takes, at each
corner, the coordinates of the initial corner it is on, or, between corners, those of the
initial face's affine map from its plane to texture space (exact on a triangle, and on any face
whose coordinates are a planar projection, as modelling tools lay them). A face that has moved
off the initial faces (``t``, ``r``, ``s``, an extrusion's top and sides) finds none, and the
caller says so.

>>> square = np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0.0]])
>>> uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
>>> half = np.array([[0, 0, 0], [1, 0, 0], [1, 2, 0], [0, 2, 0.0]])
>>> ((k, found),) = carried_uvs(half, [(0, 1, 2, 3)], [square], [uv])
>>> k, (found.round(9) + 0.0).tolist()
(0, [[0.0, 0.0], [0.5, 0.0], [0.5, 1.0], [0.0, 1.0]])
"""

from __future__ import annotations

__all__ = ["carried_uvs"]

from collections.abc import Sequence

import numpy as np

from shapegen.tolerances import COSINE_SLACK, TEXTURE_FACE_M

#: two faces' normals this close to parallel (1 - |cos|) share a plane's direction
_PARALLEL = 1e-6


def carried_uvs(
    vertices: np.ndarray,
    faces: Sequence[Sequence[int]],
    source_faces: Sequence[np.ndarray],
    source_uvs: Sequence[np.ndarray],
    tolerance: float = TEXTURE_FACE_M,
) -> list[tuple[int, np.ndarray] | None]:
    """For each face of ``vertices`` (``(n, 3)`` m) and ``faces``, the initial face it lies on
    and its corners' ``(k, 2)`` texture coordinates, or None where it lies on none.

    ``source_faces`` are the initial faces' corners (``(k, 3)`` m each), ``source_uvs`` their
    corners' texture coordinates; ``tolerance`` (m) how far off a face may lie and still be on.
    """
    if not source_faces:
        return [None] * len(faces)
    import shapely

    normals = np.array([_unit_normal(face) for face in source_faces])
    anchors = np.array([face[0] for face in source_faces], dtype=float)
    frames, outlines, maps = [], [], []
    for face, normal, uv in zip(source_faces, normals, source_uvs, strict=True):
        frame = _plane_frame(normal)
        flat = (face - face[0]) @ frame.T
        frames.append(frame)
        outlines.append(shapely.Polygon(flat) if len(flat) >= 3 else shapely.Polygon())
        maps.append(_affine_map(flat, uv))
    out: list[tuple[int, np.ndarray] | None] = []
    points = np.asarray(vertices, dtype=float).reshape(-1, 3)
    for face in faces:
        corners = points[list(face)]
        normal = _unit_normal(corners)
        if not normal.any():
            out.append(None)
            continue
        parallel = 1.0 - np.abs(normals @ normal) <= _PARALLEL
        offsets = np.abs(np.einsum("sk,csk->cs", normals, corners[:, None, :] - anchors[None]))
        near = parallel & (offsets.max(axis=0) <= tolerance)
        found = None
        for k in np.flatnonzero(near):
            flat = (corners - source_faces[k][0]) @ frames[k].T
            inside = shapely.dwithin(outlines[k], shapely.points(flat), tolerance)
            centre = shapely.Point(flat.mean(axis=0))
            if inside.all() and shapely.dwithin(outlines[k], centre, tolerance):
                found = (int(k), _uvs_at(flat, source_faces[k], frames[k], source_uvs[k],
                                         maps[k], tolerance))  # fmt: skip
                break
        out.append(found)
    return out


def _unit_normal(corners: np.ndarray) -> np.ndarray:
    """The face's unit normal by Newell's sum (zero for a face of no area)."""
    corners = np.asarray(corners, dtype=float)
    normal = np.cross(corners, np.roll(corners, -1, axis=0)).sum(axis=0)
    length = float(np.linalg.norm(normal))
    return (
        normal / length
        if length > COSINE_SLACK * max(1.0, float(np.abs(corners).max()))
        else (np.zeros(3))
    )


def _plane_frame(normal: np.ndarray) -> np.ndarray:
    """Two unit vectors ``(2, 3)`` across the plane of ``normal``."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.array([first, np.cross(normal, first)])


def _affine_map(flat: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """The ``(3, 2)`` least-squares affine map from plane coordinates ``[x, y, 1]`` to texture
    coordinates (exact for a triangle and for a planar projection)."""
    rows = np.column_stack([flat, np.ones(len(flat))])
    solution, *_ = np.linalg.lstsq(rows, np.asarray(uv, dtype=float), rcond=None)
    return solution


def _uvs_at(flat, source, frame, uv, affine, tolerance) -> np.ndarray:
    """Each corner's texture coordinates: those of the initial corner it is on, else the
    initial face's affine map at it."""
    source_flat = (source - source[0]) @ frame.T
    out = np.column_stack([flat, np.ones(len(flat))]) @ affine
    distances = np.linalg.norm(flat[:, None, :] - source_flat[None], axis=2)
    nearest = distances.argmin(axis=1)
    on_corner = distances[np.arange(len(flat)), nearest] <= tolerance
    out[on_corner] = np.asarray(uv, dtype=float)[nearest[on_corner]]
    return out
