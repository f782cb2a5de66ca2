"""Scope frames of geometry, as CityEngine sets them.

- a face's frame (``comp(f)``, the lot): x along its first edge, z along its normal, y = z x x;
- a scope fitted to geometry in a given frame: the origin at the bounding box's minimum corner,
  the size its extent (``attr_scope``: "the scope is the bounding box of the geometry");
- the lot polygon: points ``(x, z)`` counter-clockwise seen from above (+y); its scope has x along
  the first edge and y up.
"""

from __future__ import annotations

__all__ = [
    "face_rotation",
    "frame_keeping_x",
    "fills_rectangle",
    "fitted_face_scopes",
    "fitted_scope",
    "lot_polygon",
    "polygon_face",
    "quadrant",
    "rotation_keeping_x",
]

import math
from typing import TYPE_CHECKING

import numpy as np

from shapegen.errors import GeometryError
from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL, ROUNDOFF_REL, ZERO_LENGTH

if TYPE_CHECKING:
    from shapegen.model.lot import Lot


def _unit(vector: np.ndarray) -> np.ndarray | None:
    length = float(np.linalg.norm(vector))
    return None if length <= ZERO_LENGTH else vector / length


def _unit3(x: float, y: float, z: float) -> tuple[float, float, float] | None:
    """A 3-vector of Python floats divided by its length, or None when it is shorter than
    ZERO_LENGTH (frames are built one polygon at a time: numpy's per-call cost would dominate)."""
    length = math.sqrt(x * x + y * y + z * z)
    return None if length <= ZERO_LENGTH else (x / length, y / length, z / length)


def _cross3(a, b) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def face_rotation(points: np.ndarray, normal: np.ndarray | None = None) -> np.ndarray:
    """The frame of a planar polygon (columns x, y, z): x along its first edge of non-zero
    length, z its normal (Newell's unless given), y = z x x. A degenerate polygon gets a frame
    with z along ``normal`` or +y."""
    p = np.asarray(points, float)
    n = polygon_normal(p) if normal is None else np.asarray(normal, float)
    z = _unit3(*n.tolist()) or (0.0, 1.0, 0.0)
    corners = p.tolist()
    x = None
    for k, (a, b) in enumerate(zip(corners, corners[1:] + corners[:1], strict=True)):
        edge = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
        along = edge[0] * z[0] + edge[1] * z[1] + edge[2] * z[2]
        x = _unit3(edge[0] - z[0] * along, edge[1] - z[1] * along, edge[2] - z[2] * along)
        if x is not None or k == len(corners) - 1:
            break
    if x is None:
        x = _unit3(*_cross3((0.0, 1.0, 0.0), z)) or (1.0, 0.0, 0.0)
    y = _cross3(z, x)
    return np.array([x, y, z]).T.copy()


def rotation_keeping_x(old_x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """A frame with y along ``y`` and x as close to ``old_x`` as possible (``old_x`` projected to
    the plane normal to y), z = x x y (CityEngine's scope after ``extrude``)."""
    if isinstance(old_x, np.ndarray):
        old_x = old_x.tolist()
    if isinstance(y, np.ndarray):
        y = y.tolist()
    return np.array(frame_keeping_x(old_x, y)).reshape(3, 3)


def frame_keeping_x(old_x, y) -> tuple:
    """:func:`rotation_keeping_x` of two sequences of 3 floats, as the frame's 9 entries row by
    row (Python floats: a scope's form, :class:`~shapegen.model.scope.Scope`'s ``r``)."""
    y = _unit3(float(y[0]), float(y[1]), float(y[2]))
    if y is None:
        raise ValueError("a frame needs a direction of non-zero length")
    x = None
    # old x along the new y: take any perpendicular, preferring world x then z
    for guess in (old_x, (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)):
        along = guess[0] * y[0] + guess[1] * y[1] + guess[2] * y[2]
        x = _unit3(guess[0] - y[0] * along, guess[1] - y[1] * along, guess[2] - y[2] * along)
        if x is not None:
            break
    z = _cross3(x, y)
    return (x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2])


def fitted_scope(world_points: np.ndarray, rotation: np.ndarray) -> tuple[Scope, np.ndarray]:
    """The scope with axes ``rotation`` that is the bounding box of ``world_points``, and the
    points in that scope's coordinates (m)."""
    points = np.asarray(world_points, float).reshape(-1, 3)
    if len(points) == 0:  # what a cleanup left of a degenerate mesh
        raise GeometryError("the shape has no geometry left to fit a scope to")
    local = points @ rotation
    low = local.min(axis=0)
    size = local.max(axis=0) - low
    size[np.abs(size) < ROUNDOFF_REL * max(1.0, float(np.abs(local).max()))] = 0.0
    return Scope(rotation @ low, rotation, size), local - low


