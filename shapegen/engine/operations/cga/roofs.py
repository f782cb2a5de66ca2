"""CityEngine's roofs, taper and envelope: roofGable, roofHip, roofShed, roofPyramid, roofRidge.

Each builds a roof on every face of a flat shape (:mod:`shapegen.geometry.roofs` does the
geometry in the face's plane) and makes the shape a 3D one holding the roof meshes. The scope
follows CityEngine: x as close to the old x as the first face's plane allows, y along that
face's normal, z = x × y, sized to fit the roof; ``s('1, h, '1)`` after a roof then scales its
height. A rectangle's roof is a closed convex solid (it becomes a block); other roofs are
surfaces.
"""

from __future__ import annotations

__all__ = ["roof_shape"]

import numpy as np

from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.cga.arguments import number, plain_arguments, selector_name
from shapegen.engine.operations.cga.polygons import (
    array_elements,
    edge_object_quadrants,
    face_frames,
    face_holes,
    flat_faces,
)
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.shape import MASS, Shape
from shapegen.engine.shapes.tags import ComponentTags, Pending, resolved_tags
from shapegen.errors import GeometryError
from shapegen.geometry import roofs
from shapegen.geometry.envelope import envelope
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.ridge_roof import roof_ridge
from shapegen.geometry.roof_mesh import RoofMesh
from shapegen.geometry.scope_frames import fitted_scope, rotation_keeping_x
from shapegen.grammar import ast
from shapegen.limits import check_clock, limit_hint
from shapegen.tolerances import COSINE_SLACK


def roof_shape(
    parent: Shape,
    built: list[tuple[object, RoofMesh]],
    keep_axes: bool = False,
    tagged: bool = True,
    sheets: bool = False,
) -> Shape:
    """The 3D shape holding the roofs ``(frame, RoofMesh)`` built on ``parent``'s faces: its
    scope's y along the face normal (the roofs), or the parent's axes (``keep_axes``: the
    envelope, whose scope PyPRT only resizes; candler's ventilation moves along the envelope's
    scope z to its top). ``tagged``: with its auto-tags (the derivation keeps tags).
    ``sheets``: each roof's bottom, slopes and walls (its faces by their auto-tag, roof.bottom,
    roof.top, roof.side...) are sheets (:attr:`Mesh.sheets`) that share no edge, as
    CityEngine's runtime builds a roofX()'s (measured by comp(e): a gable's slopes meet neither
    its bottom nor its gable ends); a taper's or an envelope's faces are one joined surface
    (measured the same way)."""
    points, faces, holes = [], [], []
    start = 0
    for frame, mesh in built:
        points.append(frame.lift(mesh.vertices[:, :2], mesh.vertices[:, 2]))
        faces += [tuple(start + i for i in face) for face in mesh.faces]
        if mesh.holes:
            holes += [tuple(tuple(start + i for i in r) for r in rs) for rs in mesh.holes]
        else:
            holes += [()] * len(mesh.faces)
        start += len(mesh.vertices)
    local = np.concatenate(points)
    normal = parent.scope.rotation @ built[0][0].n
    frame = (
        parent.scope.rotation
        if keep_axes
        else rotation_keeping_x(parent.scope.rotation[:, 0], normal)
    )
    scope, fitted = fitted_scope(parent.scope.to_world(local), frame)
    names = [(k, tag) for k, (_, mesh) in enumerate(built) for tag in mesh.tags]
    tags = Pending(parent, _auto_tags(names, len(built))) if tagged else None
    parts = [f"{k}:{tag.split('.')[1]}" for k, (_, m) in enumerate(built) for tag in m.tags]
    mesh = Mesh(fitted, faces, holes if any(holes) else (), parts if sheets else ())
    return Shape(scope, MASS, 1, None, mesh, tags)


def _auto_tags(names: list[tuple[int, str]], count: int):
    """The rule of a roof's tags (cga_componentTags): each face its auto-tag (``roof.top``,
    ``taper.side``...), after the tags of the face it was built on (when the roofs are one per
    face of the parent); the parent's auto-tags of the same operation are replaced."""

    def tags(parent, shape):
        old = resolved_tags(parent)
        prefix = names[0][1].split(".")[0] if names else ""
        sources = old.without_prefix(prefix).faces if old is not None else ()
        if len(sources) != count:
            sources = ()
        return ComponentTags(
            tuple(
                tuple(dict.fromkeys((*(sources[k] if sources else ()), name))) for k, name in names
            )
        )

    return tags


def _value_type(node) -> tuple[str, list]:
    """``("angle" | "height", remaining argument expressions)``."""
    values = [a.value for a in node.arguments]
    first = selector_name(values[0]) if values else None
    if first in ("byAngle", "byHeight"):
        return ("angle" if first == "byAngle" else "height"), values[1:]
    return "angle", values


