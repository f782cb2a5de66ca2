"""Cutting meshes whose faces have holes by an axis-aligned plane (a ``split`` of a courtyard
building or of a lot with a courtyard).

:func:`~shapegen.geometry.cut.clip_half` hands a mesh with holes here. Each face is clipped
with its holes: every ring (the face's and its holes', the holes wound against the face) is
clipped as a polygon, each edge crossing the plane gets one new vertex, shared with the other
ring or face that runs the edge, and the rings' parts are joined along the cut in the boundary's
direction, as a non-convex face's parts are (:func:`~shapegen.geometry.rings.chain_loops`): a
hole the plane crosses becomes a notch of the face's boundary, a hole wholly kept stays a hole
of the part that holds it. A closed mesh is capped: the loops of the cut facing away from the
kept part are the caps, the loops facing the other way their holes (a floor of a courtyard
building has its courtyard).
"""

from __future__ import annotations

__all__ = ["clip_half_with_holes"]

import numpy as np

from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.geometry.rings import chains_between, joined_chains, without_repeats
from shapegen.tolerances import COINCIDENT_REL, SIZE_FLOOR_M


def clip_half_with_holes(mesh: Mesh, axis: int, value: float, keep_above: bool) -> Mesh | None:
    """:func:`~shapegen.geometry.cut.clip_half` of a mesh with holes: the part with
    ``coordinate[axis] >= value`` (``keep_above``) or ``<=``, capped if ``mesh`` is closed; None
    when nothing of positive extent is left."""
    eps = COINCIDENT_REL * max(mesh.size(), SIZE_FLOOR_M)
    sign = 1.0 if keep_above else -1.0
    vertices = mesh.vertices
    depth = ((vertices[:, axis] - value) * sign).tolist()
    if min(depth) >= -eps:
        return mesh
    if max(depth) <= eps:
        return None
    cut = _Crossings(vertices, depth, axis, value)
    normals = mesh.face_normals()
    faces: list[tuple[int, ...]] = []
    holes: list[tuple[tuple[int, ...], ...]] = []
    for k, face in enumerate(mesh.faces):
        rings = mesh.holes[k]
        near = [depth[i] for i in face]
        if min(near) > eps:  # wholly kept, its holes with it (they lie within it)
            faces.append(face)
            holes.append(rings)
            continue
        if max(near) <= eps:
            continue
        for part, part_holes in _clipped_face(face, rings, normals[k], cut, eps, axis, sign):
            faces.append(part)
            holes.append(part_holes)
    if not faces:
        return None
    points = cut.points()
    if mesh.is_closed:
        for cap, cap_holes in _caps(faces, holes, points, axis, sign):
            faces.append(cap)
            holes.append(cap_holes)
    return _compact(points, faces, holes, eps)


class _Crossings:
    """The new vertex of each edge crossing the plane, made once and shared."""

    def __init__(self, vertices: np.ndarray, depth: list[float], axis: int, value: float):
        self.vertices, self.depth, self.axis, self.value = vertices, depth, axis, value
        self.index: dict[tuple[int, int], int] = {}
        self.new: list[np.ndarray] = []

    def __call__(self, p: int, q: int) -> int:
        key = (p, q) if p < q else (q, p)
        found = self.index.get(key)
        if found is None:
            dp, dq = self.depth[p], self.depth[q]
            point = self.vertices[p] + dp / (dp - dq) * (self.vertices[q] - self.vertices[p])
            point[self.axis] = self.value
            found = self.index[key] = len(self.vertices) + len(self.new)
            self.new.append(point)
        return found

    def on_plane(self, i: int, eps: float) -> bool:
        return i >= len(self.vertices) or abs(self.depth[i]) <= eps

    def points(self) -> np.ndarray:
        return np.vstack([self.vertices, *self.new]) if self.new else self.vertices


