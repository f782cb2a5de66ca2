"""Inserting geometry: asset files (``i("assets/door.obj")``), built-in assets
(``i("builtin:cube")``) and CityEngine's primitives (``primitiveCube()``, ``primitiveQuad()``,
``primitiveCylinder(n, r, h)``...).

Semantics of CityEngine's reference (``op_i``, ``op_primitive``):

- the asset's bounding box is fitted to the scope, each axis scaled on its own; a scope size of
  0 keeps the asset's proportion: all three 0 keep the asset as it is (the scope takes its size
  and is moved by its offset), two 0 scale the asset uniformly by the third, one 0 takes the
  mean scale of the other two;
- a primitive given its dimensions keeps them: the scope becomes its bounding box, in the old
  scope's x-z centre on its y = 0 (``primitiveCube(20, 2, 20)`` on a 10 x 10 lot has the scope
  20 x 2 x 20 from (-5, 0, -5), so a following ``s(4, 1, 4)`` makes a 4 x 1 x 4 box there, as
  CityEngine's runtime does); ``primitiveQuad``/``primitiveDisk`` lie in the plane of the
  scope's two non-zero sizes (x-z when all three are non-zero) and are centred in it;
- the templates are CityEngine's (see :func:`primitive_mesh`): a radius is to the vertices,
  so ``primitiveDisk(8, 3)`` is 2 * 3 * cos(22.5 degrees) = 5.54 m across its flats;
- the defaults: 16 sides for cylinder, cone and disk, 16 x 16 for the sphere.

An asset file is found next to the rule file, then in each folder above it that holds a
``rules`` or ``assets`` folder (the project of an extracted rule package), as ``<project>/PATH``
and ``<project>/assets/PATH``. OBJ, glTF, COLLADA, PLY and STL files are read. A file that
is not found is replaced by a box filling the scope, as CityEngine's runtime does (its model of
the candler package without the asset files has the bounding box of these boxes, trimmed), and
is a warning of the derivation naming the file and the chain of rules; so is, in a ``.cga``
rule, a file of a format CityEngine reads and shapegen does not (USD, DWG, IFC; FBX when the
optional ufbx is not installed; COLLADA is read through pycollada, its up axis honoured). The
inserted geometry is cut to the shape's trim planes (:mod:`shapegen.engine.shapes.trim`); it
becomes a block when it is a closed convex solid, else a surface (see the interpreter).
"""

from __future__ import annotations

__all__ = ["asset_insert", "is_asset_name", "primitive_mesh"]

import importlib.util
import math
import os
from collections.abc import Callable

import numpy as np

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.expressions.arrays import format_value
from shapegen.engine.operations.cga.arguments import plain_arguments
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.project.asset_files import find_asset, load_asset
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.engine.shapes.trim import apply_trim
from shapegen.errors import GeometryError
from shapegen.geometry.mesh import Mesh
from shapegen.grammar import ast
from shapegen.grammar.names import OPERATION_KEYWORDS
from shapegen.limits import limit_hint
from shapegen.model.scope import Scope
from shapegen.readers.fbx import MISSING as FBX_MISSING

ASSET_SUFFIXES = (".obj", ".gltf", ".glb", ".dae", ".ply", ".stl", ".fbx")
"""Asset files shapegen reads (FBX with the optional ufbx); CityEngine also reads .usd, .dwg,
.ifc."""
OTHER_CITYENGINE_SUFFIXES = (".usd", ".usda", ".usdc", ".usdz", ".dwg", ".ifc")
BUILTIN_ASSETS = ("builtin:cube", "builtin:cube:notex")
DEFAULT_SIDES = 16


def is_asset_name(name: str) -> bool:
    """True when ``i(name)`` names an asset (a file or ``builtin:``), not a template primitive:
    the empty name (an asset that cannot be found) and a name with a ``:`` are assets too."""
    suffix = os.path.splitext(name)[1].lower()
    return (
        not name
        or ":" in name
        or "/" in name
        or "\\" in name
        or suffix in ASSET_SUFFIXES + OTHER_CITYENGINE_SUFFIXES
    )


