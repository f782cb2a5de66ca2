"""The comp *function* (func_comp): ``comp(fe) { all : scope.sx }``, an array of values, one per
component of the current shape, the shape left as it is.

As func_comp says: the array has one element per component (face, edge, vertex...) in the
component order of the comp operation (:mod:`shapegen.engine.operations.cga.topology`);
selectors take components from left to right as the operation's do; a value is the expression
evaluated on the component's shape (its ``scope``, ``geometry``, ``comp.index``, ``comp.sel``...);
with ``=`` it is evaluated once, on the selected faces merged (for edges and vertices: on the first
of them), and copied to each of them; components no selector takes get the default of the values'
type (0, "" or false). All values must be of one type.
"""

from __future__ import annotations

__all__ = ["compile_component_values"]

from types import SimpleNamespace

from shapegen.engine.expressions.arrays import Array, type_name
from shapegen.engine.operations.cga.topology import (
    COMPONENT_KINDS,
    EDGE,
    component_selector,
    components_of,
    holes_shape,
    merged_shape,
    selector_text,
    selector_word,
)
from shapegen.engine.shapes.shape import FACE, MASS
from shapegen.grammar import ast

_DEFAULTS = {float: 0.0, str: "", bool: False}


def compile_component_values(compiler, node: ast.ComponentValues, params):
    """The compiled ``comp(kind[, alignment]) { selector : expression | ... }`` function."""
    program = SimpleNamespace(expressions=compiler, error=compiler.error)
    if not node.arguments:
        raise compiler.error(node, "comp() needs the kind of component: comp(f), comp(e)...")
    kind = selector_word(node.arguments[0])
    if kind not in COMPONENT_KINDS:
        raise compiler.error(node, f"comp({kind}) splits into f, e, v, fe, fv, g, m or h")
    for branch in node.branches:
        if branch.connected:
            raise compiler.error(
                branch,
                "comp's '=:' operator (a shape per connected set of components) "
                "is not supported by shapegen",
            )
    branches = [
        (
            component_selector(program, branch.selector, params, kind),
            branch.merge,
            compiler.compile(branch.value, params),
            selector_text(branch.selector),
        )
        for branch in node.branches
    ]
    error = compiler.error

    def values(args, state):
        shape = state.shape
        if shape.kind not in (FACE, MASS, EDGE):
            raise error(node, f"comp({kind}) cannot take apart an inserted primitive")
        components = components_of(shape, kind, getattr(state.run, "object_rotation", None))
        out: list = [None] * len(components)
        taken = [False] * len(components)
        saved = (state.shape, state.comp_index, state.comp_total, state.comp_sel)
        try:
            for select, merge, value, text in branches:
                chosen = [k for k, c in enumerate(components)
                          if not taken[k] and select(c, state, args)]  # fmt: skip
                for k in chosen:
                    taken[k] = True
                if not chosen:
                    continue
                state.comp_sel = text
                if merge:
                    state.shape = (
                        merged_shape(
                            holes_shape(shape) if kind == "h" else shape,
                            [components[k] for k in chosen],
                        )
                        if kind in ("f", "h")
                        else components[chosen[0]].shape
                    )
                    state.comp_index, state.comp_total = 0, 1
                    result = value(args, state)
                    for k in chosen:
                        out[k] = result
                    continue
                state.comp_total = len(chosen)
                for index, k in enumerate(chosen):
                    state.shape = components[k].shape
                    state.comp_index = index
                    out[k] = value(args, state)
        finally:
            state.shape, state.comp_index, state.comp_total, state.comp_sel = saved
        kinds = {type(v) for v in out if v is not None}
        if len(kinds) > 1 or (kinds and next(iter(kinds)) not in _DEFAULTS):
            shown = ", ".join(sorted({type_name(v) for v in out if v is not None}))
            raise error(node, f"the comp() function's values must be of one type (float, string "
                              f"or bool), got {shown}")  # fmt: skip
        default = _DEFAULTS[next(iter(kinds))] if kinds else 0.0
        return Array(tuple(default if v is None else v for v in out), 1 if out else 0, len(out))

    return values
