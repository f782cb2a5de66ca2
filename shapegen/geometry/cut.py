"""Cutting meshes by planes (CityEngine's ``split`` of a shape with geometry).

:func:`clip_half` keeps the part of a mesh on one side of an axis-aligned plane (coordinates are
the shape's scope coordinates, so a split plane is ``coordinate[axis] = value``). Faces are
clipped as polygons (a non-convex face stays one polygon); an intersection point is computed once
per cut edge, so two faces that shared the edge share the new vertex and a closed mesh stays
closed once capped. A closed mesh is capped with the loops of the cut ("hollow meshes are closed
after the cut", op_split); open meshes (faces) are not. Holes in a cap are not represented:
each loop becomes its own face (a mesh whose faces have holes is cut by
:mod:`shapegen.geometry.holed_cut`, whose caps keep them).
"""

from __future__ import annotations

__all__ = [
    "clip_half",
    "clip_plane",
    "clip_slab",
    "NEEDS_CUT",
    "convex_decomposition",
    "placed_convex_decomposition",
]

import math
from itertools import compress

import numpy as np

from shapegen.geometry.mesh import Mesh, area_vectors, corner_layout
from shapegen.geometry.prism_cut import SPLIT_HEIGHT as _SPLIT_HEIGHT
from shapegen.geometry.prism_cut import prism_decomposition
from shapegen.geometry.rings import chains_between, joined_chains, without_repeats
from shapegen.limits import check_clock
from shapegen.model.polygons import face_normals
from shapegen.tolerances import COINCIDENT_REL, DEFAULT, SIZE_FLOOR_M


def clip_half(
    mesh: Mesh, axis: int, value: float, keep_above: bool, tolerance: float | None = None
) -> Mesh | None:
    """The part of ``mesh`` with ``coordinate[axis] >= value`` (``keep_above``) or ``<=``,
    capped if ``mesh`` is closed; None when nothing of positive extent is left. A corner
    within ``tolerance`` (m; by default round-off of the mesh's size) of the plane is on it:
    kept where it is, and no edge is cut there."""
    check_clock()  # a split's pieces, a trim's planes, the convex cut: one clip each
    if mesh.n_faces == 0:
        return None
    if mesh.holes:  # faces with holes: clipped ring by ring (geometry/holed_cut.py)
        from shapegen.geometry.holed_cut import clip_half_with_holes

        return clip_half_with_holes(mesh, axis, value, keep_above)
    if len(mesh.faces) <= _FEW_FACES:  # a face or a box: plain Python is quicker than arrays
        return _clip_half_few(mesh, axis, value, keep_above, tolerance)
    strict = COINCIDENT_REL * max(mesh.size(), SIZE_FLOOR_M)
    eps = strict if tolerance is None else tolerance
    sign = 1.0 if keep_above else -1.0
    vertices = mesh.vertices
    depth = (vertices[:, axis] - value) * sign
    if depth.min() >= -eps:
        return mesh
    if depth.max() <= eps:
        return None
    # Faces wholly in front of the plane stay as they are and faces nowhere in front of it go;
    # only the faces the plane crosses or touches are clipped one by one.
    corners, start = mesh.corner_layout
    heads = start[:-1]
    corner_depth = depth[corners]
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = heads
    repeated = np.logical_or.reduceat(corners == corners[successor], heads)
    whole = (
        (np.minimum.reduceat(corner_depth, heads) > eps)
        & ~repeated
        & ((start[1:] - start[:-1]) >= 3)
    )
    clipped = np.flatnonzero(~whole & (np.maximum.reduceat(corner_depth, heads) > eps))
    # one new vertex per crossed edge, shared by the two faces of the edge
    a, b = corners, corners[successor]
    da, db = corner_depth, corner_depth[successor]
    crossed = ((da > eps) & (db < -eps)) | ((da < -eps) & (db > eps))
    crossed &= np.repeat(~whole, (start[1:] - start[:-1]))
    n = len(vertices)
    low, high = np.minimum(a[crossed], b[crossed]), np.maximum(a[crossed], b[crossed])
    keys, first = np.unique(low * n + high, return_index=True)
    i, j = low[first], high[first]
    t = (depth[i] / (depth[i] - depth[j]))[:, None]
    new_points = vertices[i] + t * (vertices[j] - vertices[i])
    new_points[:, axis] = value
    crossing = dict(zip(keys.tolist(), range(n, n + len(keys)), strict=True))
    points = np.concatenate([vertices, new_points]) if len(keys) else vertices
    # a trim (``tolerance``) keeps a face's corners along the cut, as CityEngine's runtime
    # does (PyPRT's parthenon: the simas' top corners at the ridge's plane)
    pieces = _clipped_faces(
        mesh, clipped.tolist(), depth.tolist(), eps, crossing, points, axis, sign, min(eps, strict),
        tolerance is not None,
    )  # fmt: skip
    whole_flags = whole.tolist()
    faces: list[tuple[int, ...]] = []
    done = 0
    for k, polygons in zip(clipped.tolist(), pieces, strict=True):
        faces.extend(compress(mesh.faces[done:k], whole_flags[done:k]))
        faces.extend(polygons)
        done = k + 1
    faces.extend(compress(mesh.faces[done:], whole_flags[done:]))
    if not faces:
        return None
    if mesh.is_closed:
        faces.extend(_caps(faces, len(points)))
    return _compact(points, faces)


