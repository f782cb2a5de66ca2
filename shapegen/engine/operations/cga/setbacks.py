"""CityEngine's setbacks of faces: setback, setbackPerEdge, setbackToArea, shapeL, shapeU and
shapeO (op_setback and its kin), on the faces :mod:`.polygons` lays in their planes.

Each face's edges are taken by the first branch whose selector matches them; the distances set
them back, and :func:`shapegen.geometry.setback_pieces.setback_pieces` gives each branch its
pieces as CityEngine's runtime does (the strips of its edges joined, the corners it shares with
a later branch, a face's holes kept in the piece around them; tests/data/prt_setback.json).
shapeL, shapeU and shapeO join their strips into the one ``shape``.
"""

from __future__ import annotations

__all__ = ["compile_setback", "compile_setback_to_area", "compile_shape_luo", "joined_strips"]

import numpy as np

from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.cga.arguments import number, plain_arguments
from shapegen.engine.operations.cga.polygons import (
    FaceFrame,
    array_elements,
    edge_normals,
    emit_pieces,
    face_holes,
    flat_faces,
    selector_branches,
)
from shapegen.engine.operations.cga.setback_tags import SetbackLines, edge_component
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d
from shapegen.geometry.queries import face_matches
from shapegen.geometry.scope_frames import quadrant
from shapegen.geometry.setback_pieces import setback_pieces, setback_to_area
from shapegen.grammar import ast
from shapegen.tolerances import COINCIDENT_REL


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
    quadrants, selected, first, rings)`` gives each edge's distance (``first``: the index of the
    face's first edge among the shape's face edges, each face's outline and then its holes;
    ``rings``: the face's holes)."""

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
            distances = distances_of(args, state, frame, polygon, quadrants, selected, first, rings)
            first += n + sum(len(ring) for ring in rings)
            lines.add(state.shape.scope, frame, polygon, distances)
            if shape_selector:
                # shapeL/U/O: every set-back edge in one group, so that an O is one face with
                # a hole (tests/data/prt_setback_holes.json)
                groups = [[k for k in range(n) if distances[k] > 0]]
                names = ["shape"]
            else:
                # each branch's edges in the order the branches are written: the first takes
                # the corners it shares with a later one (tests/data/prt_setback.json)
                groups = [[k for k in range(n) if owner[k] == sel] for sel in selectors]
                names = selectors
            try:  # a face's holes kept in the piece around them, a hole across its edge a notch
                pieces = setback_pieces(polygon, rings, distances, groups)
            except GeometryError as exc:
                raise program.operation_error(node, f"{node.name}(): {exc}") from None
            for selector, group in zip(names, pieces.groups, strict=True):
                for outer, inner in group:
                    lifted = (frame.lift(outer), [frame.lift(h) for h in inner])
                    strips.setdefault(selector, []).append([lifted])
            remainder += [
                [(frame.lift(outer), [frame.lift(h) for h in inner])]
                for outer, inner in pieces.remainder
            ]

        def pieces_of(selector):
            return remainder if selector == "remainder" else strips.get(selector, [])

        emit_pieces(state, args, branches, pieces_of, out, lines)
        return True

    return setback_op


def joined_strips(frame: FaceFrame, pieces: list[np.ndarray]) -> list[list[np.ndarray]]:
    """The union of strips as face groups: one polygon per piece, or (a ring, which a face
    without holes cannot hold) the strips together as one shape."""
    merged = polygon2d.union(pieces)
    if abs(sum(map(polygon2d.signed_area, merged)) - sum(map(polygon2d.signed_area, pieces))) > (
        COINCIDENT_REL * sum(map(polygon2d.signed_area, pieces))
    ):
        return [[frame.lift(p) for p in pieces]]
    return [[frame.lift(p)] for p in merged]


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


@operation("setback", "setbackPerEdge")
def compile_setback(program, node: ast.Operation, params):
    """``setback(distance | distances) { selector : ... | remainder : ... }``; setbackPerEdge
    evaluates its distance once per edge (with ``comp.index`` the edge's index)."""
    values = plain_arguments(program, node, range(1, 2), block=True)
    branches = selector_branches(program, node, params, {"remainder"}, edges=True)
    distance = program.expressions.compile(values[0], params)
    per_edge = node.name == "setbackPerEdge"

    def distances_of(args, state, frame, polygon, quadrants, selected, first, rings=()):
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


@operation("setbackToArea")
def compile_setback_to_area(program, node: ast.Operation, params):
    """``setbackToArea(area[, minDistances[, maxDistances]]) { selector : ... }``."""
    values = plain_arguments(program, node, range(1, 4), block=True)
    branches = selector_branches(program, node, params, {"remainder"}, edges=True)
    area = number(program, node, values[0], params, "the area")
    bounds = [program.expressions.compile(v, params) for v in values[1:]]

    def distances_of(args, state, frame, polygon, quadrants, selected, first, rings=()):
        n = len(polygon)
        limits = [_distance_list(program, node, b(args, state), n, first) for b in bounds]
        return _to_area(program, node, polygon, rings, area(args, state), selected, *limits)

    return _setback_operation(program, node, branches, distances_of, shape_selector=False)


def _to_area(program, node, polygon, rings, area, selected, low=None, high=None):
    """setbackToArea's distances (:func:`~shapegen.geometry.setback_pieces.setback_to_area`). Where
    the face has less than the area the runtime sets nothing back and records nothing: the
    remainder is the whole face (tests/data/prt_setback_holes.json, with and without holes);
    a .grammar file refuses it."""
    face = polygon2d.signed_area(polygon) + sum(polygon2d.signed_area(h) for h in rings)
    if program.cga_dialect and np.isfinite(area) and area > face:
        return np.zeros(len(polygon))
    try:
        _, d = setback_to_area(polygon, area, selected, low, high, holes=rings)
    except GeometryError as exc:
        raise program.operation_error(node, str(exc)) from None
    return d


_LUO = {"shapeL": ("front", "left"), "shapeU": ("front", "right", "left"),
        "shapeO": ("front", "right", "back", "left")}  # fmt: skip


@operation("shapeL", "shapeU", "shapeO")
def compile_shape_luo(program, node: ast.Operation, params):
    """``shapeL(front, left)``, ``shapeU(front, right, left)``, ``shapeO(front, right, back,
    left) { shape : ... | remainder : ... }``: a setback of those sides, the strips as one
    polygon."""
    sides = _LUO[node.name]
    values = plain_arguments(program, node, (len(sides),), block=True)
    widths = [number(program, node, v, params, "a width") for v in values]
    branches = selector_branches(program, node, params, {"shape", "remainder"}, edges=False)

    def distances_of(args, state, frame, polygon, quadrants, selected, first, rings=()):
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