def _flag(program, node, expression, params, what: str):
    compiled = program.expressions.compile(expression, params)

    def flag(args, state):
        value = compiled(args, state)
        if type(value) is not bool:
            raise program.error(node, f"{what} must be true or false, got a {type_name(value)}")
        return value

    return flag


_SIGNATURES = {
    # the optional arguments after the angle (or the value type and value), in order
    "roofHip": ("overhang", "even"),
    "roofGable": ("overhang_x", "overhang_y", "even", "index"),
    "roofShed": ("index",),
    "roofPyramid": (),
    "roofRidge": (),
}


@operation("roofHip", "roofGable", "roofShed", "roofPyramid", "roofRidge")
def compile_roof(program, node: ast.Operation, params):
    """``roofX(angle, ...)`` or ``roofX(byAngle|byHeight, value, ...)``."""
    plain_arguments(program, node, range(len(node.arguments) + 1))  # plain, no block
    kind, values = _value_type(node)
    optional = _SIGNATURES[node.name]
    if node.name == "roofGable" and len(values) < len(node.arguments):
        optional = optional[:3]  # the byAngle/byHeight form has no index
    if not 1 <= len(values) <= 1 + len(optional):
        raise program.error(
            node,
            f"{node.name}() takes an angle (or byAngle/byHeight and a value)"
            + (f", then up to: {', '.join(optional)}" if optional else " only")
            + f"; got {len(node.arguments)} arguments",
        )
    value = number(program, node, values[0], params, f"the {kind}")
    extras = {}
    for name, expression in zip(optional, values[1:], strict=False):
        if name == "even":
            extras[name] = _flag(program, node, expression, params, f"{node.name} even")
        else:
            extras[name] = number(program, node, expression, params, f"the {name}")
    build = {
        "roofHip": roofs.roof_hip,
        "roofGable": roofs.roof_gable,
        "roofShed": roofs.roof_shed,
        "roofPyramid": roofs.roof_pyramid,
        "roofRidge": roof_ridge,
    }[node.name]
    cga = program.cga_dialect

    def roof_op(state, args, out):
        options = {k: f(args, state) for k, f in extras.items()}
        if "index" in options:
            options["index"] = int(options["index"])
        amount = value(args, state)
        _check_roof_faces(program, node, state)
        built = []
        if cga and state.shape.kind == MASS:  # op_roof*: a roof on each face of the geometry
            faces = face_frames(state.shape)
        else:
            faces = flat_faces(state, node, program, f"{node.name}()")
        # roofShed, roofHip, roofGable and roofRidge keep a face's holes; roofPyramid builds on
        # the outer ring, as CityEngine's runtime does (tests/data/prt_roofs.json)
        keeps = node.name != "roofPyramid"
        rings = face_holes(state.shape) if keeps else [()] * len(faces)
        for (frame, polygon), holes in zip(faces, rings, strict=True):
            check_clock()
            if len(holes):
                options["holes"] = holes
            else:
                options.pop("holes", None)
            if node.name == "roofGable" and "index" in options:
                if not roofs.gable_index_applies(polygon, holes):  # PyPRT's words
                    warn_at(state, node, "roofGable(): Gable roof: can not apply index!")
            try:
                if kind == "angle":
                    mesh = build(polygon, amount, **options)
                else:
                    mesh = build(polygon, height=amount, **options)
            except GeometryError as exc:
                raise program.operation_error(node, f"{node.name}(): {exc}") from None
            built.append((frame, mesh))
        if not built:
            return False
        state.shape = roof_shape(state.shape, built, tagged=state.run.tags, sheets=True)
        return True

    return roof_op


def _check_roof_faces(program, node, state) -> None:
    """Refuse, before any roof is built, roofs whose faces would pass ``max_mesh_faces``: a
    roof on a face of k corners has at least k + 1 faces (k slopes or walls, a bottom)."""
    faces = state.shape.mesh().faces
    least = len(faces) + sum(map(len, faces))
    limits = state.run.limits
    if least > limits.max_mesh_faces:
        raise program.error(
            node,
            f"{node.name}(): the roofs on the shape's {len(faces)} faces would have at least "
            f"{least} faces, more than {limits.max_mesh_faces} "
            + limit_hint("max_mesh_faces", limits),
        )


@operation("taper")
def compile_taper(program, node: ast.Operation, params):
    """``taper(height)``: a pyramid over the first face, apex above its centroid."""
    (height_expression,) = plain_arguments(program, node, range(1, 2), block=True)
    height = number(program, node, height_expression, params, "the height")

    def taper_op(state, args, out):
        faces = flat_faces(state, node, program, "taper()")
        if not faces:
            return False
        frame, polygon = faces[0]  # CityEngine tapers the first polygon only
        try:
            mesh = roofs.taper(polygon, height(args, state))
        except GeometryError as exc:
            raise program.operation_error(node, f"taper(): {exc}") from None
        state.shape = roof_shape(state.shape, [(frame, mesh)], tagged=state.run.tags)
        return True

    return taper_op


