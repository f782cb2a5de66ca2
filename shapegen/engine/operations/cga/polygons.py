"""CityEngine's polygon operations on faces: setback, setbackPerEdge, setbackToArea, shapeL,
shapeU, shapeO, innerRectangle and footprint (offset: :mod:`.offset`), and what they share.

Each acts on every face of a flat shape (the lot, a ``comp(f)`` face, an earlier result; offset
also on a 3D shape's faces): the face is laid in its own plane (x along the scope's in-plane
axis, counter-clockwise seen from its normal), the 2D work is done by
:mod:`shapegen.geometry.polygon2d`, and the pieces come back as shapes whose scope keeps the
orientation and fits the new geometry ("the scope's size is adapted to the new geometry").
Edge selectors are ``comp(f)``'s (:func:`shapegen.geometry.queries.face_matches`) applied to
each edge's outward normal in the face's plane: ``front`` +z, ``back`` -z, ``right`` +x,
``left`` -x, ``side``, ``world.*``...; a number selects that edge (modulo the count).

``offset(d)`` without a selector keeps both the inside and the border faces in one shape, with
the vertices they share welded, so ``comp(f) { inside : ... | border : ... }`` tells them apart
by adjacency (border faces have an edge no other face has).
"""

from __future__ import annotations

__all__ = [
    "FaceFrame",
    "face_frames",
    "edge_normals",
    "edge_quadrants",
    "flat_shape",
]

from dataclasses import dataclass

import numpy as np

from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.cga import compiles, warn_at
from shapegen.engine.operations.cga.arguments import number, plain_arguments, selector_name
from shapegen.engine.operations.cga.setback_tags import (
    SetbackLines,
    edge_component,
    tag_selector,
)
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.engine.shapes.tags import Pending
from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d
from shapegen.geometry.frames import quadrant
from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.geometry.queries import FACE_SELECTORS, face_matches
from shapegen.geometry.setback_pieces import setback_pieces
from shapegen.grammar import ast
from shapegen.limits import check_clock
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL, ROUNDOFF_REL

# Edge selectors are comp(f)'s, applied to each edge's outward normal in the face's plane
# (op_setback: "classifying their directions into the corresponding scope quadrants").
_EDGE_SELECTORS = frozenset(FACE_SELECTORS) - {"border", "inside"}


@dataclass(frozen=True)
class FaceFrame:
    """A face's plane in its shape's scope coordinates: ``point = u a + v b + (h0 + h) n``."""

    a: np.ndarray
    b: np.ndarray
    n: np.ndarray
    h0: float

    def lift(self, points2d: np.ndarray, height=0.0) -> np.ndarray:
        """``(k, 2)`` plane points (and heights along n, m) to ``(k, 3)`` scope coordinates."""
        p = np.asarray(points2d, float)
        h = self.h0 + np.broadcast_to(np.asarray(height, float), (len(p),))
        return np.outer(p[:, 0], self.a) + np.outer(p[:, 1], self.b) + np.outer(h, self.n)


def face_frames(shape: Shape) -> list[tuple[FaceFrame, np.ndarray]]:
    """Each face of a flat shape as its frame and its counter-clockwise ``(k, 2)`` polygon."""
    mesh = shape.mesh()
    axis = shape.normal_axis
    guess = np.eye(3)[1 if axis == 0 else 0]  # the scope axis that runs along the face
    out = []
    for k in range(mesh.n_faces):
        check_clock()
        points = mesh.face_points(k)
        normal = polygon_normal(points)
        length = float(np.linalg.norm(normal))
        if length <= 0:
            continue
        n = normal / length
        a = guess - n * float(guess @ n)
        if np.linalg.norm(a) < COINCIDENT_M:
            a = points[1] - points[0]
            a = a - n * float(a @ n)
        a = a / np.linalg.norm(a)
        b = np.cross(n, a)
        polygon = polygon2d.counter_clockwise(np.column_stack([points @ a, points @ b]))
        if len(polygon) >= 3:
            out.append((FaceFrame(a, b, n, float(points[0] @ n)), polygon))
    return out


