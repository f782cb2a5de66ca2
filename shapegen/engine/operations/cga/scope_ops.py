"""CityEngine's scope and geometry operations (op_*.html of the CGA reference).

- ``alignScopeToAxes([axes])``: the scope's axes parallel to the world's (``world.xyz``, the
  default), the object's (``object.xyz``) or one of them (``y``, ``world.y``...: the second axis
  projected as the reference says); the geometry stays where it is and the scope is refitted;
- ``alignScopeToGeometry(yUp|zUp, face, edge)``: the up axis along a face's normal, x along one
  of its edges (a face index, ``largest``, ``world.lowest`` or ``any``; an edge index,
  ``longest`` or ``world.lowest``; negative indices count from the end); the forms deprecated in
  2011 (cga_changelog), ``(upAxis, faceIndex)`` (that face's first edge) and ``(upAxis, auto)``
  (the lowest edge of any face, the longest when all lie at one height), with a warning;
- ``alignScopeToGeometryBBox(xy|yx|xz|zx|yz|zy)``: the two named scope axes turned about the
  third to the minimum-area rectangle around the geometry seen along the third, the first
  named along its longer side;
- ``rotateScope(x, y, z)``: the scope turned (degrees, x then y then z), the geometry not;
- ``mirror(x, y, z)``: the geometry flipped inside its scope along the scope axes given true;
- ``mirrorScope(x, y, z)``: the scope's axes flipped, the geometry not;
- ``setPivot(xyz|yzx|zxy, corner)``: the scope's axes permuted and put at corner 0-7 of the
  scope (0 the origin, 1 +x, 2 +x+z, 3 +z, 4-7 the same above), every axis pointing inside;
- ``reverseNormals()``; ``cleanupGeometry(vertices|edges|faces|all, tolerance)`` merges
  vertices closer than ``tolerance`` metres (0-1, as the reference's 1 m at 1) and drops
  degenerate faces (shared edges of coplanar faces are kept);
- ``resetGeometry()``: the start shape's geometry and scope;
- ``trim()``: the shape's geometry cut to its enabled trim planes
  (:mod:`shapegen.engine.shapes.trim`);
- ``deleteHoles()``: nothing to do, shapegen's faces have no holes;
- ``convexify([maxLength])``: every concave face cut into convex polygons as CityEngine's
  runtime cuts them (:mod:`shapegen.geometry.convex`: the shortest cut along an edge through a
  reflex corner first, new vertices where cuts meet the outline; with ``maxLength`` no cut
  longer than it).
"""

from __future__ import annotations

__all__ = ["argument_word", "refit", "set_scope_pivot"]


import math

import numpy as np

from shapegen.engine.operations.cga.arguments import argument_word, choice, plain_arguments, typed
from shapegen.engine.operations.cga.topology import EDGE, VERTEX
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.shape import FACE, MASS, Shape, rotation_matrix
from shapegen.engine.shapes.trim import apply_trim
from shapegen.geometry.scope_frames import fitted_scope, rotation_keeping_x
from shapegen.grammar import ast
from shapegen.tolerances import COINCIDENT_REL, ROUNDOFF_REL, at_most


def refit(shape: Shape, rotation: np.ndarray) -> Shape:
    """``shape`` with its scope's axes ``rotation`` (columns) and the scope fitted to its
    geometry, which stays where it is in the world."""
    mesh = shape.mesh()
    world = shape.scope.to_world(mesh.vertices)
    scope, local = fitted_scope(world, rotation)
    moved = mesh.moved_to(local)
    if _determinant(shape.scope.r) * _determinant(np.asarray(rotation, float).ravel().tolist()) < 0:
        moved = moved.reversed()
    kind = shape.kind if shape.kind in (FACE, MASS, EDGE, VERTEX) else MASS
    return Shape.with_geometry(scope, moved, kind, shape.normal_axis)


def _determinant(r) -> float:
    """The determinant of a frame given as its 9 entries row by row (its sign tells a mirror):
    in Python floats, a numpy call costing more than the sum."""
    return (
        r[0] * (r[4] * r[8] - r[5] * r[7])
        - r[1] * (r[3] * r[8] - r[5] * r[6])
        + r[2] * (r[3] * r[7] - r[4] * r[6])
    )


