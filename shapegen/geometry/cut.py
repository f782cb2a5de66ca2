"""Cutting meshes by planes (CityEngine's ``split`` of a shape with geometry).

:func:`clip_half` keeps the part of a mesh on one side of an axis-aligned plane (coordinates are
the shape's scope coordinates, so a split plane is ``coordinate[axis] = value``). Faces are
clipped as polygons (a non-convex face stays one polygon); an intersection point is computed once
per cut edge, so two faces that shared the edge share the new vertex and a closed mesh stays
closed once capped. A closed mesh is capped with the loops of the cut ("hollow meshes are closed
after the cut", op_split); open meshes (faces) are not. Holes in a cap are not represented:
each loop becomes its own face.
"""

from __future__ import annotations

__all__ = ["clip_half", "clip_plane", "clip_slab", "convex_decomposition"]

import numpy as np

from shapegen.geometry.mesh import Mesh, polygon_area

_REL = 1e-9  # points closer than this times the mesh size to the plane lie on it


def clip_half(mesh: Mesh, axis: int, value: float, keep_above: bool) -> Mesh | None:
    """The part of ``mesh`` with ``coordinate[axis] >= value`` (``keep_above``) or ``<=``,
    capped if ``mesh`` is closed; None when nothing of positive extent is left."""
    if mesh.n_faces == 0:
        return None
    eps = _REL * max(mesh.size(), 1e-12)
    sign = 1.0 if keep_above else -1.0
    depth = (mesh.vertices[:, axis] - value) * sign
    if depth.min() >= -eps:
        return mesh
    if depth.max() <= eps:
        return None
    closed = mesh.is_closed
    points = [p for p in mesh.vertices]
    cut_points: dict[tuple[int, int], int] = {}

    def crossing(a: int, b: int) -> int:
        key = (a, b) if a < b else (b, a)
        index = cut_points.get(key)
        if index is None:
            i, j = key
            t = depth[i] / (depth[i] - depth[j])
            point = mesh.vertices[i] + t * (mesh.vertices[j] - mesh.vertices[i])
            point[axis] = value
            index = cut_points[key] = len(points)
            points.append(point)
        return index

    faces = []
    normals = mesh.face_normals()
    for k, face in enumerate(mesh.faces):
        ring: list[int] = []
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            if depth[a] >= -eps:
                ring.append(a)
            if (depth[a] > eps and depth[b] < -eps) or (depth[a] < -eps and depth[b] > eps):
                ring.append(crossing(a, b))
        ring = _without_repeats(ring)
        if len(ring) < 3:
            continue
        flags = [i >= len(depth) or abs(depth[i]) <= eps for i in ring]
        # the direction along the cut in which the kept part's boundary runs (interior on the
        # left): t = d x n, d the kept side, n the face normal
        side = np.zeros(3)
        side[axis] = sign
        along = np.cross(side, normals[k])
        faces.extend(_split_at_bridges(ring, flags, points, along))
    if not faces:
        return None
    vertices = np.array(points)
    if closed:
        faces.extend(_caps(faces))
    return _compact(vertices, faces)


def clip_slab(mesh: Mesh, axis: int, low: float, high: float) -> Mesh | None:
    """The part of ``mesh`` with ``low <= coordinate[axis] <= high`` (m), or None."""
    piece = clip_half(mesh, axis, low, True)
    if piece is None:
        return None
    return clip_half(piece, axis, high, False)


def _without_repeats(ring: list[int]) -> list[int]:
    out: list[int] = []
    for i in ring:
        if not out or out[-1] != i:
            out.append(i)
    while len(out) > 1 and out[0] == out[-1]:
        out.pop()
    return out


def _split_at_bridges(ring, flags, points, along) -> list[tuple[int, ...]]:
    """The polygons of a clipped ring: the ring is cut at its edges lying on the cut plane
    (where a non-convex face left several parts joined by zero-width bridges), and the chains
    in between are joined again along the cut in the boundary's direction ``along``."""
    n = len(ring)
    if all(flags):  # a face lying on the cut: the cap replaces it
        return []
    on_edges = [flags[k] and flags[(k + 1) % n] for k in range(n)]
    if not any(on_edges) or float(np.linalg.norm(along)) == 0:
        return [tuple(ring)] if len(ring) >= 3 else []
    start = (on_edges.index(True) + 1) % n  # a chain begins after an edge on the plane
    chains: list[list[int]] = []
    current: list[int] = []
    for step in range(n):
        k = (start + step) % n
        current.append(ring[k])
        if on_edges[k]:
            chains.append(current)
            current = []
    if current:
        chains.append(current)
    chains = [c for c in chains if len(c) >= 2]
    if not chains:
        return []
    position = {i: float(np.asarray(points[i]) @ along) for c in chains for i in (c[0], c[-1])}
    starts = sorted(range(len(chains)), key=lambda c: position[chains[c][0]])
    link: dict[int, int] = {}
    free = list(starts)
    for c in sorted(range(len(chains)), key=lambda c: position[chains[c][-1]]):
        end = position[chains[c][-1]]
        choice = next((s for s in free if position[chains[s][0]] >= end - 1e-12), None)
        if choice is None:
            choice = free[0]
        free.remove(choice)
        link[c] = choice
    polygons = []
    seen: set[int] = set()
    for first in range(len(chains)):
        if first in seen:
            continue
        polygon: list[int] = []
        c = first
        while c not in seen:
            seen.add(c)
            polygon.extend(chains[c])
            c = link[c]
        polygon = _without_repeats(polygon)
        if len(polygon) >= 3:
            polygons.append(tuple(polygon))
    return polygons


