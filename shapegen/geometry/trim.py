"""Trim planes: CityEngine's cut of inserted geometry at the shared edges of a component split.

op_comp: "for faces, the component split generates trim planes. Trim planes are placed along
the shared edges of the new faces in a bisecting angle." attr_trim: a plane is *horizontal* when
its generating edge makes less than 40 degrees with the pivot's x-z plane, else *vertical*
(the pivot of a component is its face's frame: x along the face's first edge, z its normal, so
an edge along the face's y direction is vertical: a wall's corners, a roof plane's hips);
inserted assets and primitives are cut by the enabled ones (vertical by default).

A face's plane at an edge it shares with a neighbour contains the edge and bisects the dihedral
angle between them: its normal is ``n_face - n_neighbour`` (both perpendicular to the edge),
turned so that the face itself lies on the kept side. Two coplanar faces make no plane, as in
CityEngine's runtime: candler's roof, ``offset(-0.8)`` and ``comp(f){inside: ...}`` on an
L-shaped lot, keeps whole the boxes its ``comp(e)`` sets at the inner L's far corners in
PyPRT's model, where a plane across the inside face's edge at the L's inner corner (a
half-space, and the face not convex) would cut them away.
"""

from __future__ import annotations

__all__ = [
    "HORIZONTAL_LIMIT_DEGREES",
    "FacePlanes",
    "TrimPlane",
    "deferred_face_trim_planes",
    "face_trim_planes",
    "moved_cut",
    "trimmed",
    "trimmed_solid",
]

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from shapegen.geometry.cut import clip_plane
from shapegen.geometry.mesh import Mesh, area_vectors, corner_layout, unit_face_normals
from shapegen.limits import check_clock
from shapegen.model.polygons import CheckedFaces, cross
from shapegen.tolerances import COINCIDENT_M, TRIM_PLANE_M

HORIZONTAL_LIMIT_DEGREES = 40.0
_SIN_LIMIT = math.sin(math.radians(HORIZONTAL_LIMIT_DEGREES))


@dataclass(frozen=True)
class TrimPlane:
    """The half-space ``normal . p >= offset`` (world coordinates, ``normal`` a unit vector)
    that inserted geometry is cut to; ``horizontal`` classifies its generating edge."""

    normal: tuple[float, float, float]
    offset: float
    horizontal: bool


def face_trim_planes(vertices: np.ndarray, faces, up: np.ndarray) -> list[tuple[TrimPlane, ...]]:
    """The trim planes of each face of a mesh given in world coordinates (``vertices``), one per
    edge the face shares with another face; ``up`` is the pivot's y axis (world), one for all
    faces or one row per face (a component's pivot is its face's frame: y in the face)."""
    up = np.asarray(up, dtype=float)
    ups = np.broadcast_to(up, (len(faces), 3)) if up.ndim == 1 else up
    vertices = np.asarray(vertices, dtype=float)
    if not isinstance(faces, CheckedFaces):
        faces = CheckedFaces(tuple(map(int, face)) for face in faces)
    if not faces:
        return []
    corners, start = corner_layout(faces)
    normals = area_vectors(vertices, corners, start)
    lengths = np.linalg.norm(normals, axis=1)
    normals = np.divide(
        normals, lengths[:, None], out=np.zeros_like(normals), where=lengths[:, None] > 0
    )
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = start[:-1]
    owner = np.repeat(np.arange(len(faces)), start[1:] - start[:-1])
    a, b = corners, corners[successor]
    n = len(vertices)
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.lexsort((owner, key))  # by edge, then by face: the faces of an edge in order
    keys, first, count = np.unique(key[order], return_index=True, return_counts=True)
    if (count > 2).any():  # an edge of three faces or more: the general rule, face by face
        return _face_trim_planes_by_face(vertices, faces, unit_face_normals(vertices, faces), ups)
    group = np.searchsorted(keys, key)
    lead, last = owner[order[first[group]]], owner[order[first[group] + count[group] - 1]]
    other = np.where(lead == owner, last, lead)  # the first face of the edge that is not this one
    shared = other != owner
    edge = vertices[b] - vertices[a]
    length = np.linalg.norm(edge, axis=1)
    shared &= length > COINCIDENT_M
    k = np.flatnonzero(shared)
    edge = edge[k] / length[k, None]
    own = normals[owner[k]]
    inward = cross(own, edge)  # in the face's plane, into the face (it runs counter-clockwise)
    normal = own - normals[other[k]]
    # coplanar neighbours bisect no angle: no plane (module doc)
    kept = np.linalg.norm(normal, axis=1) > COINCIDENT_M
    k, edge, own, inward, normal = k[kept], edge[kept], own[kept], inward[kept], normal[kept]
    flat = np.abs(np.einsum("ij,ij->i", normal, inward)) <= COINCIDENT_M
    normal[flat] = inward[flat]  # folded flat (back to back): the plane across the edge
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    normal[np.einsum("ij,ij->i", normal, inward) < 0] *= -1.0
    offset = np.einsum("ij,ij->i", normal, vertices[a[k]])
    horizontal = np.abs(np.einsum("ij,ij->i", edge, ups[owner[k]])) < _SIN_LIMIT
    out: list[list[TrimPlane]] = [[] for _ in faces]
    for f, plane, height, flag in zip(
        owner[k].tolist(), normal.tolist(), offset.tolist(), horizontal.tolist(), strict=True
    ):
        out[f].append(TrimPlane(tuple(plane), height, flag))
    return [tuple(planes) for planes in out]