def set_scope_pivot(state) -> None:
    """The pivot at the scope's origin, along its axes (attr_pivot: after alignScopeToAxes,
    alignScopeToGeometry(BBox) and setPivot "the scope has zero translation and rotation")."""
    scope = state.shape.scope
    state.pivot = (np.asarray(scope.origin, float), np.asarray(scope.rotation, float))


def shape_with_faces(program, node, state, components: bool = False) -> Shape:
    """The shape ``node`` works on: one with faces, or (``components``) also the edge and vertex
    shapes of ``comp(e|v)`` and ``scatter``, whose scope the operation turns all the same."""
    kind = state.shape.kind
    if kind not in ((FACE, MASS, EDGE, VERTEX) if components else (FACE, MASS)):
        what = (
            "edges or vertices (comp(e|v))" if kind in (EDGE, VERTEX) else "an inserted primitive"
        )
        if kind in (EDGE, VERTEX):  # CityEngine: a CGA error, the shape carries on
            raise program.operation_error(
                node, f"{node.name}() needs a shape with faces, not {what}"
            )
        raise program.error(node, f"{node.name}() needs a shape with faces, not {what}")
    return state.shape


# ---------------------------------------------------------------------------- operations
_WORLD_AXES = ("x", "y", "z", "world.x", "world.y", "world.z", "world.xyz")
_OBJECT_AXES = ("object.x", "object.y", "object.z", "object.xyz")


@operation("alignScopeToAxes")
def compile_align_scope_to_axes(program, node, params):
    arguments = plain_arguments(program, node, (0, 1))
    which = "world.xyz"
    if arguments:
        which = choice(program, node, arguments[0], _WORLD_AXES + _OBJECT_AXES, "the axes")

    def align(state, args, out):
        shape = shape_with_faces(program, node, state, components=True)
        frame = np.eye(3)
        if which.startswith("object."):
            frame = getattr(state.run, "object_rotation", None)
            frame = np.eye(3) if frame is None else frame
        axis = which.split(".")[-1]
        old = shape.scope.rotation
        if axis == "xyz":
            rotation = frame
        elif axis == "y":
            rotation = rotation_keeping_x(old[:, 0], frame[:, 1])
        elif axis == "x":
            # z projected onto the frame's yz-plane, x along the frame's x
            x = frame[:, 0]
            z = old[:, 2] - x * float(old[:, 2] @ x)
            if np.linalg.norm(z) < ROUNDOFF_REL:
                z = frame[:, 2]
            z = z / np.linalg.norm(z)
            rotation = np.column_stack([x, np.cross(z, x), z])
        else:
            # x projected onto the frame's xy-plane, z along the frame's z
            z = frame[:, 2]
            x = old[:, 0] - z * float(old[:, 0] @ z)
            if np.linalg.norm(x) < ROUNDOFF_REL:
                x = frame[:, 0]
            x = x / np.linalg.norm(x)
            rotation = np.column_stack([x, np.cross(z, x), z])
        state.shape = refit(shape, rotation)
        set_scope_pivot(state)
        return True

    return align


_FACE_CHOICES = ("world.lowest", "largest", "any")
_EDGE_CHOICES = ("world.lowest", "longest")