def edge_normals(frame: FaceFrame, polygon: np.ndarray) -> np.ndarray:
    """``(n, 3)`` outward unit normals of the edges in the face's plane, scope coordinates."""
    m = polygon2d.edge_normals(polygon)
    return np.outer(m[:, 0], frame.a) + np.outer(m[:, 1], frame.b)


def edge_quadrants(frame: FaceFrame, polygon: np.ndarray) -> list[str]:
    """``front back left right top bottom`` of each edge's outward normal in scope axes."""
    return [quadrant(n) for n in edge_normals(frame, polygon)]


def face_holes(shape: Shape) -> list[list[np.ndarray]]:
    """The holes of each face of :func:`face_frames` (in its order), each clockwise ``(k, 2)``
    in the face's plane; empty lists for a shape without holes."""
    mesh = shape.mesh()
    frames = face_frames(shape)
    if not mesh.holes:
        return [[] for _ in frames]
    out = []
    for k in range(mesh.n_faces):
        if float(np.linalg.norm(polygon_normal(mesh.face_points(k)))) <= 0:
            continue  # as face_frames skips it
        frame = frames[len(out)][0]
        rings = []
        for ring in mesh.holes[k]:
            points = mesh.vertices[list(ring)]
            flat = np.column_stack([points @ frame.a, points @ frame.b])
            rings.append(flat if polygon2d.signed_area(flat) < 0 else flat[::-1])
        out.append(rings)
    return out


def _welded(points: np.ndarray, counts: list[int]):
    """One vertex per distinct point (within round-off of the size), so that faces sharing an
    edge share its vertices: ``comp(f)``'s ``inside`` / ``border`` read that adjacency."""
    eps = COINCIDENT_REL * max(1.0, float(np.ptp(points, axis=0).max()))
    keys = np.round(points / eps).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep the vertices in the order they first appear
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    index = rank[inverse.reshape(-1)]
    faces, start = [], 0
    for count in counts:
        face: list[int] = []
        for k in index[start : start + count]:
            if not face or face[-1] != k:
                face.append(int(k))
        if len(face) > 1 and face[0] == face[-1]:
            face.pop()
        faces.append(tuple(face))
        start += count
    return points[np.sort(first)], faces


def flat_shape(parent: Shape, faces: list[np.ndarray], kind: str = FACE, holes=None) -> Shape:
    """A flat shape made of ``faces`` (``(k, 3)`` in ``parent``'s scope coordinates): the
    parent's orientation, the scope fitted to the faces. ``holes``: for each face, its hole
    rings ``(k, 3)`` (or None for none)."""
    if not any(len(face) for face in faces):
        raise GeometryError("it makes no face")
    if holes is not None and any(holes):
        return _flat_shape_with_holes(parent, faces, kind, holes)
    points = np.concatenate(faces)
    low, high = points.min(axis=0), points.max(axis=0)
    size = high - low
    size[size < ROUNDOFF_REL * max(1.0, float(np.abs(points).max()))] = 0.0
    scope = Scope(parent.scope.to_world(low), parent.scope.rotation, size)
    vertices, indexed = _welded(points - low, [len(f) for f in faces])
    if any(len(face) < 2 for face in indexed):  # welded into a point (a 1e-320 m face)
        raise GeometryError("a face it makes has no extent (its corners are one point)")
    return Shape(scope, kind, parent.normal_axis, None, Mesh(vertices, indexed))


def _flat_shape_with_holes(parent: Shape, faces, kind: str, holes) -> Shape:
    """:func:`flat_shape` of faces with holes: the rings welded together, the holes' after
    the faces'."""
    rings = list(faces) + [ring for face_holes in holes for ring in face_holes]
    points = np.concatenate(rings)
    low, high = points.min(axis=0), points.max(axis=0)
    size = high - low
    size[size < ROUNDOFF_REL * max(1.0, float(np.abs(points).max()))] = 0.0
    scope = Scope(parent.scope.to_world(low), parent.scope.rotation, size)
    vertices, indexed = _welded(points - low, [len(r) for r in rings])
    if any(len(ring) < 3 for ring in indexed):
        raise GeometryError("a face it makes has no extent (its corners are in a line)")
    out_faces, rest = indexed[: len(faces)], iter(indexed[len(faces) :])
    out_holes = [tuple(next(rest) for _ in face_holes) for face_holes in holes]
    return Shape(scope, kind, parent.normal_axis, None, Mesh(vertices, out_faces, out_holes))


