"""An asset's polygons cleaned as CityEngine's runtime cleans an asset it reads.

CityEngine keeps an asset's vertices as the file lists them (two vertices at one position stay
two) and its faces whole, and repairs three things, which its log names ("contained: 6 0-length
edges (removed)", "unreferenced vertices ... were removed"):

- an edge no longer than :data:`~shapegen.tolerances.ASSET_EDGE_M` is collapsed into one
  vertex, the one more faces use (the other is left unused), and a corner repeated at once
  (``f 1 2 2 3``) is one corner; a face left with fewer than three corners goes; a face given
  twice stays twice;
- a face with no area (its corners on one line, a sliver modelling tools leave along a seam) is
  removed; one whose spanning edge a face kept shares is merged into that face (its corners
  spliced into the edge, so the face goes round the seam's corners), a fan one after another;
- the vertices no face uses are removed, and the others are numbered in the order the faces
  first use them.

Measured with PyPRT 1.12 on the 25 assets of the corpus packages (each read as an initial shape
through an identity rule): the same vertex and face counts on every one
(``tests/geometry/prt_asset_counts.json``).
"""

from __future__ import annotations

__all__ = ["cleaned_polygons", "cleaned_polygons_and_corners"]

import numpy as np

from shapegen.tolerances import ASSET_EDGE_M


def cleaned_polygons(
    vertices: np.ndarray, faces: list[list[int]], edge: float = ASSET_EDGE_M
) -> tuple[np.ndarray, list[list[int]]]:
    """``(vertices, faces)`` cleaned as CityEngine cleans an asset (see the module).

    ``edge`` is the length (the file's units) at or below which an edge has none.

    >>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 0.0005, 0], [1, 1, 0], [0, 1, 0], [9, 9, 9.0]])
    >>> points, polygons = cleaned_polygons(square, [[0, 1, 2, 3, 4]])
    >>> len(points), polygons
    (4, [[0, 1, 2, 3]])
    """
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    faces, _ = _collapsed(vertices, faces, edge)
    faces, _ = _without_slivers(vertices, faces, edge)
    return _renumbered(vertices, faces)


def cleaned_polygons_and_corners(
    vertices: np.ndarray, faces: list[list[int]], edge: float = ASSET_EDGE_M
) -> tuple[np.ndarray, list[list[int]], list[list[int]]]:
    """As :func:`cleaned_polygons`, with each cleaned face's corners named by the corner of the
    input they are: the number of the corner in the input's faces taken one after another
    (face 0's corners 0..k-1, then face 1's...). What a face corner carries (its texture
    coordinates) follows it so: a collapsed edge keeps the corner that stays, and a sliver's
    corners spliced into a face bring their own.

    >>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 0.0005, 0], [1, 1, 0], [0, 1, 0.0]])
    >>> cleaned_polygons_and_corners(square, [[0, 1, 2, 3, 4]])[1:]
    ([[0, 1, 2, 3]], [[0, 1, 3, 4]])
    """
    vertices = np.asarray(vertices, dtype=float).reshape(-1, 3)
    starts = np.cumsum([0, *(len(face) for face in faces)])
    ids = [list(range(a, a + len(face))) for a, face in zip(starts, faces, strict=False)]
    faces, ids = _collapsed(vertices, faces, edge, ids)
    faces, ids = _without_slivers(vertices, faces, edge, ids)
    vertices, faces = _renumbered(vertices, faces)
    return vertices, faces, ids


def _collapsed(vertices: np.ndarray, faces: list[list[int]], edge: float, ids=None):
    """The faces with every edge no longer than ``edge`` collapsed into one vertex, and
    ``ids`` (per face a value per corner, or None) of the corners kept."""
    if not faces:
        return [], [] if ids is not None else None
    corners = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
    sizes = np.array([len(f) for f in faces])
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    following = np.arange(1, len(corners) + 1)
    following[start + sizes - 1] = start
    lengths = np.linalg.norm(vertices[corners[following]] - vertices[corners], axis=1)
    repeated = corners == corners[following]  # f 1 2 2 3: an edge from a vertex to itself
    short = np.flatnonzero((lengths <= edge) & ~repeated)
    if len(short) == 0 and not repeated.any():
        return [list(map(int, f)) for f in faces], ids
    uses = np.bincount(corners, minlength=len(vertices))
    parent = np.arange(len(vertices))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for k in short:
        a, b = root(int(corners[k])), root(int(corners[following[k]]))
        if a == b:
            continue
        # the vertex more faces use stays (the lower number on a tie)
        keep, drop = (a, b) if (uses[a], -a) >= (uses[b], -b) else (b, a)
        parent[drop] = keep
        uses[keep] += uses[drop]
    kept, kept_ids = [], []
    for n, face in enumerate(faces):
        merged = [root(int(i)) for i in face]
        stays = [k for k, c in enumerate(merged) if c != merged[k - 1]]
        if len({merged[k] for k in stays}) >= 3:
            kept.append([merged[k] for k in stays])
            if ids is not None:
                kept_ids.append([ids[n][_own_corner(face, merged, k)] for k in stays])
    return kept, kept_ids if ids is not None else None