@operation(
    "alignScopeToGeometry",
    partial="edge and vertex shapes (comp(e|v), scatter) are refused when derived",
)
def compile_align_scope_to_geometry(program, node, params):
    arguments = plain_arguments(program, node, (2, 3))
    up = choice(program, node, arguments[0], ("yUp", "zUp"), "the up axis")
    deprecated = None
    if len(arguments) == 2:  # cga_changelog 2011: (upAxis, faceIndex) and (upAxis, auto)
        auto = argument_word(arguments[1]) == "auto"
        deprecated = "auto" if auto else "faceIndex"
        arguments = [arguments[0], ast.Name("any"), ast.Name("auto")] if auto else [
            *arguments, ast.Number(0.0)
        ]  # fmt: skip
    face_word = argument_word(arguments[1])
    edge_word = argument_word(arguments[2])
    if face_word is not None and face_word not in _FACE_CHOICES:
        face_word = None
    if edge_word is not None and edge_word not in (*_EDGE_CHOICES, "auto"):
        edge_word = None
    face_index = (
        None if face_word else typed(program, node, arguments[1], params, float, "the face index")
    )
    edge_index = (
        None if edge_word else typed(program, node, arguments[2], params, float, "the edge index")
    )
    if face_word == "any" and edge_word is None:
        raise program.error(node, "alignScopeToGeometry(): 'any' face needs an edge selector")
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def align(state, args, out):
        shape = shape_with_faces(program, node, state)
        mesh = shape.mesh()
        scope = shape.scope
        world = scope.to_world(mesh.vertices)
        if deprecated is not None:
            warn_at(
                state,
                node,
                f"alignScopeToGeometry(upAxis, {deprecated}) is deprecated (cga_changelog); "
                + ("the lowest edge of any face is taken, the longest when all lie at one "
                   "height" if deprecated == "auto" else "the face's first edge is taken"),
            )  # fmt: skip
        if mesh.n_faces == 0:
            raise error(node, "alignScopeToGeometry() of a shape without faces")
        candidates = range(mesh.n_faces)
        if face_word is None:
            k = int(face_index(args, state))
            if not -mesh.n_faces <= k < mesh.n_faces:
                _wrapped(state, node, f"face index {k}", mesh.n_faces, "faces")
            candidates = [k % mesh.n_faces]
        elif face_word == "largest":
            candidates = [max(range(mesh.n_faces), key=mesh.face_area)]
        elif face_word == "world.lowest":
            candidates = [
                min(range(mesh.n_faces), key=lambda f: (world[list(mesh.faces[f])][:, 1].mean(), f))
            ]
        rule = edge_word
        if edge_word == "auto":  # 2009.2: the longest edge when all lie at one height
            heights = world[:, 1]
            flat = float(np.ptp(heights)) <= COINCIDENT_REL * max(1.0, float(np.abs(world).max()))
            rule = "longest" if flat else "world.lowest"
        best = None
        # an explicit face index (alignScopeToGeometry(yUp, 0, longest)): the first of equally
        # long edges wins, as PyPRT aligns Building_From_FootprintSMALL on rectangles and L's
        # from every corner; over any face the last (simpleRuleDataset's L lots)
        last_wins = rule != "world.lowest" and face_word is not None
        rows = world.tolist()  # the edges' keys in Python floats: a numpy call per edge cost more
        for f in candidates:
            face = mesh.faces[f]
            n = len(face)
            if edge_word is None:
                e = int(edge_index(args, state))
                if not -n <= e < n:
                    _wrapped(state, node, f"edge index {e} of face {f}", n, "edges")
                edges = [e % n]
            else:
                edges = range(n)
            for e in edges:
                a, b = face[e], face[(e + 1) % n]
                if rule == "longest":
                    (ax, ay, az), (bx, by, bz) = rows[a], rows[b]
                    key = -math.sqrt((bx - ax) ** 2 + (by - ay) ** 2 + (bz - az) ** 2)
                elif rule == "world.lowest":
                    key = rows[a][1] + rows[b][1]
                else:
                    key = 0.0
                # Ties, as PyPRT breaks them: among equally long edges the last wins (an L with
                # two longest edges, whichever corner the lot starts at); among equally low ones
                # the first (a rectangle's x along its first edge, from any starting corner)
                if (
                    best is None
                    or key < best[0] - ROUNDOFF_REL
                    or (last_wins and at_most(key, best[0], ROUNDOFF_REL))
                ):
                    best = (key, f, a, b)
        _, f, a, b = best
        a, b = world[a], world[b]
        normal = scope.rotation @ mesh.lone_face_normal(f)
        x = b - a
        if np.linalg.norm(x) == 0 or np.linalg.norm(normal) == 0:
            raise error(node, "alignScopeToGeometry(): the chosen edge or face is degenerate")
        if up == "yUp":
            frame = rotation_keeping_x(x, normal)
        else:
            y_frame = rotation_keeping_x(x, normal)  # x, normal, x cross normal
            frame = np.column_stack([y_frame[:, 0], -y_frame[:, 2], y_frame[:, 1]])
        state.shape = refit(shape, frame)
        set_scope_pivot(state)
        return True

    return align