# ------------------------------------------------------------------------- meshes
def primitive_mesh(kind: str, sides: int = DEFAULT_SIDES, divisions: int = DEFAULT_SIDES) -> Mesh:
    """The unit template of a CityEngine primitive, as its runtime makes it (measured with
    PyPRT): the cube ``[0, 1]^3``; the quad ``[-0.5, 0.5]^2`` in ``y = 0``; the disk, cylinder,
    cone and sphere of radius 0.5 (to their vertices) about the y axis, ``y`` in ``[0, 1]``, a
    ring's first edge straddling +z (a hexagon has a vertex on +x, an octagon its flats on both
    axes). Faces counter-clockwise seen from outside (the flat ones from +y). The position
    matters where the scope has zero sizes (a point-like scope keeps the template as it is)."""
    n = sides
    # the ring counter-clockwise seen from +y: angles from +x towards +z, decreasing
    angles = np.pi / 2 + np.pi / n - 2 * np.pi * np.arange(n) / n
    ring = np.column_stack([0.5 * np.cos(angles), np.zeros(n), 0.5 * np.sin(angles)])
    if kind == "cube":
        return Mesh.box((1.0, 1.0, 1.0))
    if kind == "quad":
        return Mesh.polygon([(-0.5, 0, 0.5), (0.5, 0, 0.5), (0.5, 0, -0.5), (-0.5, 0, -0.5)])
    if kind == "disk":
        return Mesh.polygon(ring)
    if kind == "cylinder":
        top = ring + [0.0, 1.0, 0.0]
        faces = [tuple(range(n - 1, -1, -1)), tuple(range(n, 2 * n))]
        faces += [(k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)]
        return Mesh(np.vstack([ring, top]), faces)
    if kind == "cone":
        faces = [tuple(range(n - 1, -1, -1))] + [(k, (k + 1) % n, n) for k in range(n)]
        return Mesh(np.vstack([ring, [[0.0, 1.0, 0.0]]]), faces)
    if kind == "sphere":
        rows = []
        for j in range(1, divisions):
            polar = np.pi * j / divisions  # from the top
            rows.append(
                np.column_stack(
                    [
                        math.sin(polar) * ring[:, 0],
                        np.full(n, 0.5 + 0.5 * math.cos(polar)),
                        math.sin(polar) * ring[:, 2],
                    ]
                )
            )
        vertices = np.vstack([[[0.0, 1.0, 0.0]], *rows, [[0.0, 0.0, 0.0]]])
        bottom = len(vertices) - 1
        faces = [(0, 1 + (k + 1) % n, 1 + k) for k in range(n)]
        for j in range(divisions - 2):
            a, b = 1 + j * n, 1 + (j + 1) * n
            faces += [(a + k, a + (k + 1) % n, b + (k + 1) % n, b + k) for k in range(n)]
        last = 1 + (divisions - 2) * n
        faces += [(last + k, last + (k + 1) % n, bottom) for k in range(n)]
        return Mesh(vertices, [face[::-1] for face in faces])  # listed inward: turned out
    raise AssertionError(kind)


def fitted(mesh: Mesh, scope: Scope) -> tuple[Scope, Mesh]:
    """``mesh`` (asset coordinates) fitted into ``scope`` as op_i does: its bounding box scaled
    onto the scope, zero scope sizes taking the asset's proportion. Returns the new scope and
    the mesh in its coordinates."""
    bounds = mesh.__dict__.get("asset_bounds")  # an asset's mesh is inserted again and again
    if bounds is None:
        bounds = mesh.__dict__["asset_bounds"] = mesh.bounds()
    lo, hi = bounds
    extent = hi - lo
    size = np.asarray(scope.size, dtype=float).copy()
    origin = np.asarray(scope.origin, dtype=float).copy()
    zero = size <= 0
    if zero.all():
        size = extent.copy()
        origin = origin + scope.rotation @ lo
    elif zero.sum() == 2:
        k = int(np.flatnonzero(~zero)[0])
        scale = size[k] / extent[k] if extent[k] > 0 else 1.0
        for axis in np.flatnonzero(zero):
            size[axis] = scale * extent[axis]
            origin = origin + scope.rotation[:, axis] * scale * lo[axis]
    elif zero.sum() == 1:
        axis = int(np.flatnonzero(zero)[0])
        others = [k for k in range(3) if k != axis and extent[k] > 0]
        scale = np.mean([size[k] / extent[k] for k in others]) if others else 1.0
        size[axis] = scale * extent[axis]
    factors = np.divide(size, extent, out=np.zeros(3), where=extent > 0)
    local = (mesh.vertices - lo) * factors
    return Scope(origin, scope.rotation, size), Mesh.of_valid_faces(local, mesh.faces)


