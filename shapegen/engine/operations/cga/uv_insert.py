"""``insertAlongUV(uvSet, filePath, height, heightDirection, heightAlignment)``
(op_insertAlongUV), approximated: shapegen keeps no texture coordinates.

The reference maps the asset's x-span to u in [0, 1] (repeated), its z-span to -v and its
y-span to ``height``, then cuts and bends it onto the shape's uv space. shapegen takes the uv
space as 0..1 over the face's scope, as its UV split does: u along the scope's x, v along the
face's other axis; the asset is inserted once, stretched over the face, ``height`` along the
scope's y (the default ``scope.y``; the face's normal when y lies in the face or with
``vertex.normal``), its bottom on the face (``alignPosition``) or its height measured from its
origin (``keepPosition``). On a shape that is not flat (a mass, a curved surface) the uv space
is taken as 0..1 over each of its triangles and quads (the reference maps the asset "only onto
triangles and quads"): the asset is laid once on each, bent over it (u along the face's first
edge, v along its last, bilinearly between the corners) and raised by ``height`` along the
face's interpolated vertex normals (``vertex.normal``) or the scope's y (``scope.y``); faces of
more corners get nothing. Every use is a warning of the derivation saying so. A file not found
or of a format shapegen does not read gives a box of the same size, as ``i()`` does.
"""

from __future__ import annotations

__all__ = ["compile_insert_along_uv"]

import numpy as np

from shapegen.engine.operations.cga.arguments import argument_word
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.project.asset_files import find_asset, load_asset
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.errors import GeometryError
from shapegen.geometry.mesh import Mesh
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_REL

_DIRECTIONS = ("scope.y", "vertex.normal")
_ALIGNMENTS = ("alignPosition", "keepPosition")
_APPROXIMATION = (
    "shapegen keeps no texture coordinates: the asset is inserted once over the face's scope "
    "(uv taken as 0..1 over it), not cut and bent along the uvs"
)
_ON_FACES = (
    "shapegen keeps no texture coordinates: on a shape that is not flat the asset is laid once "
    "on each triangle and quad (uv taken as 0..1 over each), not cut and bent along the uvs"
)


@operation(
    "insertAlongUV",
    partial=f"{_APPROXIMATION}; on a shape that is not flat, once on each triangle and quad",
)
def compile_insert_along_uv(program, node, params):
    arguments = [a.value for a in node.arguments]
    if len(arguments) not in (3, 5) or node.branches:
        raise program.error(
            node,
            "insertAlongUV() takes (uvSet, filePath, height) or "
            "(uvSet, filePath, height, heightDirection, heightAlignment)",
        )
    words = []
    for expression, allowed, what in zip(
        arguments[3:],
        (_DIRECTIONS, _ALIGNMENTS),
        ("heightDirection", "heightAlignment"),
        strict=False,
    ):
        word = argument_word(expression)
        if word not in allowed:
            raise program.error(
                node, f"insertAlongUV()'s {what} is one of {', '.join(allowed)}; got {word!r}"
            )
        words.append(word)
    keep_position = words[1:] == ["keepPosition"]
    along_normals = words[:1] == ["vertex.normal"]
    uv_set = program.number(node, arguments[0], params, "insertAlongUV()'s uvSet")
    name_of = program.expressions.compile(arguments[1], params)
    height_of = program.number(node, arguments[2], params, "insertAlongUV()'s height")
    rule_file = getattr(getattr(node, "location", None), "file", None) or program.grammar.filename
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def insert_along_uv(state, args, out):
        layer, name, height = uv_set(args, state), name_of(args, state), height_of(args, state)
        if layer != int(layer) or not 0 <= layer <= 9:
            raise error(node, f"insertAlongUV()'s uvSet is a whole number 0..9, got {layer:g}")
        if type(name) is not str:
            raise error(node, "insertAlongUV() needs a file name")
        shape = state.shape
        if shape.kind not in (FACE, MASS) or shape.mesh().n_faces == 0:
            raise program.error(node, "insertAlongUV() needs a shape with faces (texture space)")
        if shape.kind == MASS:
            warn_at(state, node, f"insertAlongUV(): {_ON_FACES}")
            mesh = _asset(state, node, name, rule_file)
            state.shape = _laid_on_faces(mesh, shape, float(height), keep_position, along_normals)
            return True
        warn_at(state, node, f"insertAlongUV(): {_APPROXIMATION}")
        mesh = _asset(state, node, name, rule_file)
        state.shape = _laid(mesh, shape, float(height), keep_position)
        return True

    return insert_along_uv


def _asset(state, node, name: str, rule_file: str | None) -> Mesh:
    """The asset's mesh, or the unit cube (with a warning) for one shapegen cannot load."""
    path = find_asset(name, rule_file) if name and not name.startswith("builtin:") else None
    problem = "not found" if path is None else None
    if path is not None:
        try:
            return load_asset(path)
        except (GeometryError, OSError, ValueError) as exc:
            problem = f"not read ({exc})"
    if name == "builtin:cube":
        return Mesh.box((1.0, 1.0, 1.0))
    warn_at(state, node, f"insertAlongUV(): asset {name!r} {problem}; a box takes its place")
    return Mesh.box((1.0, 1.0, 1.0))