def _caps(faces: list[tuple[int, ...]]) -> list[tuple[int, ...]]:
    """Faces closing the boundary loops of a clipped closed mesh (each boundary edge turned
    around, chained into loops)."""
    directed = set()
    for face in faces:
        directed.update(zip(face, face[1:] + face[:1], strict=True))
    following: dict[int, int] = {}
    for a, b in directed:
        if (b, a) not in directed:
            following[b] = a  # the cap runs the edge the other way
    caps = []
    while following:
        start, nxt = following.popitem()
        loop = [start]
        while nxt != start and nxt in following:
            loop.append(nxt)
            nxt = following.pop(nxt)
        if nxt == start and len(loop) >= 3:
            caps.append(tuple(loop))
    return caps


def _compact(vertices: np.ndarray, faces: list[tuple[int, ...]]) -> Mesh | None:
    """The mesh of the faces with area (a bridge left along an earlier cut has none), or None."""
    span = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    faces = [f for f in faces if polygon_area(vertices[list(f)]) > _REL * span * span]
    if not faces:
        return None
    used: dict[int, int] = {}
    remapped = [tuple(used.setdefault(i, len(used)) for i in face) for face in faces]
    mesh = Mesh(vertices[list(used)], remapped)
    low, high = mesh.bounds()
    if float(np.max(high - low)) <= 0:
        return None
    return mesh


def clip_plane(mesh: Mesh, normal, offset: float, keep_above: bool) -> Mesh | None:
    """The part of ``mesh`` with ``normal . p >= offset`` (``keep_above``) or ``<=``; ``normal``
    a unit vector. The mesh is turned so that ``normal`` is its z axis, clipped, turned back."""
    from shapegen.geometry.frames import rotation_keeping_x

    normal = np.asarray(normal, float)
    guess = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    frame = rotation_keeping_x(guess, normal)  # y along the normal
    turned = Mesh(mesh.vertices @ frame, mesh.faces)
    piece = clip_half(turned, 1, offset, keep_above)
    if piece is None:
        return None
    return Mesh(piece.vertices @ frame.T, piece.faces)


def convex_decomposition(mesh: Mesh, max_pieces: int = 64) -> list[Mesh] | None:
    """Convex closed pieces whose union is the closed mesh ``mesh``: a non-convex piece is cut by
    the plane of one of its faces that has corners in front of it, until every piece is convex
    (the pieces share the cut planes as faces). None when it would take more than
    ``max_pieces`` pieces or a cut fails to close."""
    done: list[Mesh] = []
    todo = [mesh]
    while todo:
        piece = todo.pop()
        if piece.is_convex():
            done.append(piece)
            if len(done) > max_pieces:
                return None
            continue
        plane = _splitting_plane(piece)
        if plane is None:
            return None
        normal, offset = plane
        halves = [clip_plane(piece, normal, offset, side) for side in (False, True)]
        if any(h is None or not h.is_closed for h in halves):
            return None
        todo.extend(halves)
        if len(done) + len(todo) > max_pieces:
            return None
    return done


def _splitting_plane(mesh: Mesh):
    """The plane of the face with the most corners in front of it (a reflex face's plane)."""
    normals, centres = mesh._normals
    slack = _REL * max(mesh.size(), 1e-12)
    best = None
    for k in range(mesh.n_faces):
        n = normals[k]
        if not n.any():
            continue
        heights = (mesh.vertices - centres[k]) @ n
        ahead = int((heights > slack * 1e3).sum())
        behind = int((heights < -slack * 1e3).sum())
        if ahead and behind and (best is None or ahead > best[0]):
            best = (ahead, n, float(centres[k] @ n))
    return None if best is None else (best[1], best[2])