def _sized(mesh: Mesh, scope: Scope, flat_axis: int = 1, centre=(0.0, 0.0, 0.0)):
    """A primitive ``mesh`` already at its size (m) placed as op_primitive places one given its
    dimensions: its ``centre`` (the axis of a round one, in the mesh's coordinates) on the
    scope's x-z centre and its bottom on the scope's y = 0, the scope becoming its bounding box;
    a quad or disk standing in the scope's x-y or y-z plane (``flat_axis`` 2 or 0) is centred
    in that plane. The centre, not the bounding box, is centred: a triangle of radius 3 on a
    10 m lot spans z 2..6.5, as CityEngine's runtime places it. Returns the new scope and the
    mesh in its coordinates."""
    lo, hi = mesh.bounds()
    offset = lo.copy()
    centred = [k for k in range(3) if k != flat_axis]
    offset[centred] += scope.size[centred] / 2 - np.asarray(centre, float)[centred]
    origin = scope.origin + scope.rotation @ offset
    return Scope(origin, scope.rotation, hi - lo), Mesh.of_valid_faces(
        mesh.vertices - lo, mesh.faces
    )


def _flat_in_scope(mesh: Mesh, scope: Scope) -> tuple[Mesh, int]:
    """A flat template (in y = 0) turned into the plane of the scope's two non-zero sizes (x-z
    when none or several are zero), as op_primitive does; returns it and the axis it is flat
    along. Its x-z front edge (+z) goes to the bottom of an x-y plane, which it faces from +z;
    in a y-z plane it faces +x (the orders CityEngine's runtime gives, measured with PyPRT)."""
    zero = [k for k in range(3) if scope.size[k] <= 0]
    if len(zero) != 1 or zero[0] == 1:
        return mesh, 1
    v = mesh.vertices
    if zero[0] == 2:  # the x-y plane: (x, z) -> (x, -z)
        return Mesh(np.column_stack([v[:, 0], -v[:, 2], np.zeros(len(v))]), mesh.faces), 2
    # the y-z plane: (x, z) -> (-x, z)
    return Mesh(np.column_stack([np.zeros(len(v)), -v[:, 0], v[:, 2]]), mesh.faces), 0


def _shape_of(mesh: Mesh, scope: Scope) -> Shape:
    lo, hi = mesh.bounds()
    flat = [k for k in range(3) if hi[k] - lo[k] <= 0]
    if flat:
        return Shape.with_geometry(scope, mesh, FACE, flat[0])
    return Shape.with_geometry(scope, mesh, MASS)


def asset_insert(program, node: ast.Insert, params):
    """The operation of ``i(name)`` for an asset name (see :func:`is_asset_name`); a literal
    name is checked when the rule is compiled (a format shapegen does not read; in a
    ``.grammar`` file a built-in asset it lacks, which a ``.cga`` file inserts as an asset not
    found: CityEngine's compiler cannot know the strings an insert is given)."""
    if node.parameters:
        raise program.error(node, "i() of an asset file takes no keyword parameters")
    cga = program.cga_dialect
    if isinstance(node.primitive, ast.String) and not cga:
        problem = _name_problem(node.primitive.value)
        if problem:
            raise program.error(node, problem)
    name_of = program.expressions.compile(node.primitive, params)
    rule_file = getattr(getattr(node, "location", None), "file", None) or program.grammar.filename
    error = program.error
    options_of = _insert_options(program, node, params)

    def insert_asset(state, args, out):
        name = name_of(args, state)
        problem = _name_problem(name, cga) if type(name) is str else "i() needs a file name"
        scope = state.shape.scope
        if problem and cga and type(name) is str:
            # a format CityEngine reads and shapegen does not: as an asset it cannot load
            warn_at(state, node, f"{problem}; a box fills the scope, as for an asset that is "
                                 "not found")  # fmt: skip
            state.shape = _box_shape(scope)
            return apply_trim(state)
        if problem:
            raise error(node, problem)
        if name in BUILTIN_ASSETS:
            state.shape = _box_shape(scope)
            return apply_trim(state)
        known = not name.startswith("builtin:")  # another built-in: not found, as in CityEngine
        path = find_asset(name, rule_file) if name and known else None
        if not name:
            warn_at(state, node, 'i(""): the asset name is empty; a box fills the scope, as '
                    "for an asset that is not found")  # fmt: skip
            state.shape = _box_shape(scope)
            return apply_trim(state)
        if path is None:
            state.run.warn(f"asset {name!r} not found (rules: {format_chain(state.rule_path)}); "
                         f"a box fills its scope instead")  # fmt: skip
            state.shape = _box_shape(scope)
            return apply_trim(state)
        try:
            mesh = load_asset(path)
        except (GeometryError, OSError, ValueError) as exc:
            raise program.operation_error(node, f"i({name!r}): {exc}") from None
        up_axis, mode = options_of(args, state)
        if up_axis == "zUp":  # op_i: "rotated by -90 degrees around the x-axis"
            mesh = Mesh(mesh.vertices @ _Z_UP.T, mesh.faces)
        if mode == "keepSizeAndPosition":  # as s(0, 0, 0)
            scope = Scope(scope.origin, scope.rotation, np.zeros(3))
        if mode == "keepSizeAlignPosition":
            new_scope, local = _kept_size(mesh, scope)
        else:
            new_scope, local = fitted(mesh, scope)
        state.shape = _shape_of(local, new_scope)
        return apply_trim(state)

    return insert_asset


