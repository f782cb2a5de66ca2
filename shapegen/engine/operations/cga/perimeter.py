"""``splitAndSetbackPerimeter(splitOffset[, firstEdgeIndex, selectedEdgesMask]) { length :
depth : operations | ... }[*] { remainder : operations }`` (op_splitAndSetbackPerimeter).

The selected edges of the face, from ``firstEdgeIndex`` counter-clockwise, are one chain; the
pattern is laid along it as a split lays its parts along an axis (absolute, ``'`` relative to
the chain's length, ``~`` floating; ``*`` repeats), starting ``splitOffset`` along the chain
(``'`` relative to its length) and wrapping round. Each section is then set back by its depth
(evaluated per section, with ``split.index`` and ``split.total`` the section's): the face's
edges are cut at the sections' ends and one weighted setback sets every piece back by its
section's depth, so where two sections' strips would overlap the deeper one takes the overlap
("The overlap belongs to the shape that has been generated with larger depth"). A section's
strips are one shape; the remainder (the face without the strips) is a shape per polygon. The
pieces' edges get setback's auto-tags (``setback.front``, ``setback.back``, ``setback.side``,
``setback.remainder``).

shapegen works on the first face of the shape (the lot, a comp face); a shape of several faces
gives a warning and its other faces are left out.
"""

from __future__ import annotations

__all__ = ["compile_split_and_setback_perimeter"]

import math

import numpy as np

from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.cga.polygons import array_elements, flat_faces, flat_shape
from shapegen.engine.operations.cga.setback_tags import SetbackLines
from shapegen.engine.operations.cga.setbacks import joined_strips
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.split import SplitPart, SplitRepeat, resolve_split
from shapegen.engine.shapes.tags import Pending
from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d
from shapegen.grammar import ast
from shapegen.tolerances import COINCIDENT_REL


@operation(
    "splitAndSetbackPerimeter",
    partial="the perimeter of the first face only (a warning for the others)",
)
def compile_split_and_setback_perimeter(program, node: ast.Operation, params):
    arguments = node.arguments
    if len(arguments) not in (1, 3):
        raise program.error(
            node, "splitAndSetbackPerimeter() takes (splitOffset) or (splitOffset, "
            "firstEdgeIndex, selectedEdgesMask)"
        )  # fmt: skip
    if arguments[0].kind not in ("plain", "relative"):
        raise program.error(node, "splitAndSetbackPerimeter()'s offset is a length or 'a share")
    if any(a.kind != "plain" for a in arguments[1:]):
        raise program.error(node, "splitAndSetbackPerimeter() takes plain edge arguments")
    relative_offset = arguments[0].kind == "relative"
    offset = program.expressions.compile(arguments[0].value, params)
    first_edge = (
        program.expressions.compile(arguments[1].value, params) if len(arguments) > 1 else None
    )
    mask = program.expressions.compile(arguments[2].value, params) if len(arguments) > 2 else None
    pattern, remainder = [], []
    for branch in node.branches:
        if branch.depth is None:
            if not (isinstance(branch.key, ast.Name) and branch.key.name == "remainder"):
                raise program.error(
                    branch, "splitAndSetbackPerimeter's entries are 'length : depth : "
                    "operations' and '{ remainder : operations }'"
                )  # fmt: skip
            remainder.append((program.body(branch.body, params), branch))
            continue
        pattern.append(
            (
                branch.mode,
                program.expressions.compile(branch.key, params),
                program.expressions.compile(branch.depth, params),
                program.body(branch.body, params),
                branch,
            )
        )
    if not pattern:
        raise program.error(node, "splitAndSetbackPerimeter() needs 'length : depth : operations'")
    error = program.error

    def number(value, what: str) -> float:
        if type(value) is not float or not math.isfinite(value):
            raise error(node, f"splitAndSetbackPerimeter(): {what} must be a finite number, "
                              f"got {type_name(value)}")  # fmt: skip
        return value

    def perimeter_op(state, args, out):
        faces = flat_faces(state, node, program, "splitAndSetbackPerimeter()")
        if not faces:
            return False
        if len(faces) > 1:
            warn_at(state, node, "splitAndSetbackPerimeter(): shapegen splits the perimeter "
                                 "of the shape's first face; the others are left out")  # fmt: skip
        frame, polygon = faces[0]
        n = len(polygon)
        lengths = np.linalg.norm(np.roll(polygon, -1, axis=0) - polygon, axis=1)
        start = 0
        if first_edge is not None:
            start = int(number(first_edge(args, state), "the first edge index")) % n
        selected = np.ones(n, bool)
        if mask is not None:
            values = array_elements(mask(args, state))
            if values is None or any(type(v) is not bool for v in values):
                raise error(node, "splitAndSetbackPerimeter()'s edge mask is an array of booleans")
            selected = np.array([bool(values[k]) if k < len(values) else False for k in range(n)])
        chain = [(start + j) % n for j in range(n) if selected[(start + j) % n]]
        total = float(sum(lengths[k] for k in chain))
        if total <= 0:
            return False
        parts = [
            SplitPart(number(size(args, state), "a length"), mode, k)
            for k, (mode, size, _, _, _) in enumerate(pattern)
        ]
        try:
            sections = resolve_split(
                total, SplitRepeat(tuple(parts)) if node.repeat else parts, best_counts=True,
                max_pieces=state.run.max_shapes,
            )  # fmt: skip
        except ValueError as exc:
            raise program.operation_error(node, f"splitAndSetbackPerimeter(): {exc}") from None
        shift = number(offset(args, state), "the offset")
        shift = (shift * total if relative_offset else shift) % total
        depths = []
        saved = state.split_index, state.split_total
        try:
            for index, piece in enumerate(sections):
                state.split_index, state.split_total = index, len(sections)
                depth = number(pattern[piece.key][2](args, state), "a depth")
                depths.append(max(depth, 0.0))
        finally:
            state.split_index, state.split_total = saved
        cut, owner = _cut_polygon(polygon, lengths, chain, sections, shift, total)
        distances = np.array([depths[s] if s is not None else 0.0 for s in owner])
        try:
            result = polygon2d.setback(cut, distances)
        except GeometryError as exc:
            raise program.operation_error(node, f"splitAndSetbackPerimeter(): {exc}") from None
        lines = SetbackLines()
        lines.add(state.shape.scope, frame, cut, distances)
        parent = state.shape
        strips: dict[int, list] = {}
        for k, piece in result.strips:
            if owner[k] is not None:
                strips.setdefault(owner[k], []).append(piece)
        run = state.run
        for index, piece in enumerate(sections):
            if index not in strips:
                continue
            body, branch = pattern[piece.key][3], pattern[piece.key][4]
            groups = joined_strips(frame, strips[index])
            made = flat_shape(parent, [face for group in groups for face in group])
            if run.tags:
                made = made.with_tags(Pending(parent, lines.rule(False)))
            child = run.child(state, made, branch)
            child.split_index, child.split_total = index, len(sections)
            if body(child, args, out) and child.is_leaf():
                out.append((child, None, ()))
        rest = _remainder(cut, [piece for _, piece in result.strips])
        for body, branch in remainder:
            for piece in rest:
                made = flat_shape(parent, [frame.lift(piece)])
                if run.tags:
                    made = made.with_tags(Pending(parent, lines.rule(True)))
                child = run.child(state, made, branch)
                if body(child, args, out) and child.is_leaf():
                    out.append((child, None, ()))
        return False

    return perimeter_op