def _wrapped(state, node, what: str, count: int, things: str) -> None:
    """An index past the end: op_alignScopeToGeometry adjusts negative indices modulo the count
    (and splitAndSetbackPerimeter "too large or negative" ones); taken so, with a warning."""
    warn_at(
        state, node, f"alignScopeToGeometry(): {what} is past the {count} {things}; "
        f"taken modulo {count}"
    )  # fmt: skip


@operation("rotateScope")
def compile_rotate_scope(program, node, params):
    angles = [
        typed(program, node, a, params, float, "an angle")
        for a in plain_arguments(program, node, (3,))
    ]

    def rotate_scope(state, args, out):
        shape = shape_with_faces(program, node, state, components=True)
        turn = rotation_matrix([angle(args, state) for angle in angles])
        state.shape = refit(shape, shape.scope.rotation @ turn)
        return True

    return rotate_scope


def _flips(program, node, params):
    return [
        typed(program, node, a, params, bool, "a flip")
        for a in plain_arguments(program, node, (3,))
    ]


@operation("mirror")
def compile_mirror(program, node, params):
    flips = _flips(program, node, params)

    def mirror(state, args, out):
        shape = shape_with_faces(program, node, state)
        chosen = np.array([flip(args, state) for flip in flips])
        if not chosen.any():
            return True
        mesh = shape.mesh()
        size = shape.scope.size
        factors = np.where(chosen, -1.0, 1.0)
        mirrored = mesh.scaled(factors)
        mirrored = mirrored.moved_to(mirrored.vertices + np.where(chosen, size, 0.0))
        state.shape = Shape.with_geometry(shape.scope, mirrored, shape.kind, shape.normal_axis)
        return True

    return mirror


@operation("mirrorScope")
def compile_mirror_scope(program, node, params):
    flips = _flips(program, node, params)

    def mirror_scope(state, args, out):
        shape = shape_with_faces(program, node, state, components=True)
        chosen = np.array([flip(args, state) for flip in flips])
        if not chosen.any():
            return True
        rotation = shape.scope.rotation * np.where(chosen, -1.0, 1.0)[None, :]
        state.shape = refit(shape, rotation)
        return True

    return mirror_scope


_AXIS_MAPS = {"xyz": (0, 1, 2), "yzx": (2, 0, 1), "zxy": (1, 2, 0)}
_CORNERS = ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1), (0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1))


def pivot_frame(rotation: np.ndarray, axis_map: str, corner: int) -> np.ndarray:
    """setPivot's axes: the scope axes permuted by ``axis_map`` and, at ``corner``, turned to
    point inside the scope with y along (or against) the mapped y and a right-handed frame."""
    order = _AXIS_MAPS[axis_map]
    inside = [1.0 if c == 0 else -1.0 for c in _CORNERS[corner]]  # per old axis
    x_old, y_old, z_old = order
    y = rotation[:, y_old] * inside[y_old]
    for candidate in (x_old, z_old):
        x = rotation[:, candidate] * inside[candidate]
        z = np.cross(x, y)
        other = z_old if candidate == x_old else x_old
        if float(z @ (rotation[:, other] * inside[other])) > 0.5:
            return np.column_stack([x, y, z])
    raise AssertionError("no right-handed pivot")  # one of the two always is


@operation("setPivot")
def compile_set_pivot(program, node, params):
    arguments = plain_arguments(program, node, (2,))
    axis_map = choice(program, node, arguments[0], tuple(_AXIS_MAPS), "the axis map")
    corner_of = typed(program, node, arguments[1], params, float, "the corner index")
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def set_pivot(state, args, out):
        shape = shape_with_faces(program, node, state, components=True)
        corner = corner_of(args, state)
        if corner != int(corner) or not 0 <= corner <= 7:
            raise error(
                node, f"setPivot(): the corner index is a whole number 0..7, got {corner:g}"
            )
        frame = pivot_frame(shape.scope.rotation, axis_map, int(corner))
        point = shape.scope.to_world(np.asarray(_CORNERS[int(corner)], float) * shape.scope.size)
        state.shape = refit(shape, frame)
        state.pivot = (point, frame)  # op_setPivot: "pivot.p will lie at a selected corner"
        return True

    return set_pivot