_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # -90 degrees about x
_INSERT_OPTIONS = (
    ("yUp", "zUp"),
    ("alignSizeAndPosition", "keepSizeAndPosition", "keepSizeAlignPosition"),
    ("numericalCleanup", "noCleanup"),
)


def _insert_options(program, node, params) -> Callable:
    """``i(asset, upAxis, insertMode, cleanupMode)``'s words (op_i): ``f(args, state) -> (up
    axis, insert mode)``. A word written as such is checked when compiled; a string expression
    (``i(f, upMode, ...)`` with ``upMode = "zUp"``, as rules of 2014 write it) when derived.
    The cleanup mode only concerns CityEngine's mesh repair, so both are accepted."""
    options = getattr(node, "options", ())
    if len(options) > len(_INSERT_OPTIONS):
        raise program.error(node, "i() takes a file, an up axis, an insert mode and a cleanup mode")
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)
    words: list = []
    for position, (option, allowed) in enumerate(zip(options, _INSERT_OPTIONS, strict=False)):
        message = f"i()'s argument {position + 2} is one of {', '.join(allowed)}"
        if isinstance(option, ast.Name) and option.name in allowed:
            words.append(lambda args, state, word=option.name: word)
        elif isinstance(option, ast.Name) and option.name in OPERATION_KEYWORDS:
            raise program.error(node, message)
        else:
            compiled = program.expressions.compile(option, params)

            def word_of(args, state, compiled=compiled, allowed=allowed, message=message):
                word = compiled(args, state)
                if word not in allowed:
                    raise error(node, f"{message}; got {format_value(word)}")
                return word

            words.append(word_of)
    words += [lambda args, state, w=allowed[0]: w for allowed in _INSERT_OPTIONS[len(words) :]]
    return lambda args, state: (words[0](args, state), words[1](args, state))


def _kept_size(mesh: Mesh, scope: Scope) -> tuple[Scope, Mesh]:
    """``keepSizeAlignPosition``: the asset at its own size, its bounding box on the scope's
    y = 0 and centred in the scope's x and z."""
    lo, hi = mesh.bounds()
    extent = hi - lo
    offset = np.array([(scope.size[0] - extent[0]) / 2, 0.0, (scope.size[2] - extent[2]) / 2])
    origin = scope.origin + scope.rotation @ offset
    return Scope(origin, scope.rotation, extent), Mesh.of_valid_faces(
        mesh.vertices - lo, mesh.faces
    )


def _name_problem(name: str, cga: bool = False) -> str | None:
    """What keeps shapegen from reading asset ``name``: a format it lacks (an error in a
    ``.grammar`` rule, a warning and a box in a ``.cga`` one), a built-in asset it lacks in a
    ``.grammar`` rule."""
    if name.startswith("builtin:") and name not in BUILTIN_ASSETS and not cga:
        return f"i({name!r}): shapegen has the built-in assets {', '.join(BUILTIN_ASSETS)}"
    suffix = os.path.splitext(name)[1].lower()
    if suffix == ".fbx" and importlib.util.find_spec("ufbx") is None:
        return f"i({name!r}): {FBX_MISSING}"
    if suffix in OTHER_CITYENGINE_SUFFIXES:
        return (
            f"i({name!r}): {suffix} assets are not read by shapegen; "
            f"it reads {', '.join(ASSET_SUFFIXES)}"
        )
    return None


def _box_shape(scope: Scope) -> Shape:
    """The unit cube fitted to the scope: the box that fills it (the fast path), zero sizes
    taking the cube's proportion."""
    if min(scope.d) > 0:  # what fitting the unit cube gives: the scope as it is
        return Shape(scope, MASS)
    new_scope, _ = fitted(Mesh.box((1.0, 1.0, 1.0)), scope)
    return Shape(new_scope, MASS)


