"""The selectors of comp(), modify() and the comp() function (op_comp): a name (``front``,
``world.up``, ``object.side``, ``vertical``, ``border``... see
:data:`shapegen.geometry.queries.FACE_SELECTORS`; the roof edges ``eave``, ``hip``, ``valley``,
``ridge`` for comp(e)), an index, ``||``/``&&``/``!`` of those and of conditions, or any
boolean expression evaluated on the component's own shape (``geometry.area() > 1``,
``isTagged("x")``: :func:`shapegen.engine.shapes.tags.is_tagged` looks at the component the
selector is given).
"""

from __future__ import annotations

__all__ = ["Selector", "component_selector", "selector_text"]

from collections.abc import Callable

from shapegen.engine.expressions.arrays import format_value, type_name
from shapegen.engine.shapes.tags import Pending
from shapegen.geometry.queries import FACE_SELECTORS, face_matches
from shapegen.geometry.roof_edges import ROOF_EDGE_CLASSES as _ROOF_EDGES
from shapegen.grammar import ast

Selector = Callable[[object, object, tuple], bool]  # (component, state, args) -> taken


def component_selector(program, key, params, kind: str, where=None) -> Selector:
    """A predicate on components from a branch key (an AST expression, or a name string of the
    branch ``where``)."""
    if isinstance(key, str):
        if key.isdigit():
            index = int(key)
            return lambda c, state, args: c.index == index
        return _named(program, where, key, kind)
    if isinstance(key, ast.Number):
        index = int(key.value)
        return lambda c, state, args: c.index == index
    if isinstance(key, ast.Name) and (key.name in FACE_SELECTORS or key.name in _ROOF_EDGES):
        return _named(program, key, key.name, kind)
    if isinstance(key, ast.ShapeAttribute) and f"{key.obj}.{key.field}" in FACE_SELECTORS:
        return _named(program, key, f"{key.obj}.{key.field}", kind)
    # selectors and conditions mix (op_comp: isTagged("x") && side)
    if isinstance(key, ast.Binary) and key.op in ("||", "&&") and _has_selector(key):
        left = component_selector(program, key.left, params, kind)
        right = component_selector(program, key.right, params, kind)
        if key.op == "||":
            return lambda c, state, args: left(c, state, args) or right(c, state, args)
        return lambda c, state, args: left(c, state, args) and right(c, state, args)
    if isinstance(key, ast.Unary) and key.op == "!" and _has_selector(key.operand):
        inner = component_selector(program, key.operand, params, kind)
        return lambda c, state, args: not inner(c, state, args)
    # any other expression: a condition evaluated on the component's own shape
    compiled = program.expressions.compile(key, params)
    error = program.error

    def condition(c, state, args):
        saved = state.shape
        run = state.run
        outer = run.tag_selection
        run.tag_selection = (saved, kind, c)  # what isTagged() looks at
        if saved.tags is not None and c.shape.tags is None:  # geometry.tags() reads its own
            c.shape = c.shape.with_tags(Pending(saved))
        state.shape = c.shape
        try:
            value = compiled(args, state)
        finally:
            state.shape = saved
            run.tag_selection = outer
        if type(value) is float and value == int(value):  # op_comp: an index may be computed
            return c.index == int(value)
        if type(value) is not bool:
            raise error(
                key,
                f"a comp selector must be a boolean or a component index, got "
                f"{format_value(value) if type(value) is float else 'a ' + type_name(value)}",
            )
        return value

    return condition


def selector_text(key) -> str:
    """``comp.sel``: the selector as written (a name, an index), "" for an expression."""
    if isinstance(key, str):
        return key
    if isinstance(key, ast.Number):
        return str(int(key.value))
    if isinstance(key, ast.Name):
        return key.name
    if isinstance(key, ast.ShapeAttribute):
        return f"{key.obj}.{key.field}"
    return ""


def _has_selector(key) -> bool:
    """Whether a selector name or index is somewhere in the ``||``, ``&&`` and ``!`` of
    ``key``."""
    if _is_selector(key):
        return True
    if isinstance(key, ast.Binary) and key.op in ("||", "&&"):
        return _has_selector(key.left) or _has_selector(key.right)
    if isinstance(key, ast.Unary) and key.op == "!":
        return _has_selector(key.operand)
    return False


def _is_selector(key) -> bool:
    if isinstance(key, ast.Number):
        return True
    if isinstance(key, ast.Name):
        return key.name in FACE_SELECTORS or key.name in _ROOF_EDGES
    if isinstance(key, ast.ShapeAttribute):
        return f"{key.obj}.{key.field}" in FACE_SELECTORS
    if isinstance(key, ast.Binary) and key.op in ("||", "&&"):
        return _is_selector(key.left) and _is_selector(key.right)
    if isinstance(key, ast.Unary) and key.op == "!":
        return _is_selector(key.operand)
    return False


def _named(program, node, name: str, kind: str) -> Selector:
    if name in _ROOF_EDGES:
        if kind != "e":  # op_comp: "These selectors can only be applied on edge component splits"
            raise program.error(
                node, f"the roof-edge selector {name!r} needs comp(e), not comp({kind})"
            )
        return lambda c, state, args: c.roof == name
    if name not in FACE_SELECTORS:
        raise program.error(node, f"unknown comp selector {name!r}")
    if name in ("border", "inside") and kind == "h":
        # op_comp: "This selector does not work on holes": PyPRT's comp(h) takes no hole with
        # either (and warns: topology.comp_operation)
        return lambda c, state, args: False
    return lambda c, state, args: face_matches(name, c.normal, c.world, c.object, c.border)
