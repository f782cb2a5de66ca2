"""The faces an axis plane crosses, clipped ring by ring (both paths of
:func:`~shapegen.geometry.cut.clip_half`), and the whole clip of a mesh of a few faces in Python
floats (:func:`clip_half_few`): a split's face or box, a trimmed piece, where numpy's cost per
call was most of the clip. The arrays' path and this one take the same steps with the same
arithmetic (tests/geometry/test_cut.py holds them equal)."""

from __future__ import annotations

__all__ = ["FEW_FACES", "clip_half_few", "clipped_faces", "split_at_bridges"]

import math

from shapegen.geometry.mesh import Mesh, corner_layout
from shapegen.geometry.rings import chains_between, joined_chains, without_repeats
from shapegen.model.polygons import face_normals
from shapegen.tolerances import COINCIDENT_REL, SIZE_FLOOR_M


def clipped_faces(
    mesh, clipped, depth, eps, crossing, points, axis, sign, strict, keep_corners=False
):
    """The polygons left of each face in ``clipped`` (face numbers; a list of polygons per
    face), ``points`` the mesh's vertices and then the cut's (rows of 3). A corner within
    ``strict`` of the plane lies on the cut, where a bridge can part the face (a corner kept
    within a larger ``eps`` stays a corner of its face); ``keep_corners`` as
    :func:`split_at_bridges`'."""
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
            # a convex face's one cut edge: the ring begun after it (what split_at_bridges
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
            out[place] = split_at_bridges(ring, flags, points, along, keep_corners)
    return out


FEW_FACES = 16  # meshes with no more faces are clipped in Python floats


def clip_half_few(mesh, axis, value, keep_above, tolerance) -> Mesh | None:
    """:func:`~shapegen.geometry.cut.clip_half` of a mesh of a few faces without holes (a
    split's face or box, a trimmed piece) in Python floats: the same steps and the same
    arithmetic as the arrays' path, without numpy's cost per call, most of a small clip's."""
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
    pieces = clipped_faces(
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
    """cut.py's ``_caps`` in Python: each boundary edge (none runs it the other way) turned
    around, chained into loops, the first begun at the first face's cut."""
    edges = {(a, face[(m + 1) % len(face)]) for face in faces for m, a in enumerate(face)}
    following: dict[int, int] = {}
    for face in faces:
        count = len(face)
        for m in range(count):
            a, b = face[m], face[(m + 1) % count]
            if (b, a) not in edges:
                following[b] = a
    return chained_loops(following)


def chained_loops(following: dict[int, int]) -> list[tuple[int, ...]]:
    """The closed loops of at least 3 corners that ``following`` (corner -> next corner) chains,
    in the order its first corners come (emptied as it is read); an open chain is dropped."""
    loops = []
    while following:
        first = next(iter(following))
        nxt = following.pop(first)
        loop = [first]
        while nxt != first and nxt in following:
            loop.append(nxt)
            nxt = following.pop(nxt)
        if nxt == first and len(loop) >= 3:
            loops.append(tuple(loop))
    return loops


def _compact_few(points: list[list[float]], faces: list[tuple[int, ...]]) -> Mesh | None:
    """cut.py's ``_compact`` in Python: the faces with area, the vertices renumbered in the order
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


def split_at_bridges(ring, flags, points, along, keep_corners=False) -> list[tuple[int, ...]]:
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
