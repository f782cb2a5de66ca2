"""Operations and faces with holes: those that keep them, and a refusal for the others.

A face may have holes (:attr:`~shapegen.geometry.mesh.Mesh.holes`). An operation that builds
new geometry from a shape's faces and knows nothing of holes would drop them unseen, a wrong
model; so every operation not listed here as keeping them is wrapped, when the rule is
compiled, in a refusal of a shape with holes: a CGA error in ``.cga`` (the shape carries on, as
CityEngine's runtime does after an error), naming ``deleteHoles()``.
"""

from __future__ import annotations

__all__ = ["keeps_holes", "refusing_holes"]

from shapegen.engine.derivation.state import Operation
from shapegen.grammar import ast

# The operations that keep a face's holes: those that move, turn or scale the geometry as a
# whole, read it or set what it looks like, and those built for holes (extrude, comp, whose
# comp(h) makes a shape of each hole and whose e, fe, v and fv list the holes' rings, split,
# offset, the roofs hip, gable, ridge and shed, setback, setbackPerEdge, setbackToArea,
# shapeL/U/O and innerRectangle; deleteHoles removes them, roofPyramid builds on the outer ring
# as CityEngine's runtime does, and so does taper; envelope punches them through its volume;
# trim() cuts them with the face: tests/data/prt_holes.json, prt_setback.json, prt_roofs.json,
# prt_setback_holes.json, prt_comp_holes.json, prt_taper_envelope.json, prt_trim_holes.json).
_HOLE_NODES = (
    ast.Successor, ast.Nil, ast.Push, ast.Extrude, ast.Comp, ast.Translate, ast.Scale,
    ast.Rotate, ast.Center, ast.Label, ast.Set, ast.Print, ast.Report, ast.Insert, ast.Split,
)  # fmt: skip
_HOLE_OPERATIONS = frozenset(
    (
        "deleteHoles", "offset", "setback", "setbackPerEdge", "setbackToArea", "shapeL", "shapeU",
        "shapeO", "innerRectangle", "innerRect", "comp", "roofPyramid", "roofShed", "roofHip",
        "roofGable", "roofRidge", "taper", "envelope", "trim",
        "color", "texture",
        "setMaterial", "resetMaterial", "setupProjection", "projectUV", "deleteUV", "tileUV",
        "translateUV", "scaleUV", "rotateUV", "offsetUV", "normalizeUV", "copyUV",
        "setNormals", "softenNormals", "tag", "deleteTags", "setTagsFromEdgeAttrs",
        "alignScopeToAxes", "alignScopeToGeometry", "rotateScope", "mirror", "mirrorScope",
        "setPivot", "reverseNormals", "translate", "rotate",
        # geometry replaced whole, holes and all (op_primitiveCube...: a primitive in the
        # scope; op_resetGeometry: the start shape, its holes kept) or only its box read
        "primitiveCube", "primitiveCone", "primitiveCylinder", "primitiveDisk", "primitiveQuad",
        "primitiveSphere", "resetGeometry", "alignScopeToGeometryBBox",
    )
)  # fmt: skip


def keeps_holes(node) -> bool:
    """Whether the operation ``node`` keeps (or rightly removes) a face's holes."""
    if isinstance(node, ast.Operation):
        return node.name in _HOLE_OPERATIONS
    return isinstance(node, _HOLE_NODES)


def refusing_holes(operation: Operation, node, program) -> Operation:
    """``operation``, refusing (a CGA error in ``.cga``) a shape whose faces have holes."""
    name = node.name if isinstance(node, ast.Operation) else type(node).__name__.lower()

    def refusing(state, args, out):
        geometry = state.shape.geometry
        if geometry is not None and geometry.holes:
            raise program.operation_error(
                node,
                f"{name}() of a shape whose faces have holes is not supported by shapegen "
                "(deleteHoles() first removes them)",
            )
        return operation(state, args, out)

    return refusing
