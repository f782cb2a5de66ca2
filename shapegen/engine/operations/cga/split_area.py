"""CityEngine's ``splitArea(axis) { area : ... | ... }``: a split whose sizes are areas.

The pattern (absolute, ``'`` relative, ``~`` floating parts, a trailing ``*`` for a repeat) is
resolved exactly as ``split`` resolves lengths, but over the geometry's area instead of the
scope's length (:func:`shapegen.engine.shapes.split.resolve_split`); each piece's bounds in area are
then turned into cut positions along the axis, where the area of the geometry below the cut
(a continuous, increasing function) reaches them, found by bisection. The pieces are cut as
``split`` cuts (:func:`shapegen.engine.shapes.shape.split_piece`): scopes adjusted to the pieces,
or with ``noAdjust`` the slices of the shape's scope between the cuts, which "fill the parent's
scope without gaps" (op_splitArea).
"""

from __future__ import annotations

__all__ = ["compile_split_area"]

import numpy as np

from shapegen.engine.operations.cga.arguments import number, plain_arguments, selector_name
from shapegen.engine.operations.registry import operation
from shapegen.engine.shapes.shape import FACE, axis_index, split_piece
from shapegen.engine.shapes.split import PieceLimitError, SplitPart, SplitRepeat, resolve_split
from shapegen.geometry.cut import clip_half
from shapegen.grammar import ast

_BISECTIONS = 60  # halvings of the axis extent: below 1e-15 of it


def _area_below(mesh, axis: int, position: float) -> float:
    piece = clip_half(mesh, axis, position, False)
    return 0.0 if piece is None else piece.area()


def _position(mesh, axis: int, low: float, high: float, area: float, total: float) -> float:
    """Where along ``axis`` the area of ``mesh`` below the cut reaches ``area`` (m²)."""
    if area <= 0:
        return low
    if area >= total:
        return high
    for _ in range(_BISECTIONS):
        middle = 0.5 * (low + high)
        if _area_below(mesh, axis, middle) < area:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


@operation("splitArea")
def compile_split_area(program, node: ast.Operation, params):
    """``splitArea(x|y|z[, adjust|noAdjust]) { area : ... | 'fraction : ... | ~w : ... }[*]``."""
    names = [selector_name(v) for v in plain_arguments(program, node, (1, 2), block=True)]
    if names[0] not in ("x", "y", "z"):
        raise program.error(node, "splitArea()'s axis is x, y or z")
    if len(names) == 2 and names[1] not in ("adjust", "noAdjust"):
        raise program.error(node, f"splitArea()'s adjust mode is adjust or noAdjust, got "
                                  f"{names[1] or 'a value'}")  # fmt: skip
    adjust = len(names) == 1 or names[1] == "adjust"
    if not node.branches:
        raise program.error(node, "splitArea() needs a { area : ... } block")
    axis = axis_index(names[0])
    parts = []
    for branch in node.branches:
        if branch.merge:
            raise program.error(branch, "splitArea() parts take ':', not '='")
        size = number(program, node, branch.key, params, "a size", at=branch)
        parts.append((size, branch.mode, program.body(branch.body, params), branch))
    repeat = node.repeat

    def split_area_op(state, args, out):
        shape = state.shape
        if shape.kind != FACE:
            # op_splitArea "does not apply to 3D geometry": in .cga a CGA error of the runtime
            fail = program.operation_error if shape.kind != "insert" else program.error
            raise fail(node, "splitArea() needs a flat shape (the lot or a comp(f) face)")
        mesh = shape.mesh()
        if mesh.n_vertices == 0:  # cleanupGeometry() merged it all away: no pieces, as split()
            return True
        total = mesh.area()
        pattern = [SplitPart(size(args, state), mode, (body, branch))
                   for size, mode, body, branch in parts]  # fmt: skip
        run = state.run
        try:
            pieces = resolve_split(
                total,
                SplitRepeat(tuple(pattern)) if repeat else pattern,
                max_pieces=max(run.max_shapes - run.shape_count, 0) + 1,
            )
        except PieceLimitError:
            raise program.error(
                node, f"splitArea() creates more than {run.max_shapes} shapes (max_shapes)"
            ) from None  # fmt: skip
        except ValueError as exc:
            raise program.operation_error(node, str(exc)) from None
        low, high = (float(v) for v in np.array(mesh.bounds())[:, axis])
        if not adjust:  # the slices fill the scope: the first from its start, the last to its end
            low, high = min(low, 0.0), max(high, float(shape.scope.size[axis]))
        made = []
        for piece in pieces:
            run.check_clock(node)  # 120 bisections a piece, before any child is counted
            start = _position(mesh, axis, low, high, piece.start, total)
            end = _position(mesh, axis, low, high, piece.start + piece.size, total)
            cut = split_piece(shape, axis, start, end - start, adjust)
            if cut is not None:
                made.append((piece.key, cut))
        for index, ((body, branch), cut) in enumerate(made):
            child = run.child(state, cut, branch)
            child.split_index = index
            child.split_total = len(made)
            if body(child, args, out) and child.is_leaf():
                out.append((child, None, ()))
        return True

    return split_area_op