def _own_corner(face: list[int], merged: list[int], first: int) -> int:
    """Of the run of corners from ``first`` that became one vertex, the one that was that
    vertex (else the first): the corner that stays."""
    k = first
    while True:
        if int(face[k]) == merged[k]:
            return k
        k = (k + 1) % len(face)
        if k == first or merged[k] != merged[first]:
            return first


def _without_slivers(vertices: np.ndarray, faces: list[list[int]], edge: float, ids=None):
    """The faces without those of no area. A sliver whose longest edge (the one that spans it)
    a face kept shares, run the other way as between two faces of one consistently turned
    surface, is merged into that face: its other corners are spliced into the edge, and the
    edges so made may take in the next sliver of a fan. A sliver that meets no face kept so is
    dropped. ``ids`` (per face a value per corner, or None) follow the corners."""
    if not faces:
        return faces, ids
    thin = (_thicknesses(vertices, faces) <= edge).tolist()
    if not any(thin):
        return faces, ids
    if ids is None:
        ids = [[None] * len(face) for face in faces]
        named = False
    else:
        named = True
    kept = {k: list(face) for k, face in enumerate(faces) if not thin[k]}
    kept_ids = {k: list(ids[k]) for k in kept}
    owner = {(a, b): k for k, face in kept.items() for a, b in _edges(face)}
    slivers = [(list(face), list(ids[k])) for k, face in enumerate(faces) if thin[k]]
    merged = True
    while merged and slivers:
        merged = False
        for sliver, sliver_ids in list(slivers):
            a, b = _longest_edge(vertices, sliver)
            k = owner.get((b, a))
            if k is None:
                continue
            face = kept[k]
            at = next(i for i in range(len(face)) if (face[i], face[(i + 1) % len(face)]) == (b, a))
            start = sliver.index(b)
            turn = [(start + j) % len(sliver) for j in range(1, len(sliver))]
            turn = turn[: [sliver[j] for j in turn].index(a)]  # from b round to a
            path = [sliver[j] for j in turn]
            face[at + 1 : at + 1] = path
            kept_ids[k][at + 1 : at + 1] = [sliver_ids[j] for j in turn]
            del owner[(b, a)]
            owner.update({pair: k for pair in _edges([b, *path, a])[:-1]})
            slivers.remove((sliver, sliver_ids))
            merged = True
    order = sorted(kept)
    return [kept[k] for k in order], [kept_ids[k] for k in order] if named else None


def _longest_edge(vertices: np.ndarray, face: list[int]) -> tuple[int, int]:
    """The sliver's longest edge: the one that spans it, its other corners lying along it."""
    pairs = _edges(face)
    ends = np.array(pairs)
    lengths = np.linalg.norm(vertices[ends[:, 1]] - vertices[ends[:, 0]], axis=1)
    return pairs[int(np.argmax(lengths))]


def _edges(face: list[int]) -> list[tuple[int, int]]:
    return list(zip(face, face[1:] + face[:1], strict=True))


def _thicknesses(vertices: np.ndarray, faces: list[list[int]]) -> np.ndarray:
    """Each face's width across its longest edge: twice its area (Newell's method) over that
    edge's length (0 for a face whose corners are one point)."""
    corners = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
    sizes = np.array([len(f) for f in faces])
    start = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    following = np.arange(1, len(corners) + 1)
    following[start + sizes - 1] = start
    here, there = vertices[corners], vertices[corners[following]]
    normal = np.add.reduceat(np.cross(here, there), start, axis=0)
    longest = np.maximum.reduceat(np.linalg.norm(there - here, axis=1), start)
    area2 = np.linalg.norm(normal, axis=1)
    return np.divide(area2, longest, out=np.zeros_like(area2), where=longest > 0)


def _renumbered(vertices: np.ndarray, faces: list[list[int]]):
    """The vertices the faces use, numbered in the order the faces first use them."""
    if not faces:
        return vertices[:0], []
    corners = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
    order, first = np.unique(corners, return_index=True)
    used = order[np.argsort(first, kind="stable")]
    number = np.full(len(vertices), -1, dtype=np.int64)
    number[used] = np.arange(len(used))
    return vertices[used], [number[np.asarray(f, dtype=np.int64)].tolist() for f in faces]
