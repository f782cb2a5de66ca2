"""``extrude(type, distance)`` (op_extrude): a face made a solid.

- ``face.normal`` (the default; ``extrude(h)``, the parser's
  :class:`~shapegen.grammar.ast.Extrude`): every face along its own normal;
- ``world.up`` / ``world.up.flatTop``: along world y (flatTop: a flat top ``distance`` above the
  lowest corner, below the highest for a negative distance);
- ``vertex.normal``: every vertex along its vertex normal (the mean of the normals of the faces
  that use it), so faces that share an edge stay joined: one bottom and one top per face, sides
  only along the boundary; the scope's y along the first vertex's normal;
- an edge of ``comp(e|fe)`` (``.cga``): along the edge's normal (op_extrude: the mean of the
  adjacent faces' normals for ``comp(e)``, in the face's plane for ``comp(fe)``), a face;
- ``world.x``, ``world.y``, ``world.z`` and ``x``, ``y``, ``z``: the forms deprecated in 2016
  (cga_changelog: "use type world.up instead of axis world.y"), along that world axis, with a
  warning.

The scope follows op_extrude: x kept as far as possible, y along the extrusion, fitted to the
geometry.

The batch form (:func:`batch_extrude`) is ``extrude(h)`` of a lot's flat footprint: every lot's
height as a column, the lot's leaf then the prism of its footprint.
"""

from __future__ import annotations

__all__ = ["batch_extrude", "compile_extrude", "edge_extrusion", "vertex_normal_extrusion"]

import numpy as np

from shapegen.engine.operations.cga.arguments import argument_word
from shapegen.engine.operations.cga.topology import EDGE
from shapegen.engine.operations.registry import Unsupported, batch_form, operation, warn_at
from shapegen.engine.shapes.auto_tags import extruded
from shapegen.engine.shapes.shape import FACE, MASS, Shape, extrude_shape
from shapegen.geometry.extrude import extrude_faces
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.scope_frames import fitted_scope, rotation_keeping_x
from shapegen.grammar import ast
from shapegen.tolerances import BATCH_DOUBT_REL

_EXTRUSION_TYPES = ("face.normal", "vertex.normal", "world.up", "world.up.flatTop")
_WORLD_AXES = {"x": 0, "y": 1, "z": 2}
_DEPRECATED = tuple(f"{prefix}{axis}" for prefix in ("world.", "") for axis in "xyz")


@operation(
    "extrude",
    nodes=(ast.Extrude, ast.Operation),
    partial="an edge of comp(e|fe) is extruded along its normal only",
)
def compile_extrude(program, node: ast.Extrude | ast.Operation, params):
    """``extrude(distance)`` (:class:`~shapegen.grammar.ast.Extrude`), or ``extrude(type,
    distance)`` with one of :data:`_EXTRUSION_TYPES` or a deprecated axis."""
    if type(node) is ast.Extrude:
        return _extrude_along_normals(program, node, params)
    arguments = [a.value for a in node.arguments]
    if len(arguments) not in (1, 2) or node.branches:
        raise program.error(node, "extrude() takes (distance) or (type, distance)")
    kind = "face.normal"
    if len(arguments) == 2:
        kind = argument_word(arguments[0]) or type(arguments[0]).__name__
        if kind not in _EXTRUSION_TYPES + _DEPRECATED:
            raise program.error(
                node, f"extrude()'s type is one of {', '.join(_EXTRUSION_TYPES)}; got {kind!r}"
            )
    distance = program.number(node, arguments[-1], params, "extrude height")
    cityengine = program.cga_dialect
    error = program.error

    def extrude_op(state, args, out):
        shape = state.shape
        if cityengine and shape.kind == EDGE and kind == "face.normal":
            state.shape = extruded(state, shape, edge_extrusion(shape, distance(args, state)))
            return True
        if cityengine and shape.kind in (EDGE, "vertex"):  # vertex.normal, or a vertex
            raise error(
                node, f"extrude({kind}, ...) of an edge or a vertex of comp() is not supported; "
                "extrude(distance) extrudes an edge along its normal"
            )  # fmt: skip
        if shape.kind != FACE and not (cityengine and shape.kind == MASS):
            raise error(node, "extrude() needs a flat shape; this shape is already 3D")
        height = distance(args, state)
        try:
            if kind in _DEPRECATED:
                warn_at(
                    state,
                    node,
                    f"extrude({kind}, ...) is deprecated (cga_changelog 2016.0: use world.up); "
                    f"the face is extruded along the world's {kind[-1]} axis",
                )
                made = _along_world_axis(shape, height, _WORLD_AXES[kind[-1]])
            elif kind == "vertex.normal":
                made = vertex_normal_extrusion(shape, height)
            else:
                made = extrude_shape(shape, height, cityengine, kind)
            state.shape = extruded(state, shape, made)
        except ValueError as exc:
            raise program.operation_error(node, str(exc)) from None
        return True

    return extrude_op


def _extrude_along_normals(program, node: ast.Extrude, params):
    """``extrude(distance)``: a flat shape along its faces' normals (an edge of ``comp(e|fe)``
    along its normal, in ``.cga``)."""
    height = program.number(node, node.height, params, "extrude height")
    error, operation_error = program.error, program.operation_error
    cityengine = program.cga_dialect

    def extrude_op(state, args, out):
        shape = state.shape
        if cityengine and shape.kind == EDGE:  # an edge of comp(e|fe): a face
            state.shape = extruded(state, shape, edge_extrusion(shape, height(args, state)))
            return True
        if shape.kind != FACE and not (cityengine and shape.kind == MASS):
            raise error(
                node,
                "extrude() needs a flat shape (the lot or a comp(f) face); "
                "this shape is already 3D",
            )
        try:
            state.shape = extruded(
                state, shape, extrude_shape(shape, height(args, state), cityengine)
            )
        except ValueError as exc:
            raise operation_error(node, str(exc)) from None
        return True

    return extrude_op


