"""Texture coordinates carried from an initial shape's faces onto the faces derived on them.

CityEngine's runtime keeps a face's texture coordinates through the derivation: a shape passed
on unchanged, a component taken by ``comp``, a piece cut by ``split`` or ``offset`` keeps the
coordinates of the initial face it lies on (a cut's new corners interpolated). shapegen's
shapes carry no texture coordinates, so they are carried afterwards, by where each leaf face
lies: a face whose corners lie on an initial face (within
:data:`~shapegen.tolerances.TEXTURE_FACE_M` of its plane and of its outline) takes, at each
corner, the coordinates of the initial corner it is on, or, between corners, those of the
initial face's affine map from its plane to texture space (exact on a triangle, and on any face
whose coordinates are a planar projection, as modelling tools lay them). A face that lies over
an initial face instead (an extrusion's top and sides, and what is cut of them) takes, at each
corner, the coordinates of the point of the initial face below it along the face's normal: as
CityEngine's runtime gives an extruded face's six faces, each corner the coordinates of the
corner it was extruded from (PyPRT's OBJ files tests/data/obj-pyprt/extruded_*). A face that
has moved off the initial faces (``t``, ``r``, ``s`` across them) finds none, and the caller
says so.

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
    points = np.asarray(vertices, dtype=float).reshape(-1, 3)
    sources = _Sources(source_faces, source_uvs, tolerance)
    out: list[tuple[int, np.ndarray] | None] = []
    for face in faces:
        corners = points[list(face)]
        found = sources.same_corners(corners)
        if found is None:
            found = sources.lying_on(corners)
        out.append(found if found is not None else sources.over(corners))
    return out


class _Sources:
    """The initial faces, with what finding the one a face lies on needs: each face keyed by
    its corners (a face passed on unchanged is found at once), and the bounding spheres,
    planes and outlines of the others (made when first asked)."""

    def __init__(self, faces, uvs, tolerance: float):
        self.faces = [np.asarray(face, dtype=float) for face in faces]
        self.uvs = [np.asarray(uv, dtype=float) for uv in uvs]
        self.tolerance = tolerance
        self.by_corners: dict[tuple, int] = {}
        for k, face in enumerate(self.faces):
            self.by_corners.setdefault(self._key(face), k)
        self._planes = None

    def _key(self, corners: np.ndarray) -> tuple:
        return tuple(
            sorted(map(tuple, np.round(corners / self.tolerance).astype(np.int64).tolist()))
        )

    def same_corners(self, corners: np.ndarray) -> tuple[int, np.ndarray] | None:
        """The initial face with these very corners (to the tolerance's grid), each corner
        taking its coordinates; None when there is none."""
        k = self.by_corners.get(self._key(corners))
        if k is None:
            return None
        source = self.faces[k]
        distances = np.linalg.norm(corners[:, None, :] - source[None], axis=2)
        return k, self.uvs[k][distances.argmin(axis=1)]

    def lying_on(self, corners: np.ndarray) -> tuple[int, np.ndarray] | None:
        """The initial face ``corners`` lie on (its plane and outline) and their coordinates."""
        import shapely

        normal = _unit_normal(corners)
        if not normal.any():
            return None
        normals, anchors, centres, radii, spheres = self._spheres()
        centre = corners.mean(axis=0)
        reach = float(np.linalg.norm(corners - centre, axis=1).max()) + self.tolerance
        nearby = np.array(spheres.query_ball_point(centre, reach + radii.max()), dtype=int)
        nearby = nearby[np.linalg.norm(centres[nearby] - centre, axis=1) <= reach + radii[nearby]]
        parallel = 1.0 - np.abs(normals[nearby] @ normal) <= COSINE_SLACK
        offsets = np.einsum("sk,csk->cs", normals[nearby], corners[:, None, :] - anchors[nearby])
        for k in np.sort(nearby[parallel & (np.abs(offsets).max(axis=0) <= self.tolerance)]):
            source = self.faces[k]
            frame = _plane_frame(normals[k])
            source_flat = (source - source[0]) @ frame.T
            flat = (corners - source[0]) @ frame.T
            outline = shapely.Polygon(source_flat)
            inside = shapely.dwithin(outline, shapely.points(flat), self.tolerance)
            middle = shapely.Point(flat.mean(axis=0))
            if inside.all() and shapely.dwithin(outline, middle, self.tolerance):
                return int(k), _uvs_at(flat, source_flat, self.uvs[k], self.tolerance)
        return None

    def over(self, corners: np.ndarray) -> tuple[int, np.ndarray] | None:
        """The initial face ``corners`` lie over (each corner, moved along the initial face's
        normal into its plane, on it) and the coordinates of those points."""
        import shapely

        normals, anchors, centres, radii, _ = self._spheres()
        # the corners moved into each initial face's plane, near enough its centre
        offsets = np.einsum("sk,csk->cs", normals, corners[:, None, :] - anchors[None])
        dropped = corners[:, None, :] - offsets[..., None] * normals[None]
        reach = np.linalg.norm(dropped - centres[None], axis=2).max(axis=0)
        for k in np.flatnonzero(reach <= radii + self.tolerance):
            source = self.faces[k]
            frame = _plane_frame(normals[k])
            source_flat = (source - source[0]) @ frame.T
            flat = (dropped[:, k] - source[0]) @ frame.T
            outline = shapely.Polygon(source_flat)
            # a face seen edge-on from the initial face (a side) stands on its outline, as an
            # extrusion's sides stand on its edges; one standing inside it is no extrusion's
            edge_on = abs(_flat_area(flat)) <= self.tolerance * float(np.ptp(flat, axis=0).max())
            if edge_on:
                covered = outline.exterior.buffer(self.tolerance).covers(
                    shapely.LineString(np.concatenate([flat, flat[:1]]))
                )
            else:
                covered = outline.buffer(self.tolerance).covers(shapely.Polygon(flat))
            if covered:
                return int(k), _uvs_at(flat, source_flat, self.uvs[k], self.tolerance)
        return None

    def _spheres(self):
        if self._planes is None:
            from scipy.spatial import cKDTree

            normals = np.array([_unit_normal(face) for face in self.faces])
            anchors = np.array([face[0] for face in self.faces])
            # the initial faces near a face, by their bounding spheres: a mesh of thousands of
            # faces is not compared face against face
            centres = np.array([face.mean(axis=0) for face in self.faces])
            radii = np.array([np.linalg.norm(face - c, axis=1).max() for face, c in
                              zip(self.faces, centres, strict=True)])  # fmt: skip
            self._planes = (normals, anchors, centres, radii, cKDTree(centres))
        return self._planes


def _unit_normal(corners: np.ndarray) -> np.ndarray:
    """The face's unit normal by Newell's sum (zero for a face of no area)."""
    corners = np.asarray(corners, dtype=float)
    normal = np.cross(corners, np.roll(corners, -1, axis=0)).sum(axis=0)
    length = float(np.linalg.norm(normal))
    floor = COSINE_SLACK * max(1.0, float(np.abs(corners).max()))
    return normal / length if length > floor else np.zeros(3)


def _flat_area(flat: np.ndarray) -> float:
    """The signed area of a ring of ``(k, 2)`` points (m^2)."""
    x, y = flat[:, 0], flat[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _plane_frame(normal: np.ndarray) -> np.ndarray:
    """Two unit vectors ``(2, 3)`` across the plane of ``normal``."""
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    first = np.cross(normal, helper)
    first /= np.linalg.norm(first)
    return np.array([first, np.cross(normal, first)])


def _uvs_at(flat, source_flat, uv, tolerance) -> np.ndarray:
    """Each corner's texture coordinates: those of the initial corner it is on, else the
    initial face's least-squares affine map from plane coordinates ``[x, y, 1]`` to texture
    coordinates at it (exact for a triangle and for a planar projection)."""
    rows = np.column_stack([source_flat, np.ones(len(source_flat))])
    affine, *_ = np.linalg.lstsq(rows, uv, rcond=None)
    out = np.column_stack([flat, np.ones(len(flat))]) @ affine
    distances = np.linalg.norm(flat[:, None, :] - source_flat[None], axis=2)
    nearest = distances.argmin(axis=1)
    on_corner = distances[np.arange(len(flat)), nearest] <= tolerance
    out[on_corner] = uv[nearest[on_corner]]
    return out