def flat_faces(state, node, program, what: str) -> list[tuple[FaceFrame, np.ndarray]]:
    """The faces of ``state``'s shape (see :func:`face_frames`), which must be flat."""
    shape = state.shape
    if shape.kind in ("edge", "vertex"):  # CityEngine: a CGA error, the shape carries on
        raise program.operation_error(
            node, f"{what}: the shape has no faces (an edge or a vertex of comp())"
        )
    if shape.kind == MASS and program.cga_dialect:
        # each face of the geometry, in its own plane: op_envelope builds "above each face of
        # the current shape's geometry", op_setback and op_innerRectangle apply "to shapes
        # with more than one face", op_taper takes the first
        return face_frames(shape)
    if shape.kind != FACE:
        raise program.error(node, f"{what} needs a flat shape (the lot or a comp(f) face)")
    return face_frames(shape)


def _branches(program, node, params, allowed: set[str], edges: bool):
    """``(selector, body, merge, branch)`` for each branch: a name or an edge index."""
    from shapegen.grammar import expressions as ex

    out = []
    for branch in node.branches:
        name = selector_name(branch.key)
        if name is None and isinstance(branch.key, ex.Number) and edges:
            selector: str | int = int(branch.key.value)
        elif name in allowed or (edges and name in _EDGE_SELECTORS):
            selector = name
        elif edges and (tagged := tag_selector(program, branch.key, params)) is not None:
            selector = tagged
        else:
            choices = sorted(allowed | (set(_EDGE_SELECTORS) if edges else set()))
            raise program.error(
                branch,
                f"{node.name}() has no selector {name or 'of this form'}; "
                f"shapegen knows {', '.join(choices)} and edge indices"
                if edges
                else f"{node.name}() selects {' or '.join(sorted(allowed))}, not {name}",
            )
        out.append((selector, program.body(branch.body, params), branch.merge, branch))
    return out


# -- setbacks -------------------------------------------------------------------------------


def _edge_selected(selector, normals, index: int, count: int, where) -> bool:
    """Whether edge ``index`` with ``normals`` (scope, world, object) matches ``selector``
    (``where``: state, face frame, polygon, arguments, for a selector written with isTagged)."""
    if isinstance(selector, int):
        return index == selector % count
    if callable(selector):
        state, frame, polygon, args = where
        return selector(edge_component(state.shape, frame, polygon, index, normals), state, args)
    return face_matches(selector, *normals, True)