def _clipped_faces(
    mesh, clipped, depth, eps, crossing, points, axis, sign, strict, keep_corners=False
):
    """The polygons left of each face in ``clipped`` (face numbers; a list of polygons per
    face), ``points`` the mesh's vertices and then the cut's (rows of 3). A corner within
    ``strict`` of the plane lies on the cut, where a bridge can part the face (a corner kept
    within a larger ``eps`` stays a corner of its face); ``keep_corners`` as
    :func:`_split_at_bridges`'."""
    n = len(depth)
    out = []
    bridged = []  # (place in out, face, ring, flags): faces left with several edges on the cut
    for k in clipped:
        face = mesh.faces[k]
        ring: list[int] = []
        count = len(face)
        for m in range(count):
            p, q = face[m], face[(m + 1) % count]
            dp, dq = depth[p], depth[q]
            if dp >= -eps:
                ring.append(p)
            if (dp > eps and dq < -eps) or (dp < -eps and dq > eps):
                ring.append(crossing[p * n + q if p < q else q * n + p])
        ring = without_repeats(ring)
        if len(ring) < 3:
            out.append(())
            continue
        flags = [i >= n or abs(depth[i]) <= strict for i in ring]
        size = len(ring)
        on_cut = [e for e in range(size) if flags[e] and flags[(e + 1) % size]]
        if not on_cut:  # the face only touches the cut: kept as it is
            out.append([tuple(ring)])
            continue
        if len(on_cut) == 1 and not all(flags):
            # a convex face's one cut edge: the ring begun after it (what _split_at_bridges
            # makes of it, without the face's normal; a face whose normal is zero has no area
            # and _compact drops it either way)
            start = (on_cut[0] + 1) % size
            out.append([tuple(ring[start:] + ring[:start])])
            continue
        bridged.append((len(out), k, ring, flags))
        out.append(None)
    if bridged:
        # the direction along the cut in which the kept part's boundary runs (interior on the
        # left): t = d x n, d the kept side (sign along axis), n the face normal; the normals
        # of these faces only (Newell's, the same numbers as the whole mesh's)
        cached = mesh.__dict__.get("normals_and_centres")
        if cached is not None:
            normals = cached[0][[k for _, k, _, _ in bridged]]
        else:
            corners, start = corner_layout([mesh.faces[k] for _, k, _, _ in bridged])
            normals = face_normals(mesh.vertices, corners, start)[0]
        for (place, _, ring, flags), normal in zip(bridged, normals.tolist(), strict=True):
            nx, ny, nz = normal
            along = ((0.0, -nz, ny), (nz, 0.0, -nx), (-ny, nx, 0.0))[axis]
            along = tuple(sign * c for c in along)
            out[place] = _split_at_bridges(ring, flags, points, along, keep_corners)
    return out


