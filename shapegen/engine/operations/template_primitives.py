"""shapegen's template primitives in ``i("name", key=value)`` (``box``, ``arch``, ``column``...,
the registry of :mod:`shapegen.primitives`): which names they are, the check of a call with a
literal name when the rule loads, the parameters of one when it is derived, and the compiled
``i()`` itself (:func:`compile_insert`)."""

from __future__ import annotations

__all__ = ["INSERT", "check_primitive_call", "compile_insert", "is_template", "resolve_primitive"]

from collections.abc import Callable

from shapegen.engine.derivation.state import Operation
from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.registry import operation
from shapegen.engine.shapes.shape import MASS, Shape
from shapegen.errors import GeometryError, OptionError, did_you_mean
from shapegen.grammar import ast

INSERT = "insert"
"""The kind of a shape that holds an inserted primitive (``i(...)``), beside FACE and MASS."""


def is_template(name: str) -> bool:
    """True when ``name`` is one of shapegen's template primitives (``box``, ``arch``...)."""
    from shapegen.primitives import get

    try:
        get(name)
    except OptionError:
        return name == "box"
    return True


def check_primitive_call(node: ast.Insert, error: Callable) -> None:
    """At load time: ``i("name", key=...)`` with a literal name must name a registered
    primitive and only its parameters (values are checked when the shape is derived)."""
    from shapegen.primitives import get

    name = node.primitive.value
    if name == "box" and not node.parameters:
        return
    try:
        primitive = get(name)
    except OptionError as exc:
        raise error(node, str(exc)) from None
    for keyword in node.parameters:
        if keyword.name not in primitive.parameters:
            known = ", ".join(sorted(primitive.parameters)) or "none"
            hint = did_you_mean(keyword.name, primitive.parameters, parenthesised=True)
            raise error(
                keyword if getattr(keyword, "location", None) else node,
                f"primitive {name!r} has no parameter {keyword.name!r}{hint}; "
                f"its parameters: {known}",
            )


def resolve_primitive(name: str, values: dict) -> dict:
    from shapegen.primitives import get

    return get(name).resolve(values)


@operation(
    "i",
    nodes=(ast.Insert,),
    partial="reads OBJ, glTF, COLLADA, PLY and STL assets, and FBX with the optional ufbx "
    "(`shapegen[fbx]`), cleaned as CityEngine cleans them; a .usd, .dwg or .ifc asset (or an "
    ".fbx without ufbx) is a box with a warning in .cga rules (refused in .grammar ones)",
)
def compile_insert(program, node: ast.Insert, params) -> Operation:
    """``i(name, key=value...)`` (op_i): a template primitive put in the scope, or an asset
    (:func:`~shapegen.engine.operations.cga.assets.asset_insert`) when the name is a file or a
    builtin asset; ``program`` is the grammar's
    :class:`~shapegen.engine.operations.compiler.OperationCompiler`."""
    from shapegen.engine.operations.cga.assets import asset_insert, is_asset_name

    literal = isinstance(node.primitive, ast.String)
    if literal and is_asset_name(node.primitive.value):  # a file or builtin: asset
        return asset_insert(program, node, params)
    cga = program.cga_dialect
    if literal and cga and not node.parameters and not is_template(node.primitive.value):
        # CityEngine knows no template primitives: a name shapegen lacks is an asset
        return asset_insert(program, node, params)
    assets = None if literal or node.parameters else asset_insert(program, node, params)
    if literal:
        check_primitive_call(node, program.error)
    if node.options and (literal or node.parameters):
        raise program.error(node, "i() of a template primitive takes key=value parameters only")
    name_of = program.expressions.compile(node.primitive, params)
    keywords = [(k.name, program.expressions.compile(k.value, params)) for k in node.parameters]
    error = program.error

    def insert_op(state, args, out):
        name = name_of(args, state)
        if type(name) is not str:
            raise error(node, f"i() needs a primitive name (a string), got a {type_name(name)}")
        if assets is not None and (is_asset_name(name) or (cga and not is_template(name))):
            return assets(state, args, out)
        if node.options:
            raise error(node, f"i({name!r}): a template primitive takes key=value parameters only")
        values = {key: value(args, state) for key, value in keywords}
        scope = state.shape.scope
        if name == "box" and not values:
            # The box primitive is exactly the block a 3D leaf makes: skip the registry.
            state.shape = Shape(scope, MASS)
            return True
        try:
            resolved = resolve_primitive(name, values)
        except (GeometryError, OptionError) as exc:
            raise error(node, str(exc)) from None
        state.shape = Shape(scope, INSERT, insert=(name, resolved, node))
        return True

    return insert_op