def deferred_face_trim_planes(vertices, faces, up) -> list[FacePlanes]:
    """:func:`face_trim_planes`, worked out when one face's planes are first read.

    A component split makes trim planes for every face, but only an insert (``i()``, a
    primitive, ``trim()``) below it reads them: most components of a building are split on
    without ever inserting, and their planes need not be made."""
    faces = faces if isinstance(faces, tuple) else tuple(faces)
    pending = _PendingPlanes(np.array(vertices, dtype=float), faces, np.array(up, float))
    return [FacePlanes(pending, k) for k in range(len(pending.faces))]


class _PendingPlanes:
    __slots__ = ("vertices", "faces", "up", "planes")

    def __init__(self, vertices, faces, up):
        self.vertices, self.faces, self.up, self.planes = vertices, faces, up, None

    def of(self, index: int) -> tuple[TrimPlane, ...]:
        if self.planes is None:
            self.planes = face_trim_planes(self.vertices, self.faces, self.up)
            self.vertices = self.up = None  # no longer needed
        return self.planes[index]


class FacePlanes(Sequence):
    """One face's trim planes (a sequence of :class:`TrimPlane`), made with its mesh's others
    when first read (:func:`deferred_face_trim_planes`)."""

    __slots__ = ("_pending", "_index")

    def __init__(self, pending: _PendingPlanes, index: int):
        self._pending, self._index = pending, index

    def __getitem__(self, k):
        return self._pending.of(self._index)[k]

    def __len__(self) -> int:
        return len(self._pending.of(self._index))

    def __eq__(self, other) -> bool:
        return tuple(self) == (tuple(other) if isinstance(other, Sequence) else other)

    def __hash__(self) -> int:
        return hash(tuple(self))

    def __repr__(self) -> str:
        return repr(self._pending.of(self._index))


def _face_trim_planes_by_face(vertices, faces, normals, ups) -> list[tuple[TrimPlane, ...]]:
    sharing: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            sharing.setdefault((min(a, b), max(a, b)), []).append(f)
    out = []
    for f, face in enumerate(faces):
        check_clock()
        planes = []
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            others = [g for g in sharing[(min(a, b), max(a, b))] if g != f]
            if not others:
                continue
            plane = _bisector(vertices[a], vertices[b], normals[f], normals[others[0]], ups[f])
            if plane is not None:
                planes.append(plane)
        out.append(tuple(planes))
    return out


def _bisector(start, end, own: np.ndarray, other: np.ndarray, up) -> TrimPlane | None:
    edge = end - start
    length = float(np.linalg.norm(edge))
    if length <= COINCIDENT_M:
        return None
    edge = edge / length
    inward = np.cross(own, edge)  # in the face's plane, into the face (it runs counter-clockwise)
    normal = own - other
    if np.linalg.norm(normal) <= COINCIDENT_M:
        return None  # coplanar neighbours bisect no angle: no plane (module doc)
    if abs(float(normal @ inward)) <= COINCIDENT_M:
        normal = inward  # folded flat (back to back): the plane across the edge
    normal = normal / np.linalg.norm(normal)
    if normal @ inward < 0:
        normal = -normal
    horizontal = abs(float(edge @ up)) < _SIN_LIMIT
    return TrimPlane(tuple(float(c) for c in normal), float(normal @ start), horizontal)