def _setback_operation(program, node, branches, distances_of, shape_selector: bool):
    """The closure of setback-like operations. ``distances_of(args, state, frame, polygon,
    quadrants, selected, first)`` gives each edge's distance (``first``: the index of the
    face's first edge among the shape's face edges, each face's outline and then its holes)."""

    def setback_op(state, args, out):
        strips: dict[object, list[list]] = {}  # selector -> groups of faces
        remainder: list[list] = []
        lines = SetbackLines()
        frames = flat_faces(state, node, program, f"{node.name}()")
        holes = face_holes(state.shape)  # in the order of the frames
        selectors = [s for s, _, _, _ in branches if s not in ("remainder", "shape")]
        first = 0
        for (frame, polygon), rings in zip(frames, holes, strict=True):
            n = len(polygon)
            scope_normals = edge_normals(frame, polygon)
            quadrants = [quadrant(v) for v in scope_normals]
            world = scope_normals @ state.shape.scope.rotation.T
            rotation = getattr(state.run, "object_rotation", None)
            objects = world if rotation is None else world @ rotation
            owner: list[object] = [None] * n  # the first selector that takes each edge
            where = (state, frame, polygon, args)
            for selector in selectors:
                for k in range(n):
                    normals = (scope_normals[k], world[k], objects[k])

                    if owner[k] is None and _edge_selected(selector, normals, k, n, where):
                        owner[k] = selector
            selected = np.array([o is not None for o in owner]) if not shape_selector else None
            distances = distances_of(args, state, frame, polygon, quadrants, selected, first)
            first += n + sum(len(ring) for ring in rings)
            lines.add(state.shape.scope, frame, polygon, distances)
            if shape_selector:
                try:
                    result = polygon2d.setback(polygon, distances)
                except GeometryError as exc:
                    raise program.operation_error(node, f"{node.name}(): {exc}") from None
                shape_pieces = [piece for _, piece in result.strips]
                if shape_pieces:
                    strips.setdefault("shape", []).extend(_joined(frame, shape_pieces))
                remainder += [[frame.lift(p)] for p in result.remainder]
                continue
            # each branch's edges in the order the branches are written: the first takes
            # the corners it shares with a later one (tests/data/prt_setback.json)
            groups = [[k for k in range(n) if owner[k] == sel] for sel in selectors]
            try:
                pieces = setback_pieces(polygon, rings, distances, groups)
            except GeometryError as exc:
                raise program.operation_error(node, f"{node.name}(): {exc}") from None
            for selector, group in zip(selectors, pieces.groups, strict=True):
                for outer, inner in group:
                    lifted = (frame.lift(outer), [frame.lift(h) for h in inner])
                    strips.setdefault(selector, []).append([lifted])
            remainder += [
                [(frame.lift(outer), [frame.lift(h) for h in inner])]
                for outer, inner in pieces.remainder
            ]

        def pieces_of(selector):
            return remainder if selector == "remainder" else strips.get(selector, [])

        _emit_all(state, args, branches, pieces_of, out, lines)
        return True

    return setback_op


def _joined(frame: FaceFrame, pieces: list[np.ndarray]) -> list[list[np.ndarray]]:
    """The union of strips as face groups: one polygon per piece, or (a ring, which a face
    without holes cannot hold) the strips together as one shape."""
    merged = polygon2d.union(pieces)
    if abs(sum(map(polygon2d.signed_area, merged)) - sum(map(polygon2d.signed_area, pieces))) > (
        COINCIDENT_REL * sum(map(polygon2d.signed_area, pieces))
    ):
        return [[frame.lift(p) for p in pieces]]
    return [[frame.lift(p)] for p in merged]


def _emit_all(state, args, branches, pieces_of, out, lines=None) -> None:
    """Give each branch its face groups: ``:`` one shape per group, ``=`` one for all;
    ``lines`` (a :class:`SetbackLines`) gives the pieces the setback's auto-tags."""
    run = state.run
    parent = state.shape
    for selector, body, merge, branch in branches:
        pieces = pieces_of(selector)
        if not pieces:
            continue
        groups = [[face for group in pieces for face in group]] if merge else pieces
        for index, group in enumerate(groups):
            piece = _face_shape(parent, group)
            if lines is not None and run.tags:
                piece = piece.with_tags(Pending(parent, lines.rule(selector == "remainder")))
            child = run.child(state, piece, branch)
            child.comp_index = index
            child.comp_total = len(groups)
            if body(child, args, out) and child.is_leaf():
                out.append((child, None, ()))


def _face_shape(parent: Shape, group: list) -> Shape:
    """:func:`flat_shape` of a group of faces, each ``(k, 3)`` or ``(outer, holes)``."""
    if all(isinstance(face, np.ndarray) for face in group):
        return flat_shape(parent, group)
    faces = [face if isinstance(face, np.ndarray) else face[0] for face in group]
    holes = [[] if isinstance(face, np.ndarray) else list(face[1]) for face in group]
    return flat_shape(parent, faces, FACE, holes)


def array_elements(value):
    """The elements of a CGA array (or a Python sequence), or None for a single value."""
    from shapegen.engine.expressions.arrays import Array

    if isinstance(value, Array):
        return value.values
    return value if isinstance(value, (list, tuple)) else None