# ------------------------------------------------------------------------- primitives
_PRIMITIVES = {
    # name: (template, counts of arguments, names of the numbers, dimensions from them)
    "primitiveCube": ("cube", (0, 3)),
    "primitiveQuad": ("quad", (0, 2)),
    "primitiveDisk": ("disk", (0, 1, 2)),
    "primitiveCylinder": ("cylinder", (0, 1, 3)),
    "primitiveCone": ("cone", (0, 1, 3)),
    "primitiveSphere": ("sphere", (0, 2, 3)),
}


@operation(*_PRIMITIVES)
def compile_primitive(program, node: ast.Operation, params):
    kind, counts = _PRIMITIVES[node.name]
    plain_arguments(program, node, counts)
    numbers = [program.number(node, a.value, params, f"a {node.name}() argument")
               for a in node.arguments]  # fmt: skip
    error = program.error
    cga = program.cga_dialect

    def primitive(state, args, out):
        return place(state, args) and apply_trim(state)

    def place(state, args):
        values = [n(args, state) for n in numbers]
        sides, divisions, dimensions = DEFAULT_SIDES, DEFAULT_SIDES, None
        if kind in ("cylinder", "cone", "disk") and values:
            sides = values[0]
            if len(values) == 3:  # sides, radius, height
                dimensions = (2 * values[1], values[2], 2 * values[1])
            elif kind == "disk" and len(values) == 2:  # sides, radius
                dimensions = (2 * values[1], 0.0, 2 * values[1])
        elif kind == "sphere" and values:
            sides, divisions = values[0], values[1]
            if len(values) == 3:
                dimensions = (2 * values[2],) * 3
        elif kind == "quad" and values:
            dimensions = (values[0], 0.0, values[1])
        elif kind == "cube" and values:
            dimensions = tuple(values)
        if cga and math.isfinite(sides) and math.isfinite(divisions):
            # CityEngine's runtime rounds them half to even, as round() does (PyPRT: 3.5 and
            # 4.5 sides both make 4, 7.6 makes 8, 2.5 is 2 and skips the operation)
            sides, divisions = round(sides), round(divisions)
        for what, count, least in (("sides", sides, 3), ("divisions", divisions, 2)):
            if count != int(count) or count < least or count > 4096:
                raise program.operation_error(
                    node, f"{node.name}(): {what} is a whole number {least}..4096, got "
                    f"{format_value(count)}"
                )  # fmt: skip
        faces = {"sphere": sides * divisions, "cylinder": sides + 2, "cone": sides + 1}
        limits = state.run.limits
        if faces.get(kind, 1) > limits.max_mesh_faces:
            raise error(node, f"{node.name}(): its mesh would have {faces[kind]:.0f} faces, more "
                              f"than {limits.max_mesh_faces} "
                              + limit_hint("max_mesh_faces", limits))  # fmt: skip
        signs = np.ones(3)
        if dimensions is not None and any(d < 0 for d in dimensions):
            if not cga:
                raise error(node, f"{node.name}(): dimensions must be >= 0 m")
            # as s() with negative sizes (op_s: "negative sizes result in mirroring")
            warn_at(state, node, f"{node.name}(): a negative dimension mirrors the primitive "
                                 "within its size, as s() does (a negative height hangs it "
                                 "below the scope's y = 0)")  # fmt: skip
            signs = np.where(np.asarray(dimensions) < 0, -1.0, 1.0)
            dimensions = tuple(abs(d) for d in dimensions)
        scope = state.shape.scope
        if kind == "cube":  # a box filling its scope: the fast path, mirrored or not
            if dimensions is None:
                state.shape = _box_shape(scope)
            else:
                # a negative height hangs the box below y = 0, as the runtime does (PyPRT)
                signed = np.asarray(dimensions) * signs
                box = Mesh.box(dimensions).scaled(signs)
                state.shape = Shape(_sized(box, scope, 1, signed / 2)[0], MASS)
            return True
        template = primitive_mesh(kind, int(sides), int(divisions))
        if dimensions is not None:  # op_primitive: the primitive at its size, the scope its box
            template = template.scaled(np.asarray(dimensions) * signs)
        elif (signs < 0).any():
            template = template.scaled(signs)
        if kind in ("quad", "disk"):
            template, axis = _flat_in_scope(template, scope)
            if dimensions is not None:
                scope, local = _sized(template, scope, axis)
            else:
                scope, local = fitted(template, scope)
            state.shape = Shape.with_geometry(scope, local, FACE, axis)
            return True
        if dimensions is not None:
            scope, local = _sized(template, scope)
        else:
            scope, local = fitted(template, scope)
        state.shape = Shape.with_geometry(scope, local, MASS)
        return True

    return primitive