@batch_form("extrude")
def batch_extrude(program, node: ast.Extrude | ast.Operation, params):
    """``extrude(h)`` of the lots' flat footprints: each lot's height (a number shared by the
    lots or a column), which must be clearly up for the batch's prism to be the one-shape
    derivation's leaf (a height in doubt falls back)."""
    if type(node) is not ast.Extrude:
        raise Unsupported(f"extrude({node.arguments[0].value}, ...)")

    def extrude_batch(batch, out):
        if batch.height is not None:
            raise Unsupported("extrude() of a 3D shape")
        value = batch.value(node.height)
        if type(value) is not float and not (
            isinstance(value, np.ndarray) and value.dtype == np.float64
        ):
            raise Unsupported("extrude() of a value that is not a number")
        height = np.broadcast_to(np.asarray(value, dtype=float), (batch.size,)).copy()
        # a height near 0 or below: the one-shape derivation's prism may differ (flipped faces,
        # a flat leaf), so those lots go one at a time
        sizes = batch.footprints.span[batch.index]
        batch.give_up(
            ~(np.isfinite(height) & (height > BATCH_DOUBT_REL * sizes)),
            "an extrusion not clearly up",
        )
        batch.height = height
        return True

    return extrude_batch


def edge_extrusion(shape: Shape, height: float) -> Shape:
    """An edge shape of ``comp(e|fe)`` extruded by ``height`` (m) along its normal (the scope's
    z, op_extrude's "default extrusion direction" of an edge): a quad face whose scope has x
    along the edge and y along the extrusion."""
    scope = shape.scope
    start, end = scope.to_world(shape.mesh().vertices[:2])
    x, normal = scope.rotation[:, 0], scope.rotation[:, 2]
    rotation = np.column_stack([x, normal, np.cross(x, normal)])
    rise = height * normal
    corners = np.array([start, end, end + rise, start + rise])
    new_scope, local = fitted_scope(corners, rotation)
    quad = Mesh(local, [(0, 1, 2, 3) if height >= 0 else (3, 2, 1, 0)])
    return Shape.with_geometry(new_scope, quad, FACE, 2)


def _solid(shape: Shape, prism: Mesh, y_axis: np.ndarray) -> Shape:
    """The extruded ``prism`` (scope coordinates of ``shape``) in a scope whose y runs along
    ``y_axis`` (world) and whose x is the old x as far as possible, fitted to it."""
    if prism.n_faces == 0:
        raise ValueError("extrude() of a face with no area")
    scope = shape.scope
    rotation = rotation_keeping_x(scope.rotation[:, 0], y_axis)
    new_scope, local = fitted_scope(scope.to_world(prism.vertices), rotation)
    return Shape.with_geometry(new_scope, Mesh(local, prism.faces), MASS)


def _along_world_axis(shape: Shape, height: float, axis: int) -> Shape:
    direction = np.eye(3)[axis]
    if axis == 1:
        return extrude_shape(shape, height, True, "world.up")
    local = shape.scope.rotation.T @ direction
    prism = extrude_faces(shape.mesh(), height, local)
    return _solid(shape, prism, direction)


def vertex_normals(mesh: Mesh) -> np.ndarray:
    """``(n, 3)`` unit normals per vertex: the mean of the unit normals of the faces using it
    (0 for an unused vertex)."""
    normals = np.zeros((mesh.n_vertices, 3))
    for k, normal in enumerate(mesh.face_normals()):
        for i in mesh.faces[k]:
            normals[i] += normal
    lengths = np.linalg.norm(normals, axis=1)
    return np.divide(
        normals, lengths[:, None], out=np.zeros_like(normals), where=lengths[:, None] > 0
    )


def vertex_normal_extrusion(shape: Shape, height: float) -> Shape:
    """``extrude(vertex.normal, height)`` of a flat shape: the faces' vertices moved by
    ``height`` (m) along their vertex normals; faces in the order of op_extrude's prism (each
    face turned as the bottom, then each moved as the top, then the sides along the edges
    that only one face uses), turned so that the solid faces out."""
    mesh = shape.mesh()
    n = mesh.n_vertices
    normals = vertex_normals(mesh)
    vertices = np.vstack([mesh.vertices, mesh.vertices + height * normals])
    bottoms = [(f[1], f[0], *reversed(f[2:])) for f in mesh.faces]
    tops = [tuple(n + i for i in f) for f in mesh.faces]
    uses: dict[tuple[int, int], int] = {}
    for f in mesh.faces:
        for a, b in zip(f, f[1:] + f[:1], strict=True):
            uses[(min(a, b), max(a, b))] = uses.get((min(a, b), max(a, b)), 0) + 1
    sides = [
        (a, b, n + b, n + a)
        for f in mesh.faces
        for a, b in zip(f, f[1:] + f[:1], strict=True)
        if uses[(min(a, b), max(a, b))] == 1
    ]
    solid = Mesh(vertices, [*bottoms, *tops, *sides])
    if height < 0:
        solid = solid.reversed()
    first = shape.scope.rotation @ normals[mesh.faces[0][0]] if mesh.n_faces else None
    if first is None or not first.any():
        raise ValueError("extrude(vertex.normal, ...) of a shape without faces")
    return _solid(shape, solid, first)
