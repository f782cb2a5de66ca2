"""``extrude(type, distance)`` (op_extrude): a face made a solid, along its normal or up."""

from __future__ import annotations

__all__ = ["compile_extrude"]

from shapegen.engine.cga_ops import compiles
from shapegen.engine.cga_ops.scope_ops import argument_word
from shapegen.engine.shape import FACE, extrude_shape
from shapegen.grammar import ast

_EXTRUSION_TYPES = ("face.normal", "world.up", "world.up.flatTop")


@compiles("extrude")
def compile_extrude(program, node: ast.Operation, params):
    """``extrude(type, distance)``: op_extrude's extrusion types ``face.normal`` (the default),
    ``world.up`` and ``world.up.flatTop``; ``vertex.normal`` is refused."""
    arguments = [a.value for a in node.arguments]
    if len(arguments) not in (1, 2) or node.branches:
        raise program.error(node, "extrude() takes (distance) or (type, distance)")
    kind = "face.normal"
    if len(arguments) == 2:
        kind = argument_word(arguments[0]) or type(arguments[0]).__name__
        if kind == "vertex.normal":
            raise program.error(node, "extrude(vertex.normal, ...) is not supported by shapegen")
        if kind not in _EXTRUSION_TYPES:
            raise program.error(
                node, f"extrude()'s type is one of {', '.join(_EXTRUSION_TYPES)}; got {kind!r}"
            )
    distance = program._number(node, arguments[-1], params, "extrude height")
    cityengine = program.cga_dialect
    error = program.error

    def extrude_op(state, args, out):
        shape = state.shape
        if shape.kind != FACE:
            raise error(node, "extrude() needs a flat shape; this shape is already 3D")
        try:
            state.shape = extrude_shape(shape, distance(args, state), cityengine, kind)
        except ValueError as exc:
            raise error(node, str(exc)) from None
        return True

    return extrude_op