PUNCH_FAILED = (
    "Punching holes failed: a hole's edge lies on a crease of the envelope's upper faces; "
    "its faces are cut, its inner walls left out (CityEngine's runtime: "
    "addInnerSideFacesAndNonplanarizeHoles(): failed to extract points in plane)"
)
_ENVELOPE_SIDES = {
    2: ("front",),
    4: ("front", "back"),
    6: ("front", "back", "side"),
    8: ("front", "back", "right", "left"),
}


@operation(
    "envelope",
    partial="refused: world.up on a face that does not face up, and sloped sides of "
    "different base heights",
)
def compile_envelope(program, node: ast.Operation, params):
    """``envelope(normal|world.up, maxHeight, frontBaseHeight, frontAngle[, back...[, side...
    | right..., left...]])`` or ``envelope(direction, maxHeight, baseHeights, angles)``."""
    values = plain_arguments(program, node, range(len(node.arguments) + 1))
    # cga_changelog: the deprecated signatures without a direction (3, 5, 7 or 9 arguments)
    deprecated = len(values) % 2 == 1 and selector_name(values[0]) not in ("normal", "world.up")
    if deprecated:
        values = [ast.Name("normal"), *values]
    if len(values) - 2 not in _ENVELOPE_SIDES:
        raise program.error(
            node, f"envelope() takes 4, 6, 8 or 10 arguments, got {len(values)}"
        )  # fmt: skip
    direction = selector_name(values[0])
    if direction not in ("normal", "world.up"):
        raise program.error(node, "envelope()'s direction is normal or world.up")
    max_height = number(program, node, values[1], params, "the maximum height")
    pairs = [program.expressions.compile(v, params) for v in values[2:]]
    sides = _ENVELOPE_SIDES[len(values) - 2]

    def per_edge(value, n: int, default: float, what: str) -> np.ndarray:
        if array_elements(value) is not None:
            value = array_elements(value)
            out = np.full(n, default)
            for k, item in enumerate(value[:n]):
                if type(item) is bool or not isinstance(item, (int, float)):
                    raise program.error(node, f"envelope {what} must be numbers, got {item!r}")
                out[k] = float(item)
            return out
        if type(value) is bool or not isinstance(value, (int, float)):
            raise program.error(node, f"envelope {what} must be numbers, got {type_name(value)}")
        return np.full(n, float(value))

    def envelope_op(state, args, out):
        if deprecated:
            warn_at(
                state, node, "envelope() without a direction is deprecated (cga_changelog: "
                "signatures without direction parameter); it is built along the normal"
            )  # fmt: skip
        top = max_height(args, state)
        evaluated = [f(args, state) for f in pairs]
        built = []
        faces = flat_faces(state, node, program, "envelope()")
        # op_envelope's "side faces from holes": each hole punched through the envelope
        for (frame, polygon), holes in zip(faces, face_holes(state.shape), strict=True):
            if direction == "world.up":
                up = state.shape.scope.rotation @ frame.n
                if up[1] < 1 - COSINE_SLACK:
                    raise program.error(
                        node, "envelope(world.up, ...) on a face that does not face up is not "
                        "supported; use envelope(normal, ...)"
                    )  # fmt: skip
            n = len(polygon)
            # op_envelope: the edges are classed by the street.* selectors, which fall back
            # to object.* (the start shape's axes), not by the scope's axes
            quadrants = edge_object_quadrants(
                state.shape, getattr(state.run, "object_rotation", None), frame, polygon
            )
            if len(pairs) == 2 and array_elements(evaluated[0]) is not None:
                base = per_edge(evaluated[0], n, 0.0, "base heights")
                angle = per_edge(evaluated[1], n, 90.0, "angles")
            else:
                base, angle = np.zeros(n), np.full(n, 90.0)
                for side, k in zip(sides, range(0, len(evaluated), 2), strict=True):
                    chosen = {"side": ("left", "right")}.get(side, (side,))
                    mask = np.array([q in chosen for q in quadrants])
                    base[mask] = per_edge(evaluated[k], 1, 0.0, "base heights")[0]
                    angle[mask] = per_edge(evaluated[k + 1], 1, 90.0, "angles")[0]
            try:
                mesh = envelope(polygon, top, base, angle, holes)
            except GeometryError as exc:
                raise program.operation_error(node, f"envelope(): {exc}") from None
            if mesh.punch_failed:  # CityEngine's runtime's warning, and its model
                warn_at(state, node, f"envelope(): {PUNCH_FAILED}")
            built.append((frame, mesh))
        if not built:
            return False
        state.shape = roof_shape(state.shape, built, keep_axes=True, tagged=state.run.tags)
        return True

    return envelope_op
