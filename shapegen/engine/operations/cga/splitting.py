"""``split(x|y|z) { size : body | ... }*`` (op_split): the shape cut along one scope axis into
pieces laid out by the sizes (absolute, ``'`` relative, ``~`` floating, ``{ ... }*``
repeated; :mod:`shapegen.engine.shapes.split`), each piece derived by its body.
"""

from __future__ import annotations

__all__ = ["compile_split"]

from collections.abc import Callable

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.operations.registry import operation
from shapegen.engine.operations.template_primitives import INSERT
from shapegen.engine.shapes.shape import axis_index, split_pieces
from shapegen.engine.shapes.split import PieceLimitError, SplitPart, SplitRepeat, resolve_split
from shapegen.grammar import ast


def _split_items(program, group: ast.SplitGroup, params) -> Callable:
    """A closure giving the evaluated split items of ``group`` (nested groups inline)."""
    builders = []
    for part in group.parts:
        if isinstance(part, ast.SplitGroup):
            inner = _split_items(program, part, params)
            if part.repeat:
                builders.append(
                    lambda args, state, inner=inner: [SplitRepeat(tuple(inner(args, state)))]
                )
            else:
                builders.append(inner)
            continue
        size = program.number(part, part.size, params, "a split size")
        key = (program.body(part.body, params), part)
        mode = part.mode
        builders.append(
            lambda args, state, size=size, key=key, mode=mode: [
                SplitPart(size(args, state), mode, key)
            ]
        )

    def items(args, state):
        out = []
        for build in builders:
            out.extend(build(args, state))
        return out

    return items


@operation(
    "split",
    nodes=(ast.Split,),
    partial="split(u|v, ...) runs along the scope's x or y, with a warning (no texture "
    "coordinates)",
)
def compile_split(program, node: ast.Split, params):
    """``split(axis [, adjust | noAdjust] [, texture]) { ... }``: the pieces CityEngine makes
    (its repeat counts in ``.cga`` files), those with no geometry dropped."""
    axis = axis_index(node.axis)
    items = _split_items(program, node.group, params)
    repeat = node.group.repeat
    error, operation_error = program.error, program.operation_error
    best_counts = program.cga_dialect  # CityEngine's repeat counts in .cga files
    where = node.location
    adjust = node.adjust  # noAdjust: the pieces keep the scope slices (op_split)

    def split_op(state, args, out):
        shape = state.shape
        if shape.kind == INSERT:
            raise error(
                node,
                "split() cannot cut an inserted primitive; split first, then "
                "insert into the pieces",
            )
        pattern = items(args, state)
        if repeat:
            pattern = SplitRepeat(tuple(pattern))
        run = state.run
        extent = shape.scope.d[axis]
        scale = 1.0
        if node.texture is not None:
            run.warn(
                f"{where}: split({'u' if axis == 0 else 'v'}, {node.texture}) runs along "
                f"the scope's {'x' if axis == 0 else 'y'} axis: shapegen keeps no texture "
                "coordinates"
                + (" (uv taken as 0..1 over the scope)" if node.texture == "uvSpace" else "")
            )
            if node.texture == "uvSpace":
                extent, scale = 1.0, extent
        try:
            pieces = resolve_split(
                extent,
                pattern,
                max_pieces=max(run.max_shapes - run.shape_count, 0) + 1,
                best_counts=best_counts,
            )
        except PieceLimitError:
            raise error(
                node,
                f"the split creates more than {run.max_shapes} shapes "
                f"(max_shapes). Chain of rules: "
                f"{format_chain(state.rule_path)} "
                f"(raise it with Grammar.build(max_shapes=...) or "
                f"shapegen.limits.work_limits(max_shapes=...))",
            ) from None
        except ValueError as exc:
            raise operation_error(node, str(exc)) from None
        spans = [(piece.start * scale, piece.size * scale) for piece in pieces]
        cuts, within = split_pieces(shape, axis, spans, run.limits.max_coordinate, adjust)
        made = [  # CityEngine drops pieces with no geometry
            (piece.key, cut) for piece, cut in zip(pieces, cuts, strict=True) if cut is not None
        ]
        total = len(made)
        for index, ((body, part), cut) in enumerate(made):
            child = run.child(state, cut, part, within_bounds=within)
            child.split_index = index
            child.split_total = total
            if body(child, args, out) and child.is_leaf():
                out.append((child, None, ()))
        return True

    return split_op