def clip_slab(mesh: Mesh, axis: int, low: float, high: float) -> Mesh | None:
    """The part of ``mesh`` with ``low <= coordinate[axis] <= high`` (m), or None."""
    piece = clip_half(mesh, axis, low, True)
    if piece is None:
        return None
    return clip_half(piece, axis, high, False)


_FEW_FACES = 16  # meshes with no more faces are clipped in Python floats


def _clip_half_few(mesh, axis, value, keep_above, tolerance) -> Mesh | None:
    """:func:`clip_half` of a mesh of a few faces without holes (a split's face or box, a
    trimmed piece) in Python floats: the same steps and the same arithmetic as the arrays'
    path, without numpy's cost per call, which is most of a small clip's."""
    rows = mesh.vertices.tolist()
    size = mesh.__dict__.get("_size")
    if size is None:
        low = [min(c) for c in zip(*rows, strict=True)]
        high = [max(c) for c in zip(*rows, strict=True)]
        size = math.sqrt(sum((b - a) * (b - a) for a, b in zip(low, high, strict=True)))
    strict = COINCIDENT_REL * max(size, SIZE_FLOOR_M)
    eps = strict if tolerance is None else tolerance
    sign = 1.0 if keep_above else -1.0
    depth = [(r[axis] - value) * sign for r in rows]
    if min(depth) >= -eps:
        return mesh
    if max(depth) <= eps:
        return None
    # as clip_half: faces wholly in front stay, faces nowhere in front go, the rest are
    # clipped; one new vertex per crossed edge, numbered in the order of the edges' keys
    n = len(rows)
    faces = mesh.faces
    whole: list[bool] = []
    clipped: list[int] = []
    keys: set[int] = set()
    for k, face in enumerate(faces):
        count = len(face)
        ds = [depth[i] for i in face]
        repeated = any(face[m] == face[(m + 1) % count] for m in range(count))
        is_whole = min(ds) > eps and not repeated and count >= 3
        whole.append(is_whole)
        if is_whole:
            continue
        if max(ds) > eps:
            clipped.append(k)
        for m in range(count):
            da, db = ds[m], ds[(m + 1) % count]
            if (da > eps and db < -eps) or (da < -eps and db > eps):
                a, b = face[m], face[(m + 1) % count]
                keys.add(a * n + b if a < b else b * n + a)
    crossing = {}
    points = rows  # a new list (tolist): the cut's vertices follow the mesh's
    for key in sorted(keys):
        i, j = divmod(key, n)
        t = depth[i] / (depth[i] - depth[j])
        p, q = rows[i], rows[j]
        point = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])]
        point[axis] = value
        crossing[key] = len(points)
        points.append(point)
    pieces = _clipped_faces(
        mesh, clipped, depth, eps, crossing, points, axis, sign, min(eps, strict),
        tolerance is not None,
    )  # fmt: skip
    out: list[tuple[int, ...]] = []
    done = 0
    for k, polygons in zip(clipped, pieces, strict=True):
        out.extend(f for f, w in zip(faces[done:k], whole[done:k], strict=True) if w)
        out.extend(polygons)
        done = k + 1
    out.extend(f for f, w in zip(faces[done:], whole[done:], strict=True) if w)
    if not out:
        return None
    if _closed_few(mesh):
        out.extend(_caps_few(out))
    return _compact_few(points, out)


def _closed_few(mesh: Mesh) -> bool:
    """:attr:`Mesh.is_closed` of a mesh without holes, worked out in Python and kept as the
    property keeps it (on the faces)."""
    faces = mesh.faces
    kept = faces.__dict__.get("is_closed")
    if kept is None:
        edges = [(a, face[(m + 1) % len(face)]) for face in faces for m, a in enumerate(face)]
        unique = set(edges)
        kept = bool(faces) and len(unique) == len(edges) and all((b, a) in unique for a, b in edges)
        faces.__dict__["is_closed"] = kept
    return kept


