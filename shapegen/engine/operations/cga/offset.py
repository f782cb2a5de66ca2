"""CityEngine's ``offset(distance[, all|inside|border])`` on every face of a shape.

Each face is laid in its own plane (:func:`~shapegen.engine.operations.cga.polygons.
face_frames`); :func:`shapegen.geometry.polygon2d.offset` (or ``offset_with_holes`` for a face
with holes) gives the inside and the border faces, and they come back as one shape whose scope
keeps the orientation and fits them. Without a selector both are kept, with the vertices they
share welded, so ``comp(f) { inside : ... | border : ... }`` tells them apart by adjacency
(border faces have an edge no other face has).
"""

from __future__ import annotations

__all__ = ["compile_offset"]

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.operations.cga.arguments import number, plain_arguments, selector_name
from shapegen.engine.operations.cga.polygons import face_frames, face_holes, flat_shape
from shapegen.engine.operations.registry import operation
from shapegen.engine.shapes.shape import FACE, MASS
from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d
from shapegen.grammar import ast


@operation("offset")
def compile_offset(program, node: ast.Operation, params):
    """``offset(distance[, all|inside|border])``."""
    values = plain_arguments(program, node, range(1, 3), block=True)
    if node.branches:
        raise program.error(node, "offset() takes no { ... } block; use comp(f) after it")
    distance = number(program, node, values[0], params, "the distance")
    keep = "all"
    if len(values) == 2:
        keep = selector_name(values[1]) or ""
        if keep not in ("all", "inside", "border"):
            raise program.error(node, "offset()'s second argument is all, inside or border")

    def offset_op(state, args, out):
        d = distance(args, state)
        faces = []
        shape = state.shape
        if shape.kind in ("edge", "vertex"):
            raise program.operation_error(
                node, "offset(): the shape has no faces (an edge or a vertex of comp())"
            )
        if shape.kind not in (FACE, MASS):
            raise program.error(node, "offset() cannot offset an inserted primitive's faces")
        holes = []  # each face's holes (an inside face of a face with holes has them)
        frames = face_frames(shape)
        for (frame, polygon), rings in zip(frames, face_holes(shape), strict=True):
            try:
                if rings:
                    result = polygon2d.offset_with_holes(polygon, rings, d)
                else:
                    result = polygon2d.offset(polygon, d)
            except GeometryError as exc:
                raise program.operation_error(node, f"offset({d:g}): {exc}") from None
            if keep in ("all", "inside"):  # a ring of no corners: an offset of 1e-320 m
                inside = [k for k, p in enumerate(result.inside) if len(p) >= 3]
                faces += [frame.lift(result.inside[k]) for k in inside]
                holes += [
                    [frame.lift(h) for h in result.inside_holes[k]] if result.inside_holes else []
                    for k in inside
                ]
            if keep in ("all", "border"):
                border = [frame.lift(p) for p in result.border if len(p) >= 3]
                faces += border
                holes += [[] for _ in border]
        if not faces:  # CityEngine: "offset(): no face selected, ignoring operation"
            state.run.warn(
                f"offset({d:g}, {keep}) left no face; the operation is ignored, as CityEngine "
                f"does (rules: {format_chain(state.rule_path)})"
            )
            return True
        state.shape = flat_shape(shape, faces, shape.kind, holes)
        return True

    return offset_op