def trimmed(mesh: Mesh, origin, rotation, planes) -> Mesh | None:
    """``mesh`` (coordinates of the frame ``origin``, ``rotation``: a (3, 3) array or its 9
    entries row by row) cut to every plane in
    ``planes``; None when nothing is left, ``mesh`` itself when no plane cuts it.

    The outcome is kept for the same mesh and the same planes in the mesh's frame (a bounded
    cache): a rebuild (a search, the design page) inserts the same assets at the same places
    and would cut them again, plane by plane."""
    # in Python floats: a few planes a shape, where numpy's per-call cost would dominate
    ox, oy, oz = (float(v) for v in origin)
    r = rotation.ravel().tolist() if isinstance(rotation, np.ndarray) else rotation
    local = []
    for plane in planes:
        nx, ny, nz = plane.normal
        local.append(
            (
                r[0] * nx + r[3] * ny + r[6] * nz,
                r[1] * nx + r[4] * ny + r[7] * nz,
                r[2] * nx + r[5] * ny + r[8] * nz,
                plane.offset - (nx * ox + ny * oy + nz * oz),
            )
        )
    key = (mesh.vertices.tobytes(), id(mesh.faces), tuple(local))
    kept = _TRIMMED.get(key)
    if kept is not None and kept[0] is mesh.faces:  # the same faces object, not a reused id
        return mesh if kept[1] is _UNCUT else kept[1]
    cut = _trimmed(mesh, local)
    while _TRIMMED and (len(_TRIMMED) >= _TRIMMED_LIMIT or _held[0] > _TRIMMED_BYTES):
        oldest = next(iter(_TRIMMED))  # the oldest entry goes first
        _held[0] -= _entry_bytes(oldest, _TRIMMED.pop(oldest)[1])
    entry = (mesh.faces, _UNCUT if cut is mesh else cut)
    _TRIMMED[key] = entry
    _held[0] += _entry_bytes(key, entry[1])
    return cut


def _entry_bytes(key, cut) -> int:
    """About what an entry of the cut cache holds: the key's vertices and the cut's."""
    return len(key[0]) + (cut.vertices.nbytes * 3 if isinstance(cut, Mesh) else 0)


def trimmed_solid(mesh: Mesh | None) -> Mesh | None:
    """The closed solid a trimmed cut of a closed mesh bounds (:func:`trimmed`: the cut with
    its caps on the trim planes, the same vertices), None for any other mesh."""
    return None if mesh is None else mesh.__dict__.get(_SOLID)


def moved_cut(cut: Mesh, vertices) -> Mesh:
    """A cut of :func:`trimmed` with its vertices at ``vertices`` (the same count and order),
    keeping its solid (:func:`trimmed_solid`) on the same vertices."""
    moved = Mesh.of_valid_faces(vertices, cut.faces, holes=cut.holes)
    solid = trimmed_solid(cut)
    if solid is not None:
        moved.__dict__[_SOLID] = Mesh.of_valid_faces(moved.vertices, solid.faces)
    return moved


def _trimmed(mesh: Mesh, local) -> Mesh | None:
    cutting = []
    for *normal, local_offset in local:
        local_normal = np.array(normal)
        heights = mesh.vertices @ local_normal - local_offset
        if heights.min() >= -TRIM_PLANE_M:
            continue
        piece = clip_plane(mesh, local_normal, local_offset, keep_above=True,
                           tolerance=TRIM_PLANE_M)  # fmt: skip
        if piece is None:
            return None
        mesh = piece
        cutting.append((local_normal, local_offset))
    return _uncapped(mesh, cutting) if cutting and mesh.is_closed else mesh


def _uncapped(solid: Mesh, planes) -> Mesh:
    """``solid`` (a closed mesh cut to ``planes``) without the caps the cuts closed it with:
    CityEngine's runtime cuts an insert at the trim planes and leaves the cut open (PyPRT's
    candler: no face on any trim plane, every vertex of the cut). The open mesh keeps the
    solid (:func:`trimmed_solid`), which the statics judge."""
    normals = solid.face_normals()
    corners, start = solid.corner_layout
    cap = np.zeros(solid.n_faces, dtype=bool)
    for normal, offset in planes:
        on = np.abs(solid.vertices @ normal - offset) <= TRIM_PLANE_M
        facing = normals @ normal < 0.0  # a cap faces away from the kept side
        cap |= np.logical_and.reduceat(on[corners], start[:-1]) & facing
    kept = [face for face, is_cap in zip(solid.faces, cap.tolist(), strict=True) if not is_cap]
    vertices = solid.vertices
    if len(kept) == solid.n_faces:
        return solid
    if not kept:
        return solid  # nothing but caps: a sliver of the plane, kept as it is
    holes = ()
    if solid.holes:  # the kept faces keep theirs (PyPRT: a courtyard slab cut by its planes)
        holes = tuple(r for r, is_cap in zip(solid.holes, cap.tolist(), strict=True) if not is_cap)
        holes = holes if any(holes) else ()
    cut = Mesh.of_valid_faces(vertices, tuple(kept), holes=holes)
    cut.__dict__[_SOLID] = solid
    return cut


_SOLID = "trimmed_solid"  # the key under which an open trimmed cut keeps its solid


_TRIMMED: dict = {}
_TRIMMED_LIMIT = 256  # cuts kept by trimmed()
_TRIMMED_BYTES = 64 << 20  # and about this much memory at most
_held = [0]  # bytes held by _TRIMMED now
_UNCUT = object()