def _caps_few(faces: list[tuple[int, ...]]) -> list[tuple[int, ...]]:
    """:func:`_caps` in Python: each boundary edge (none runs it the other way) turned
    around, chained into loops, the first begun at the first face's cut."""
    edges = {(a, face[(m + 1) % len(face)]) for face in faces for m, a in enumerate(face)}
    following: dict[int, int] = {}
    for face in faces:
        count = len(face)
        for m in range(count):
            a, b = face[m], face[(m + 1) % count]
            if (b, a) not in edges:
                following[b] = a
    caps = []
    while following:
        first = next(iter(following))
        nxt = following.pop(first)
        loop = [first]
        while nxt != first and nxt in following:
            loop.append(nxt)
            nxt = following.pop(nxt)
        if nxt == first and len(loop) >= 3:
            caps.append(tuple(loop))
    return caps


def _compact_few(points: list[list[float]], faces: list[tuple[int, ...]]) -> Mesh | None:
    """:func:`_compact` in Python: the faces with area, the vertices renumbered in the order
    the kept faces first use them; None when nothing with extent is left."""
    columns = list(zip(*points, strict=True))
    span = max(max(c) - min(c) for c in columns)
    floor = COINCIDENT_REL * span * span
    kept_faces = []
    for face in faces:
        count = len(face)
        ring = [points[i] for i in face]
        cx = sum(p[0] for p in ring) / count
        cy = sum(p[1] for p in ring) / count
        cz = sum(p[2] for p in ring) / count
        nx = ny = nz = 0.0
        for m in range(count):
            p, q = ring[m], ring[(m + 1) % count]
            px, py, pz = p[0] - cx, p[1] - cy, p[2] - cz
            qx, qy, qz = q[0] - cx, q[1] - cy, q[2] - cz
            nx += py * qz - pz * qy
            ny += pz * qx - px * qz
            nz += px * qy - py * qx
        if 0.5 * math.sqrt(nx * nx + ny * ny + nz * nz) > floor:
            kept_faces.append(face)
    if not kept_faces:
        return None
    number: dict[int, int] = {}
    renumbered = tuple(
        tuple(number.setdefault(i, len(number)) for i in face) for face in kept_faces
    )
    kept = [points[i] for i in number]
    if max(max(c) - min(c) for c in zip(*kept, strict=True)) <= 0:
        return None
    return Mesh.of_valid_faces(kept, renumbered)


def _split_at_bridges(ring, flags, points, along, keep_corners=False) -> list[tuple[int, ...]]:
    """The polygons of a clipped ring: the ring is cut at its edges lying on the cut plane
    (where a non-convex face left several parts joined by zero-width bridges), and the chains
    in between are joined again along the cut in the boundary's direction ``along``.
    ``keep_corners``: a ring the cut does not part keeps its corners along the cut."""
    n = len(ring)
    if all(flags):  # a face lying on the cut: the cap replaces it
        return []
    on_edges = [flags[k] and flags[(k + 1) % n] for k in range(n)]
    if not any(on_edges) or not any(along):
        return [tuple(ring)] if len(ring) >= 3 else []
    chains = chains_between(ring, on_edges)
    if not chains:
        return []
    if len(chains) == 1 and keep_corners:  # no bridge: the face as it is, every corner kept
        return [tuple(ring)] if len(ring) >= 3 else []
    ax, ay, az = along
    position = {}
    for c in chains:
        for i in (c[0], c[-1]):
            x, y, z = points[i]
            position[i] = x * ax + y * ay + z * az
    return joined_chains(chains, position)


def _caps(faces: list[tuple[int, ...]], count: int) -> list[tuple[int, ...]]:
    """Faces closing the boundary loops of a clipped closed mesh (each boundary edge turned
    around, chained into loops); ``count`` vertices."""
    corners, start = corner_layout(faces)
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = start[:-1]
    edges = corners * count + corners[successor]
    reverse = np.sort(corners[successor] * count + corners)
    found = np.searchsorted(reverse, edges)
    found[found == len(reverse)] = 0
    boundary = reverse[found] != edges  # no face runs this edge the other way
    following: dict[int, int] = dict(
        zip(corners[successor][boundary].tolist(), corners[boundary].tolist(), strict=True)
    )  # the cap runs each boundary edge the other way
    caps = []
    while following:
        # a cap begins at the cut of the first face the cut crosses, running it the other way
        # (PyPRT's gambrel roofs: the split's cap of the lower roof, whose gable then rises
        # along the cap's first edge, begins at the cut of the roof's first gable)
        first = next(iter(following))
        nxt = following.pop(first)
        loop = [first]
        while nxt != first and nxt in following:
            loop.append(nxt)
            nxt = following.pop(nxt)
        if nxt == first and len(loop) >= 3:
            caps.append(tuple(loop))
    return caps