def fitted_face_scopes(
    points: np.ndarray, normals: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The scopes of a batch of planar polygons of the same corner count, as
    :func:`face_rotation` and :func:`fitted_scope` make them one at a time: ``points``
    ``(n, k, 3)`` world corners (m), ``normals`` ``(n, 3)`` their normals. Returns the origins
    ``(n, 3)``, rotations ``(n, 3, 3)`` (columns x, y, z), sizes ``(n, 3)`` and the corners in
    each scope's coordinates ``(n, k, 3)``."""
    n0, n1, n2 = normals[:, 0], normals[:, 1], normals[:, 2]
    length = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    flat = length <= ZERO_LENGTH
    with np.errstate(invalid="ignore", divide="ignore"):
        z = normals / length[:, None]
    z[flat] = (0.0, 1.0, 0.0)
    edges = np.concatenate([points[:, 1:], points[:, :1]], axis=1) - points
    along = edges[..., 0] * z[:, None, 0] + edges[..., 1] * z[:, None, 1]
    along = along + edges[..., 2] * z[:, None, 2]
    across = edges - z[:, None, :] * along[..., None]
    a0, a1, a2 = across[..., 0], across[..., 1], across[..., 2]
    reach = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    usable = reach > ZERO_LENGTH
    first = usable.argmax(axis=1)
    rows = np.arange(len(points))
    with np.errstate(invalid="ignore", divide="ignore"):
        x = across[rows, first] / reach[rows, first][:, None]
    rotations = np.empty((len(points), 3, 3))
    rotations[:, :, 0] = x
    rotations[:, :, 1] = np.stack(
        [
            z[:, 1] * x[:, 2] - z[:, 2] * x[:, 1],
            z[:, 2] * x[:, 0] - z[:, 0] * x[:, 2],
            z[:, 0] * x[:, 1] - z[:, 1] * x[:, 0],
        ],
        axis=1,
    )
    rotations[:, :, 2] = z
    for row in np.flatnonzero(~usable.any(axis=1)):  # no edge off the normal: one at a time
        rotations[row] = face_rotation(points[row], normals[row])
    local = points @ rotations
    low = local.min(axis=1)
    sizes = local.max(axis=1) - low
    span = np.maximum(1.0, np.abs(local).max(axis=(1, 2)))
    sizes[np.abs(sizes) < ROUNDOFF_REL * span[:, None]] = 0.0
    origins = np.einsum("nij,nj->ni", rotations, low)
    return origins, rotations, sizes, local - low[:, None, :]


def fills_rectangle(local: np.ndarray, sizes: np.ndarray) -> list[bool]:
    """Per quad ``(n, 4, 3)``: its corners are (0, 0) (sx, 0) (sx, sy) (0, sy) of its scope, as
    ``np.allclose`` tells (absolute slack COINCIDENT_REL of the larger side, relative 1e-5);
    other polygons ``(n, k, 3)`` do not."""
    if local.shape[1] != 4:
        return [False] * len(local)
    sx, sy = sizes[:, 0], sizes[:, 1]
    expected = np.zeros_like(local)
    expected[:, 1, 0] = expected[:, 2, 0] = sx
    expected[:, 2, 1] = expected[:, 3, 1] = sy
    slack = COINCIDENT_REL * np.maximum(np.maximum(sx, sy), COINCIDENT_M)
    close = np.abs(local - expected) <= slack[:, None, None] + 1e-5 * np.abs(expected)
    return close.all(axis=(1, 2)).tolist()


def lot_polygon(lot: Lot) -> tuple[Scope, Mesh]:
    """The start shape of a polygon :class:`~shapegen.model.lot.Lot` (checked when it was made,
    at the edge: not again here). Returns the scope (x along the first edge, y up, the bounding
    box in that frame) and the face in scope coordinates."""
    return polygon_face(lot.corners, lot.holes)


def polygon_face(corners, holes=()) -> tuple[Scope, Mesh]:
    """The face of ``corners`` ``(x, z)`` (m, counter-clockwise seen from above, as a
    :class:`~shapegen.model.lot.Lot` has them; not checked here) in a scope with x along its
    first edge and y up; ``holes`` its hole rings (clockwise seen from above), whose corners
    follow the polygon's in the mesh."""
    flat = np.array(corners, dtype=float)
    world = np.column_stack([flat[:, 0], np.zeros(len(flat)), flat[:, 1]])
    if len(holes):
        rings, first = [], len(flat)
        for hole in holes:
            rings.append(tuple(range(first, first + len(hole))))
            first += len(hole)
        inner = np.array([corner for hole in holes for corner in hole], dtype=float)
        rotation = face_rotation(world, np.array([0.0, 1.0, 0.0]))
        rotation = np.column_stack(
            [rotation[:, 0], [0.0, 1.0, 0.0], np.cross(rotation[:, 0], [0, 1, 0])]
        )
        every = np.vstack(
            [world, np.column_stack([inner[:, 0], np.zeros(len(inner)), inner[:, 1]])]
        )
        scope, local = fitted_scope(every, rotation)
        return scope, Mesh(local, [tuple(range(len(flat)))], [tuple(rings)])
    rotation = face_rotation(world, np.array([0.0, 1.0, 0.0]))
    # x along the first edge, y up (the lot's normal), z = x x y
    rotation = np.column_stack(
        [rotation[:, 0], [0.0, 1.0, 0.0], np.cross(rotation[:, 0], [0, 1, 0])]
    )
    scope, local = fitted_scope(world, rotation)
    return scope, Mesh.polygon(local)


_QUADRANTS = {
    (0, 1): "right",
    (0, -1): "left",
    (1, 1): "top",
    (1, -1): "bottom",
    (2, 1): "front",
    (2, -1): "back",
}


def quadrant(normal: np.ndarray) -> str:
    """``front back left right top bottom`` of a direction in scope coordinates: its largest
    component (CityEngine classifies face normals into the scope's quadrants)."""
    n = np.asarray(normal, float).tolist()  # three floats: numpy's calls cost more here
    a = [abs(v) for v in n]
    if a[0] != a[0] or a[1] != a[1] or a[2] != a[2]:  # NaN: argmax takes the first NaN
        axis = int(np.argmax(np.abs(np.asarray(n))))
    else:  # the first largest, as np.argmax
        axis = 0 if a[0] >= a[1] and a[0] >= a[2] else (1 if a[1] >= a[2] else 2)
    if a[1] >= max(a[0], a[2]) - ROUNDOFF_REL and n[1] != 0:
        axis = 1
    return _QUADRANTS[(axis, 1 if n[axis] >= 0 else -1)]