@operation("reverseNormals")
def compile_reverse_normals(program, node, params):
    plain_arguments(program, node, (0,))

    def reverse_normals(state, args, out):
        shape = shape_with_faces(program, node, state)
        state.shape = Shape.with_geometry(
            shape.scope, shape.mesh().reversed(), shape.kind, shape.normal_axis
        )
        return True

    return reverse_normals


@operation("cleanupGeometry")
def compile_cleanup_geometry(program, node, params):
    arguments = plain_arguments(program, node, (2,))
    choice(program, node, arguments[0], ("vertices", "edges", "faces", "all"), "the components")
    tolerance_of = typed(program, node, arguments[1], params, float, "the tolerance")

    def cleanup(state, args, out):
        shape = shape_with_faces(program, node, state, components=True)
        tolerance = min(
            max(tolerance_of(args, state), 0.0), 1.0
        )  # metres, as the reference's 1 m at 1
        if shape.geometry is not None and shape.kind in (FACE, MASS):  # edges: nothing to merge
            state.shape = Shape.with_geometry(
                shape.scope, shape.geometry.cleaned(tolerance), shape.kind, shape.normal_axis
            )
        return True

    return cleanup


_NOT_REDUCED = "the geometry is kept whole: shapegen does not simplify meshes"


@operation("reduceGeometry", partial=_NOT_REDUCED)
def compile_reduce_geometry(program, node, params):
    """reduceGeometry(tolerance): the edge collapses are not made; a warning says so."""
    (argument,) = plain_arguments(program, node, (1,))
    tolerance_of = typed(program, node, argument, params, float, "the tolerance")

    def reduce_geometry(state, args, out):
        shape_with_faces(program, node, state, components=True)
        if not 0.0 <= (tolerance := tolerance_of(args, state)) <= 1.0:
            raise program.operation_error(
                node, f"reduceGeometry(): the tolerance is 0..1, got {tolerance:g}"
            )
        warn_at(state, node, f"reduceGeometry({tolerance:g}): {_NOT_REDUCED}")
        return True

    return reduce_geometry


@operation("resetGeometry")
def compile_reset_geometry(program, node, params):
    plain_arguments(program, node, (0,))

    def reset(state, args, out):
        start = getattr(state.run, "start_shape", None)
        if start is None:
            raise program.error(node, "resetGeometry(): no start shape")
        state.shape = start.copy()
        state.pivot = None  # op_resetGeometry: "scope and pivot are reset"
        return True

    return reset


@operation("trim")
def compile_trim(program, node, params):
    """``trim()``: the shape cut to its enabled trim planes, a face's holes cut with it (PyPRT:
    a courtyard slab cut by its top's planes keeps its holes, tests/data/prt_trim_holes.json)."""
    plain_arguments(program, node, (0,))
    return lambda state, args, out: apply_trim(state)


@operation("deleteHoles")
def compile_delete_holes(program, node, params):
    """``deleteHoles()``: every face's holes closed (op_deleteHoles); the vertices only the
    holes used go, the scope stays (checked with PyPRT, tests/data/prt_holes.json)."""
    plain_arguments(program, node, (0,))

    def delete_holes(state, args, out):
        shape = state.shape
        if shape.geometry is not None and shape.geometry.holes:
            state.shape = Shape.with_geometry(
                shape.scope, shape.geometry.without_holes(), shape.kind, shape.normal_axis
            )
        return True

    return delete_holes


@operation("convexify")
def compile_convexify(program, node, params):
    arguments = plain_arguments(program, node, (0, 1))
    limit_of = typed(program, node, arguments[0], params, float, "maxLength") if arguments else None

    def convexify(state, args, out):
        from shapegen.geometry.convex import convex_faces

        shape = shape_with_faces(program, node, state)
        limit = None if limit_of is None else limit_of(args, state)
        mesh = shape.mesh()
        state.shape = Shape.with_geometry(
            shape.scope, convex_faces(mesh, limit), shape.kind, shape.normal_axis
        )
        return True

    return convexify