def _compact(vertices: np.ndarray, faces: list[tuple[int, ...]]) -> Mesh | None:
    """The mesh of the faces with area (a bridge left along an earlier cut has none), or None."""
    span = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    corners, start = corner_layout(faces)
    area = 0.5 * np.linalg.norm(area_vectors(vertices, corners, start), axis=1)
    keep = area > COINCIDENT_REL * span * span
    if not keep.any():
        return None
    counts = (start[1:] - start[:-1])[keep]
    corners = corners[np.repeat(keep, (start[1:] - start[:-1]))]
    # vertices renumbered in the order the kept faces first use them
    used, first = np.unique(corners, return_index=True)
    order = used[np.argsort(first, kind="stable")]
    number = np.empty(len(vertices), dtype=np.intp)
    number[order] = np.arange(len(order))
    corners = number[corners]
    start = np.zeros(len(counts) + 1, dtype=np.intp)
    np.cumsum(counts, out=start[1:])
    flat = corners.tolist()
    faces = tuple(
        tuple(flat[a:b]) for a, b in zip(start[:-1].tolist(), start[1:].tolist(), strict=True)
    )
    kept = vertices[order]
    if float(np.ptp(kept, axis=0).max()) <= 0:
        return None
    return Mesh.of_valid_faces(kept, faces, (corners, start))


def clip_plane(
    mesh: Mesh, normal, offset: float, keep_above: bool, tolerance: float | None = None
) -> Mesh | None:
    """The part of ``mesh`` with ``normal . p >= offset`` (``keep_above``) or ``<=``; ``normal``
    a unit vector (``tolerance`` as :func:`clip_half`'s). The mesh is turned so that
    ``normal`` is its y axis, clipped, turned back."""
    frame = _frame_of(normal)
    piece = clip_half(_turned(mesh, frame), 1, offset, keep_above, tolerance)
    return _turned_back(piece, frame)


def _frame_of(normal) -> np.ndarray:
    """A rotation whose y axis (second column) is the unit vector ``normal``."""
    from shapegen.geometry.scope_frames import rotation_keeping_x

    normal = np.asarray(normal, float)
    guess = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    return rotation_keeping_x(guess, normal)  # y along the normal


def _turned(mesh: Mesh, frame: np.ndarray) -> Mesh:
    turned = Mesh.of_valid_faces(
        mesh.vertices @ frame, mesh.faces, mesh.corner_layout, holes=mesh.holes
    )  # the holes too: a trim plane cuts a face with holes (clip_half_with_holes)
    if "is_closed" in mesh.__dict__:
        turned.__dict__["is_closed"] = mesh.is_closed  # a rotation keeps the topology
    return turned


def _turned_back(piece: Mesh | None, frame: np.ndarray) -> Mesh | None:
    return None if piece is None else _turned(piece, frame.T)


def convex_decomposition(
    mesh: Mesh, max_pieces: int = 64, *, cleaned: bool = False
) -> list[Mesh] | None:
    """Convex closed pieces whose union is the closed mesh ``mesh``: a non-convex piece is cut by
    the plane of one of its faces that has corners in front of it, until every piece is convex
    (the pieces share the cut planes as faces). None when it would take more than
    ``max_pieces`` pieces or a cut fails to close.

    A right prism (an extruded footprint) is cut on its footprint by
    :func:`~shapegen.geometry.prism_cut.prism_decomposition`, which gives these pieces at a
    fraction of the cost; anything else, and any prism it is not sure of, is cut here.
    ``cleaned``: the pieces :meth:`~Mesh.cleaned` (a prism's pieces are made so)."""
    pieces = prism_decomposition(mesh, max_pieces)
    if pieces is not None:
        return _without_slivers(pieces, mesh)
    pieces = _general_decomposition(mesh, max_pieces)
    if pieces is not None and cleaned:
        pieces = [piece.cleaned() for piece in pieces]
    return _without_slivers(pieces, mesh)