def _distance_list(program, node, value, n: int, first: int = 0) -> np.ndarray:
    """The distances of the ``n`` edges from face edge ``first`` on: a number for each, or
    an array in face-edge order (op_setback), missing values 0."""
    if array_elements(value) is not None:
        value = array_elements(value)
        d = np.zeros(n)
        for k, item in enumerate(value[first : first + n]):
            if type(item) is bool or not isinstance(item, (int, float)):
                raise program.error(node, f"setback distances must be numbers, got {item!r}")
            d[k] = float(item)
        return d
    if type(value) is bool or not isinstance(value, (int, float)):
        raise program.error(node, f"a setback distance must be a number, got {type_name(value)}")
    return np.full(n, float(value))


def _warn_array_size(state, node, value) -> None:
    """CityEngine's runtime warns when an array of distances does not have one value per face
    edge (the holes' edges counted; PyPRT, tests/data/prt_setback.json) and carries on."""
    values = array_elements(value)
    if values is None:
        return
    mesh = state.shape.mesh()
    edges = sum(map(len, mesh.faces)) + sum(len(r) for rings in mesh.holes for r in rings)
    if len(values) < edges:
        warn_at(state, node, f"{node.name}(): Provided array size smaller than face edge "
                "count, using default value (0).")  # fmt: skip
    elif len(values) > edges:
        warn_at(state, node, f"{node.name}(): Provided array size larger than face edge "
                "count, ignoring some values.")  # fmt: skip


@compiles("setback", "setbackPerEdge")
def compile_setback(program, node: ast.Operation, params):
    """``setback(distance | distances) { selector : ... | remainder : ... }``; setbackPerEdge
    evaluates its distance once per edge (with ``comp.index`` the edge's index)."""
    values = plain_arguments(program, node, range(1, 2), block=True)
    branches = _branches(program, node, params, {"remainder"}, edges=True)
    distance = program.expressions.compile(values[0], params)
    per_edge = node.name == "setbackPerEdge"

    def distances_of(args, state, frame, polygon, quadrants, selected, first):
        n = len(polygon)
        if per_edge:
            saved = state.comp_index, state.comp_total
            d = np.zeros(n)
            try:
                for k in range(n):
                    state.comp_index, state.comp_total = k, n
                    d[k] = _distance_list(program, node, distance(args, state), 1)[0]
            finally:
                state.comp_index, state.comp_total = saved
        else:
            value = distance(args, state)
            if first == 0:
                _warn_array_size(state, node, value)
            d = _distance_list(program, node, value, n, first)
        if np.any(d < 0):
            if not program.cga_dialect:
                raise program.error(
                    node, f"{node.name}() distances must be >= 0, got {d.min():g}"
                )  # fmt: skip
            # CityEngine's runtime takes a negative distance as 0, and records nothing (PyPRT)
            warn_at(state, node, f"{node.name}(): a negative distance is taken as 0, as "
                    "CityEngine does")  # fmt: skip
            d = np.maximum(d, 0.0)
        return np.where(selected, d, 0.0)

    return _setback_operation(program, node, branches, distances_of, shape_selector=False)


@compiles("setbackToArea")
def compile_setback_to_area(program, node: ast.Operation, params):
    """``setbackToArea(area[, minDistances[, maxDistances]]) { selector : ... }``."""
    values = plain_arguments(program, node, range(1, 4), block=True)
    branches = _branches(program, node, params, {"remainder"}, edges=True)
    area = number(program, node, values[0], params, "the area")
    bounds = [program.expressions.compile(v, params) for v in values[1:]]

    def distances_of(args, state, frame, polygon, quadrants, selected, first):
        n = len(polygon)
        limits = [_distance_list(program, node, b(args, state), n, first) for b in bounds]
        try:
            _, d = polygon2d.setback_to_area(polygon, area(args, state), selected, *limits)
        except GeometryError as exc:
            raise program.operation_error(node, str(exc)) from None
        return d

    return _setback_operation(program, node, branches, distances_of, shape_selector=False)


