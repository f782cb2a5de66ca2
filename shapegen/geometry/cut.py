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

from itertools import compress

import numpy as np

from shapegen.geometry import clip_faces
from shapegen.geometry.clip_faces import clip_half_few, clipped_faces
from shapegen.geometry.mesh import Mesh, area_vectors, corner_layout
from shapegen.geometry.prism_cut import SPLIT_HEIGHT as _SPLIT_HEIGHT
from shapegen.geometry.prism_cut import prism_decomposition
from shapegen.limits import check_clock
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
    if len(mesh.faces) <= clip_faces.FEW_FACES:  # a face or a box: Python beats arrays
        return clip_half_few(mesh, axis, value, keep_above, tolerance)
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
    pieces = clipped_faces(
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


def clip_slab(mesh: Mesh, axis: int, low: float, high: float) -> Mesh | None:
    """The part of ``mesh`` with ``low <= coordinate[axis] <= high`` (m), or None."""
    piece = clip_half(mesh, axis, low, True)
    if piece is None:
        return None
    return clip_half(piece, axis, high, False)


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
    # a cap begins at the cut of the first face the cut crosses, running it the other way
    # (PyPRT's gambrel roofs: the split's cap of the lower roof, whose gable then rises along
    # the cap's first edge, begins at the cut of the roof's first gable)
    return clip_faces.chained_loops(following)


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