def _without_slivers(pieces: list[Mesh] | None, mesh: Mesh) -> list[Mesh] | None:
    """The pieces but the slivers, None when nothing else is left.

    A cut along the plane of one of two faces that meet at corners nearly in line (a window's
    frame whose diamond opening bends 4e-6 of its size at each side's middle) leaves between
    that plane and the other face a wedge as long as the face and only as thick as the bend:
    a sliver. Its weight is nothing the model can tell, and no block is judged from it: it
    passed the leaf's own volume floor and then failed the model's (the parthenon's window
    frames, 1.1e-8 m^3 against 5.6e-7 m^3 for an 82 m model). A piece is a sliver when its
    mean thickness, its volume over its size squared, is below the convexity tolerance of
    the whole mesh (``convex_rel`` times its size: the height within which a corner counts as
    on a face's plane), or when its volume is below ``volume_rel`` times the mesh's size
    cubed. A needle or a thin plate is far thicker than that, and stays."""
    if not pieces or len(pieces) == 1:
        return pieces
    size = mesh.size()
    floor = DEFAULT.volume_rel * size**3
    thin = DEFAULT.convex_rel * size
    kept = [
        piece
        for piece in pieces
        if (volume := piece.signed_volume()) > floor and volume > thin * piece.size() ** 2
    ]
    return kept or None


def _general_decomposition(mesh: Mesh, max_pieces: int) -> list[Mesh] | None:
    done: list[Mesh] = []
    todo = [mesh]
    while todo:
        check_clock()
        piece = todo.pop()
        slack = COINCIDENT_REL * max(piece.size(), SIZE_FLOOR_M)
        heights = piece.heights_above_faces()
        if heights.max(initial=0.0) <= slack:  # convex: Mesh.is_convex's test
            done.append(piece)
            if len(done) > max_pieces:
                return None
            continue
        planes = _splitting_planes(piece, heights, slack)
        if not planes and heights.max() <= _SPLIT_HEIGHT * slack:
            # convex but for round-off (an asset's nearly coplanar faces): no face plane
            # can split it, and a block takes it as convex
            done.append(piece)
            if len(done) > max_pieces:
                return None
            continue
        # the first plane whose halves close: a cut that leaves a sliver whose faces are too
        # small to keep (a notch between corners nearly in line) gives way to the next plane
        halves = next(filter(None, (_halves(piece, plane) for plane in planes)), None)
        if halves is None:
            return None
        todo.extend(halves)
        if len(done) + len(todo) > max_pieces:
            return None
    return done