def _laid(mesh: Mesh, shape: Shape, height: float, keep_position: bool) -> Shape:
    """``mesh`` (asset coordinates, y up) stretched over the face ``shape``: x along u (the
    scope's x), z along -v (the face's other axis), y by ``height`` along the height axis."""
    scope = shape.scope
    normal = shape.normal_axis
    v_axis = next(k for k in (1, 2, 0) if k not in (0, normal)) if normal != 0 else 2
    u_axis = 0 if normal != 0 else 1
    up_axis = 1 if normal == 1 else normal  # the scope's y, unless y lies in the face
    lo, hi = mesh.bounds()
    extent = np.where(hi - lo > 0, hi - lo, 1.0)
    points = mesh.vertices
    local = np.zeros_like(points)
    local[:, u_axis] = (points[:, 0] - lo[0]) / extent[0] * scope.size[u_axis]
    local[:, v_axis] = (hi[2] - points[:, 2]) / extent[2] * scope.size[v_axis]  # z to -v
    base = 0.0 if keep_position else lo[1]
    local[:, up_axis] = (points[:, 1] - base) / extent[1] * height
    faces = mesh.faces
    handed = np.eye(3)[[u_axis, up_axis, v_axis]]
    if np.linalg.det(handed) > 0:  # z to -v keeps the turn of the faces only in a mirror
        faces = tuple(tuple(reversed(f)) for f in faces)
    low, high = local.min(axis=0), local.max(axis=0)
    new_scope = Scope(scope.origin + scope.rotation @ low, scope.rotation, high - low)
    flat = [k for k in range(3) if high[k] - low[k] <= 0]
    placed = Mesh(local - low, faces)
    if flat:
        return Shape.with_geometry(new_scope, placed, FACE, flat[0])
    return Shape.with_geometry(new_scope, placed, MASS)


def _laid_on_faces(
    mesh: Mesh, shape: Shape, height: float, keep_position: bool, along_normals: bool
) -> Shape:
    """``mesh`` (asset coordinates, y up) laid once on each triangle and quad of ``shape``: its
    x-span along u (the face's first edge), its z-span along -v (from the face's last corner
    back to its first), its y-span ``height`` along the vertex normals or the scope's y."""
    target = shape.mesh()
    lo, hi = mesh.bounds()
    extent = np.where(hi - lo > 0, hi - lo, 1.0)
    u = (mesh.vertices[:, 0] - lo[0]) / extent[0]
    v = (hi[2] - mesh.vertices[:, 2]) / extent[2]  # z to -v
    base = 0.0 if keep_position else lo[1]
    w = (mesh.vertices[:, 1] - base) / extent[1] * height
    faces = mesh.faces if height >= 0 else tuple(tuple(reversed(f)) for f in mesh.faces)
    normals = _vertex_normals(target) if along_normals else None
    points, laid = [], []
    for face in target.faces:
        if len(face) not in (3, 4):
            continue  # op_insertAlongUV: "only mapped onto triangles and quads"
        corners = list(face) + [face[2]] * (4 - len(face))  # a triangle: its last edge shrunk
        a, b, c, d = target.vertices[corners]
        spot = ((1 - v) * (1 - u))[:, None] * a + ((1 - v) * u)[:, None] * b
        spot += (v * u)[:, None] * c + (v * (1 - u))[:, None] * d
        if normals is None:
            rise = np.tile((0.0, 1.0, 0.0), (len(u), 1))
        else:
            na, nb, nc, nd = normals[corners]
            rise = ((1 - v) * (1 - u))[:, None] * na + ((1 - v) * u)[:, None] * nb
            rise += (v * u)[:, None] * nc + (v * (1 - u))[:, None] * nd
        start = sum(len(p) for p in points)
        points.append(spot + w[:, None] * rise)
        laid.extend(tuple(start + i for i in f) for f in faces)
    scope = shape.scope
    if not points:
        return Shape.with_geometry(
            Scope(scope.origin, scope.rotation, np.zeros(3)), Mesh(np.empty((0, 3)), ()), MASS
        )
    local = np.vstack(points)
    low, high = local.min(axis=0), local.max(axis=0)
    new_scope = Scope(scope.origin + scope.rotation @ low, scope.rotation, high - low)
    flat = [k for k in range(3) if high[k] - low[k] <= 0]
    placed = Mesh(local - low, laid)
    if flat:
        return Shape.with_geometry(new_scope, placed, FACE, flat[0])
    return Shape.with_geometry(new_scope, placed, MASS)


def _vertex_normals(mesh: Mesh) -> np.ndarray:
    """Unit vertex normals: the mean of the unit normals of the faces at each vertex, the
    vertices where faces meet merged first (op_insertAlongUV: "Vertex normals are always
    calculated from the geometry of the current shape ... duplicate vertices must be merged")."""
    keys = np.round(mesh.vertices / (COINCIDENT_REL * max(1.0, mesh.size()))).astype(np.int64)
    _, weld = np.unique(keys, axis=0, return_inverse=True)
    weld = weld.reshape(-1)
    sums = np.zeros((weld.max() + 1, 3))
    for face, normal in zip(mesh.faces, mesh.face_normals(), strict=True):
        np.add.at(sums, weld[list(face)], normal)
    lengths = np.linalg.norm(sums, axis=1)
    sums[lengths > 0] /= lengths[lengths > 0, None]
    return sums[weld]