def _clipped_face(face, rings, normal, cut: _Crossings, eps: float, axis: int, sign: float):
    """The parts ``(ring, holes)`` left of one face with holes."""
    chains: list[list[int]] = []
    closed: list[tuple[int, ...]] = []  # rings the plane does not open: a part, or a hole
    kept_holes: list[tuple[int, ...]] = []
    for r, ring in enumerate((face, *rings)):
        near = [cut.depth[i] for i in ring]
        if min(near) > eps:
            (closed if r == 0 else kept_holes).append(ring)
            continue
        if max(near) <= eps:
            continue
        clipped = _clipped_ring(ring, cut, eps)
        if len(clipped) < 3:
            continue
        flags = [cut.on_plane(i, eps) for i in clipped]
        on_edges = [flags[k] and flags[(k + 1) % len(clipped)] for k in range(len(clipped))]
        if not any(on_edges):
            (closed if r == 0 else kept_holes).append(tuple(clipped))
            continue
        chains += chains_between(clipped, on_edges)
    points = cut.points()
    parts = list(closed)
    if chains:
        # the direction along the cut in which the kept part's boundary runs (interior on
        # the left): d x n, d the kept side along the axis, n the face normal
        nx, ny, nz = (float(c) for c in normal)
        along = np.array(((0.0, -nz, ny), (nz, 0.0, -nx), (-ny, nx, 0.0))[axis]) * sign
        position = {i: float(points[i] @ along) for c in chains for i in (c[0], c[-1])}
        parts += joined_chains(chains, position)
    return _with_holes(parts, kept_holes, points, normal)


def _clipped_ring(ring, cut: _Crossings, eps: float) -> list[int]:
    out: list[int] = []
    count = len(ring)
    for m in range(count):
        p, q = ring[m], ring[(m + 1) % count]
        dp, dq = cut.depth[p], cut.depth[q]
        if dp >= -eps:
            out.append(p)
        if (dp > eps and dq < -eps) or (dp < -eps and dq > eps):
            out.append(cut(p, q))
    return without_repeats(out)


def _with_holes(parts, holes, points: np.ndarray, normal) -> list[tuple[tuple, tuple]]:
    """Each part with the holes that lie inside it (tested in the face's plane)."""
    if not holes:
        return [(part, ()) for part in parts]
    import shapely

    drop = int(np.argmax(np.abs(normal)))  # project along the normal's largest component
    keep = [a for a in range(3) if a != drop]
    shapes = [shapely.Polygon(points[list(part)][:, keep]) for part in parts]
    owned: list[list[tuple[int, ...]]] = [[] for _ in parts]
    for hole in holes:
        inside = shapely.Point(points[list(hole)][:, keep].mean(axis=0))
        for k, polygon in enumerate(shapes):
            if polygon.buffer(0).contains(inside):
                owned[k].append(hole)
                break
    return [(part, tuple(mine)) for part, mine in zip(parts, owned, strict=True)]


def _caps(faces, holes, points: np.ndarray, axis: int, sign: float):
    """The caps of a clipped closed mesh with their holes: every boundary edge of the rings
    (faces' and holes') turned around and chained into loops; a loop facing out of the kept
    part (against ``sign`` along ``axis``) is a cap, one facing the other way a hole of the
    cap that holds it."""
    rings = [*faces, *(ring for rs in holes for ring in rs)]
    edges = {(a, b) for ring in rings for a, b in zip(ring, ring[1:] + ring[:1], strict=True)}
    following = {b: a for a, b in edges if (b, a) not in edges}
    loops = []
    while following:
        first, nxt = following.popitem()
        loop = [first]
        while nxt != first and nxt in following:
            loop.append(nxt)
            nxt = following.pop(nxt)
        if nxt == first and len(loop) >= 3:
            loops.append(tuple(loop))
    outward = -sign
    outer = [loop for loop in loops if polygon_normal(points[list(loop)])[axis] * outward > 0]
    inner = [loop for loop in loops if polygon_normal(points[list(loop)])[axis] * outward <= 0]
    normal = np.zeros(3)
    normal[axis] = outward
    return _with_holes(outer, inner, points, normal)


def _compact(points: np.ndarray, faces, holes, eps: float) -> Mesh | None:
    """The mesh of the faces with area, its vertices those they use, or None."""
    mesh = Mesh(points, faces, holes)
    areas = mesh.face_areas()
    span = float(np.ptp(points, axis=0).max())
    keep = [k for k in range(len(faces)) if areas[k] > COINCIDENT_REL * span * span]
    if not keep:
        return None
    return mesh.subset(keep)