def placed_convex_decomposition(mesh: Mesh, rotation, origin, *, cut: bool = True):
    """:func:`convex_decomposition` of ``mesh`` (scope coordinates), the pieces moved by
    ``rotation`` and ``origin`` into world coordinates.

    ``cut=False`` asks only for a mesh that needs no cut: a mesh with a corner clearly in front
    of one of its faces' planes (beyond the round-off a cut takes as convex) gives
    :data:`NEEDS_CUT`, uncut, and costs no more than that test. A derivation keeps such leaves
    as derived, and the statics cut them when they judge (the answer is kept all the same).

    The pieces are kept (a bounded cache) for the mesh brought to unit size: its lowest corner
    at the origin and its largest extent 1 (keyed by its coordinates to 1e-12). A rule inserts
    the same asset in many places and at many sizes (a temple's columns, which a change of
    their diameter scales as a whole), and a rebuild (a search, the design page) derives the
    same leaves again, so each distinct shape is cut once. The decomposition does not depend
    on the mesh's position or size: its cuts are the planes of its faces and its tolerances
    are relative to its size, so the pieces of the unit mesh, scaled back, are those of the
    mesh up to round-off. A convex mesh is its own one piece; the pieces are
    :meth:`~Mesh.cleaned`."""
    vertices = np.asarray(mesh.vertices, dtype=float)
    if len(vertices) == 0:
        return None
    low = vertices.min(axis=0)
    scale = float(np.ptp(vertices, axis=0).max())
    if not scale > 0:
        return None
    unit = (vertices - low) / scale
    key = (np.round(unit, 12).tobytes(), mesh.faces)  # equal sizes up to round-off: one key
    # (whether it needs a cut, its pieces or NEEDS_CUT while nobody asked for them): the
    # answer to cut=False is the same whether or not the pieces were made before
    needs_cut, pieces = _DECOMPOSED.get(key, (None, _MISSING))
    if pieces is _MISSING or (pieces is NEEDS_CUT and cut):
        unit_mesh = Mesh.of_valid_faces(unit, mesh.faces)
        if needs_cut is None:
            needs_cut = _clearly_not_convex(unit_mesh)
        if needs_cut and not cut:
            pieces = NEEDS_CUT
        else:
            pieces = convex_decomposition(unit_mesh, cleaned=True)
        if len(_DECOMPOSED) >= _DECOMPOSED_LIMIT:
            del _DECOMPOSED[next(iter(_DECOMPOSED))]  # the oldest entry
        _DECOMPOSED[key] = (needs_cut, pieces)
    if needs_cut and not cut:
        return NEEDS_CUT
    if pieces is None:
        return None
    rotation = np.asarray(rotation, float)
    (a, b, c), (d, e, f), (g, h, i) = rotation.tolist()
    if a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) < 0:
        # a mirror: transformed turns the faces around
        return [
            Mesh(piece.vertices * scale + low, piece.faces).transformed(rotation, origin)
            for piece in pieces
        ]
    # as transformed moves them, without checking the pieces' faces again
    turn, shift = rotation.T, np.asarray(origin, float)
    return [
        Mesh.of_valid_faces((piece.vertices * scale + low) @ turn + shift, piece.faces)
        for piece in pieces
    ]


def _clearly_not_convex(mesh: Mesh) -> bool:
    """True when :func:`convex_decomposition` would cut ``mesh`` (or find it cannot): a corner
    lies in front of a face's plane by more than the height a cut plane needs."""
    if not mesh.is_closed:
        return False
    slack = _SPLIT_HEIGHT * COINCIDENT_REL * max(mesh.size(), SIZE_FLOOR_M)
    return bool(mesh.heights_above_faces(slack).max(initial=0.0) > slack)


class _NeedsCut:
    def __repr__(self) -> str:
        return "NEEDS_CUT"


NEEDS_CUT = _NeedsCut()
""":func:`placed_convex_decomposition`'s answer, asked not to cut, for a mesh that needs a cut."""

_DECOMPOSED: dict = {}
_DECOMPOSED_LIMIT = 512  # distinct meshes kept by placed_convex_decomposition
_MISSING = object()


def _splitting_planes(mesh: Mesh, heights: np.ndarray, slack: float) -> list:
    """The planes of the faces with corners both in front of and behind them (a reflex face's
    plane), as ``(normal, offset)``: most corners in front first, ties in face order;
    ``heights`` are :meth:`Mesh.heights_above_faces`, ``slack`` the mesh's round-off (m)."""
    normals, centres = mesh.normals_and_centres
    ahead = (heights > slack * _SPLIT_HEIGHT).sum(axis=1)
    behind = (heights < -slack * _SPLIT_HEIGHT).sum(axis=1)
    usable = np.flatnonzero((ahead > 0) & (behind > 0) & normals.any(axis=1))
    order = usable[np.argsort(-ahead[usable], kind="stable")]
    return [(normals[k], float(centres[k] @ normals[k])) for k in order.tolist()]


def _halves(piece: Mesh, plane) -> list[Mesh] | None:
    """The two closed halves of ``piece`` on either side of ``plane``, or None."""
    normal, offset = plane
    frame = _frame_of(normal)
    turned = _turned(piece, frame)
    halves = [_turned_back(clip_half(turned, 1, offset, side), frame) for side in (False, True)]
    if any(h is None or not h.is_closed for h in halves):
        return None
    return halves