def _cut_polygon(polygon, lengths, chain, sections, shift: float, total: float):
    """``polygon`` with corners added where the sections (shifted by ``shift`` along the chain
    of edges ``chain`` and wrapped round its ``total`` length) begin and end, and the section
    index of each of its edges (None for an edge outside the chain or between sections)."""
    bounds = []
    for piece in sections:
        bounds += [(piece.start + shift) % total, (piece.start + piece.size + shift) % total]
    along = {}  # edge -> its start's position along the chain
    position = 0.0
    for k in chain:
        along[k] = position
        position += lengths[k]
    slack = COINCIDENT_REL * max(1.0, total)
    points, owner = [], []
    n = len(polygon)
    for k in range(n):
        a, b = polygon[k], polygon[(k + 1) % n]
        cuts = [0.0]
        if k in along:
            cuts += sorted(
                t - along[k] for t in bounds if along[k] + slack < t < along[k] + lengths[k] - slack
            )
        cuts.append(float(lengths[k]))
        for lo, hi in zip(cuts, cuts[1:], strict=False):
            if hi - lo <= slack:
                continue
            points.append(a + (b - a) * (lo / lengths[k]))
            owner.append(
                _section_at(along[k] + (lo + hi) / 2, sections, shift, total)
                if k in along
                else None
            )
    return np.array(points), owner


def _remainder(polygon: np.ndarray, strips: list[np.ndarray]) -> list[np.ndarray]:
    """``polygon`` without the ``strips``, counter-clockwise polygons. The weighted setback's
    own remainder (its front) leaves out what lies before an edge that stays put between two
    that move, which belongs to the remainder here: the pieces tile the face."""
    import shapely
    from shapely.geometry import Polygon

    whole = Polygon(polygon)
    rest = whole.difference(shapely.union_all([Polygon(p) for p in strips])) if strips else whole
    slack = COINCIDENT_REL * max(1.0, whole.area)
    out = []
    for part in getattr(rest, "geoms", [rest]):
        if isinstance(part, Polygon) and part.area > slack:
            ring = shapely.geometry.polygon.orient(part, 1.0).exterior.coords
            out.append(np.array(ring[:-1]))
    return out


def _section_at(position: float, sections, shift: float, total: float):
    for index, piece in enumerate(sections):
        offset = (position - shift - piece.start) % total
        if offset < piece.size:
            return index
    return None