_LUO = {"shapeL": ("front", "left"), "shapeU": ("front", "right", "left"),
        "shapeO": ("front", "right", "back", "left")}  # fmt: skip


@compiles("shapeL", "shapeU", "shapeO")
def compile_shape_luo(program, node: ast.Operation, params):
    """``shapeL(front, left)``, ``shapeU(front, right, left)``, ``shapeO(front, right, back,
    left) { shape : ... | remainder : ... }``: a setback of those sides, the strips as one
    polygon."""
    sides = _LUO[node.name]
    values = plain_arguments(program, node, (len(sides),), block=True)
    widths = [number(program, node, v, params, "a width") for v in values]
    branches = _branches(program, node, params, {"shape", "remainder"}, edges=False)

    def distances_of(args, state, frame, polygon, quadrants, selected, first):
        by_side = {side: w(args, state) for side, w in zip(sides, widths, strict=True)}
        if any(v < 0 for v in by_side.values()):
            if not program.cga_dialect:
                raise program.error(node, f"{node.name}() widths must be >= 0")
            # CityEngine's runtime takes a negative width as 0, and records nothing (PyPRT)
            warn_at(
                state, node, f"{node.name}(): a negative width is taken as 0, as CityEngine does"
            )
            by_side = {side: max(v, 0.0) for side, v in by_side.items()}
        return np.array([by_side.get(q, 0.0) for q in quadrants])

    return _setback_operation(program, node, branches, distances_of, shape_selector=True)


@compiles("innerRectangle", "innerRect")
def compile_inner_rectangle(program, node: ast.Operation, params):
    """``innerRectangle(scope|edge) { shape : ... | remainder : ... }``."""
    values = plain_arguments(
        program, node, range(0 if node.name == "innerRect" else 1, 2), block=True
    )
    alignment = selector_name(values[0]) if values else "scope"
    if alignment not in ("scope", "edge"):
        raise program.error(node, f"{node.name}()'s alignment is scope or edge")
    branches = _branches(program, node, params, {"shape", "remainder"}, edges=False)

    def inner_op(state, args, out):
        pieces: dict[str, list[np.ndarray]] = {"shape": [], "remainder": []}
        for frame, polygon in flat_faces(state, node, program, f"{node.name}()"):
            rectangle, rest = polygon2d.inner_rectangle(polygon, alignment)
            if rectangle is not None:
                pieces["shape"].append([frame.lift(rectangle)])
            pieces["remainder"] += [[frame.lift(p)] for p in rest]
        if not node.branches:  # innerRect without a block: the shape becomes the rectangle
            if not pieces["shape"]:
                return False
            state.shape = flat_shape(state.shape, [g[0] for g in pieces["shape"]])
            return True
        _emit_all(state, args, branches, lambda s: pieces[s], out)
        return True

    return inner_op


@compiles("footprint")
def compile_footprint(program, node: ast.Operation, params):
    """``footprint()``: the shape's geometry projected on its scope's plane y = 0, as a flat
    shape facing +y (the union of the projected faces)."""
    plain_arguments(program, node, range(0, 1), block=True)

    def footprint_op(state, args, out):
        mesh = state.shape.mesh()
        # (x, -z) is counter-clockwise seen from +y.
        plan = [
            np.column_stack([p[:, 0], -p[:, 2]])
            for p in (mesh.face_points(k) for k in range(mesh.n_faces))
        ]
        plan = [polygon2d.counter_clockwise(p) for p in plan if len(p) >= 3]
        plan = [p for p in plan if len(p) >= 3 and polygon2d.signed_area(p) > 0]
        if not plan:
            return False
        faces = [np.column_stack([p[:, 0], np.zeros(len(p)), -p[:, 1]]) for p in plan]
        faces = [
            np.column_stack([q[:, 0], np.zeros(len(q)), -q[:, 1]]) for q in polygon2d.union(plan)
        ] or faces
        shape = flat_shape(state.shape, faces)
        state.shape = Shape(shape.scope, FACE, 1, None, shape.geometry)
        return True

    return footprint_op
