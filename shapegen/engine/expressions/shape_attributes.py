"""Reading the current shape's attributes in expressions: ``scope.*``, ``split.*``, ``comp.*``,
``geometry.*`` (asked of :func:`shapegen.engine.shapes.shape.shape_geometry_value`), ``material.*``
(:func:`shapegen.model.appearance.material_value`), ``initialShape.*``, ``pivot.*``, ``trim.*``,
``seedian`` and the deprecated ``uid``.

:func:`shape_reader` gives, at compile time, a reader ``value(state, *args)`` for one of them.
The frames they are measured in are :mod:`shapegen.engine.shapes.frames`': in a ``.cga``
file ``scope.t*`` and ``scope.r*`` are relative to the pivot, as attr_scope says ("relative to
the pivot"); ``.grammar`` files keep world coordinates.
"""

from __future__ import annotations

__all__ = [
    "PARTIAL_ATTRIBUTES",
    "PARTIAL_FUNCTIONS",
    "STATE_FUNCTIONS",
    "convert_value",
    "shape_reader",
]

from collections.abc import Callable

import numpy as np

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.shapes.frames import (
    euler_angles,
    euler_matrix,
    frame_of,
    in_frame,
    object_frame,
    pivot_frame,
)
from shapegen.geometry.queries import GEOMETRY_FUNCTIONS as ANSWERED_GEOMETRY
from shapegen.geometry.queries import TEXTURE_BOUNDS
from shapegen.grammar.names import GEOMETRY_FUNCTIONS, SHAPE_ATTRIBUTES

Reader = Callable[..., object]

#: The name CityEngine's runtime gives the one material of a geometry that has no other: PyPRT
#: 1.12 reports ``geometry.materials`` as ``(1)[CityEngineMaterial]`` for the lot, an extrusion,
#: the primitives and the box that stands in for an asset not found.
DEFAULT_GEOMETRY_MATERIAL = "CityEngineMaterial"
_READ_ONLY = "read only: set() of it is refused when the file loads"
#: Shape attributes read with a difference from the reference: name -> what differs.
PARTIAL_ATTRIBUTES: dict[str, str] = {
    "initialShape.name": 'always "Lot" (shapegen derives one unnamed lot)',
    "material.color.a": "deprecated alias of material.opacity (cga_changelog 2011.1), warned",
    "initialShape.symbol": "deprecated alias of initialShape.startRule, warned",
    **{
        f"scope.{k}": "set() of it in .cga rules only (shapegen's .grammar reads it in world "
        "coordinates)"
        for k in ("tx", "ty", "tz", "rx", "ry", "rz", "sx", "sy", "sz")
    },
    "seedian": _READ_ONLY,
    "uid": "deprecated (cga_changelog 2015.0): a number unique per shape, not CityEngine's",
}

#: Deprecated names of material attributes (cga_changelog 2011.1) -> the current ones.
MATERIAL_ALIASES = {
    "color.a": "opacity",
    "map3": "specularmap",
    "map4": "opacitymap",
    "map5": "normalmap",
}


def material_alias(name: str) -> str:
    """The current name of the material attribute ``name`` (a deprecated one replaced)."""
    head, dot, rest = name.partition(".")
    if name in MATERIAL_ALIASES:
        return MATERIAL_ALIASES[name]
    if head in MATERIAL_ALIASES and dot:
        return f"{MATERIAL_ALIASES[head]}.{rest}"
    return name


def _no_arguments(reader: Callable[[object], object]) -> Reader:
    def read(state, *args):
        if args:
            raise ValueError("takes no arguments")
        return reader(state)

    read.plain = reader  # called as it is where the call has no arguments (expressions/compiler)
    return read


def _seedian(state) -> float:
    # the seed of the random numbers (attr_seedian): the derivation's --seed, as PyPRT prints
    # the initial shape's seed (0 by default) for print(seedian)
    return float(state.run.seed)


def _world_scope(k: int) -> Callable[[object], float]:
    if k < 3:
        return lambda state: state.shape.scope.o[k]
    return lambda state: euler_angles(state.shape.scope.rotation)[k - 3]


def _pivot_scope(k: int) -> Callable[[object], float]:
    """``scope.t*`` (k 0-2) and ``scope.r*`` (3-5) relative to the pivot (attr_scope)."""

    def read(state) -> float:
        scope = state.shape.scope
        position, angles = in_frame(pivot_frame(state), scope.origin, scope.rotation)
        return float(position[k]) if k < 3 else angles[k - 3]

    return read


def _relative_to_object(frame_of_state, k: int) -> Callable[[object], float]:
    """A frame's origin (k 0-2) or Euler angles (3-5) in object coordinates (attr_pivot)."""

    def read(state) -> float:
        origin, axes = frame_of_state(state)
        position, angles = in_frame(object_frame(state), origin, axes)
        return float(position[k]) if k < 3 else angles[k - 3]

    return read


def _origin(k: int) -> Callable[[object], float]:
    """initialShape.origin: the object frame relative to the world."""

    def read(state) -> float:
        origin, axes = object_frame(state)
        return float(origin[k]) if k < 3 else euler_angles(axes)[k - 3]

    return read


_FIELDS = ("px", "py", "pz", "ox", "oy", "oz")

_READERS: dict[str, Callable[[object], object]] = {
    "scope.sx": lambda state: state.shape.scope.d[0],
    "scope.sy": lambda state: state.shape.scope.d[1],
    "scope.sz": lambda state: state.shape.scope.d[2],
    # the height of the scope's origin above the ground plane y = 0 (world coordinates)
    "scope.elevation": lambda state: state.shape.scope.o[1],
    "split.index": lambda state: float(state.split_index),
    "split.total": lambda state: float(state.split_total),
    "comp.index": lambda state: float(state.comp_index),
    "comp.total": lambda state: float(state.comp_total),
    # the selector that took the component, as written (attr_comp: "" before any comp)
    "comp.sel": lambda state: state.comp_sel,
    **{f"initialShape.origin.{f}": _origin(k) for k, f in enumerate(_FIELDS)},
    **{f"pivot.{f}": _relative_to_object(pivot_frame, k) for k, f in enumerate(_FIELDS)},
    "initialShape.name": lambda state: "Lot",
    "seedian": _seedian,
    # as set() left them in the shape's past, else attr_trim's defaults (names.SETTABLE_...)
    "trim.horizontal": lambda state: state.attrs.get("trim.horizontal", False),
    "trim.vertical": lambda state: state.attrs.get("trim.vertical", True),
}
_SCOPE_PLACEMENT = ("tx", "ty", "tz", "rx", "ry", "rz")


def shape_reader(obj: str, field: str, grammar) -> Reader | None:
    """The reader of ``obj.field`` (``field`` empty for ``seedian`` and ``uid``), or None when
    shapegen does not evaluate it. Raises ``ValueError`` for a name CGA does not have."""
    key = f"{obj}.{field}" if field else obj
    if obj == "geometry":
        if field not in GEOMETRY_FUNCTIONS:
            raise ValueError(f"unknown geometry function {key!r}")
        if field in ("tags", "hasTags"):
            from shapegen.engine.shapes.tags import tags_value

            return lambda state, *args: tags_value(state.shape, field, *args)
        if field == "materials":
            return _geometry_materials
        if field not in ANSWERED_GEOMETRY:
            return None  # CGA has it (tags, groups, uv bounds...); shapegen does not answer it

        def geometry(state, *args):
            from shapegen.engine.shapes.shape import shape_geometry_value

            return shape_geometry_value(state, field, *args)

        if field in TEXTURE_BOUNDS or field in ("du", "dv"):
            return _said_to_stand_in(field, geometry)
        return geometry
    if obj == "material":
        return _material_reader(field)
    if obj == "scope" and field in _SCOPE_PLACEMENT:
        k = _SCOPE_PLACEMENT.index(field)
        cga = grammar.dialect == "cga"
        return _no_arguments(_pivot_scope(k) if cga else _world_scope(k))
    if key in ("initialShape.startRule", "initialShape.symbol"):
        start = grammar.start_rule
        name = start.name if start is not None else ""
        if field == "startRule":
            return _no_arguments(lambda state: name)

        def symbol(state):
            state.run.warn(
                "initialShape.symbol is deprecated (cga_changelog: replaced by "
                "initialShape.startRule); it reads the start rule's name"
            )
            return name

        return _no_arguments(symbol)
    reader = _READERS.get(key)
    if reader is not None:
        return _no_arguments(reader)
    if obj in SHAPE_ATTRIBUTES and field in SHAPE_ATTRIBUTES[obj]:
        return None  # CGA has it; shapegen does not evaluate it
    raise ValueError(f"unknown shape attribute {key!r}")


def _material_reader(field: str) -> Reader:
    from shapegen.model.appearance import material_value

    name = material_alias(field)

    def material(state, *args):
        if args:
            raise ValueError("takes no arguments")
        if name != field:
            state.run.warn(
                f"material.{field} is deprecated (cga_changelog 2011.1); it reads material.{name}"
            )
        return material_value(state.appearance, name)

    return material


# Builtins of the shape's state: uid, getGeoCoord --------------------------------------------


def _uid(state) -> float:
    """uid (deprecated): a number unique per shape of the derivation, in the order asked."""
    numbers = state.run.__dict__.setdefault("shape_uids", {})
    state.run.warn(
        "uid is deprecated (cga_changelog 2015.0: use getTreeKey); shapegen numbers the "
        f"shapes itself, not as CityEngine does (rules: {format_chain(state.rule_path)})"
    )
    return float(numbers.setdefault(state.path, len(numbers)))


def _geo_coordinate(state, which: object) -> float:
    """getGeoCoord(X|Y|lon|lat) of the scope's origin. shapegen's scene has no georeference:
    its coordinate system is CityEngine's own in metres, X east (+x) and Y north (-z); lon and
    lat (WGS84) are not defined without one, nan and a warning."""
    origin = state.shape.scope.origin
    if which == "X":
        return float(origin[0])
    if which == "Y":
        return float(-origin[2])
    if which in ("lon", "lat"):
        state.run.warn(
            f"getGeoCoord({which}): the scene has no georeference, so there is no WGS84 "
            f"coordinate; it is nan (rules: {format_chain(state.rule_path)})"
        )
        return float("nan")
    raise ValueError(f"the coordinate is X, Y, lon or lat, got {which!r}")


def _tree_key(state) -> str:
    """getTreeKey() (func_getTreeKey): the 0-based child indices from the root shape to the
    shape whose rule is being applied, each followed by ``;`` (``0;0;1;``). It stays the same
    through the whole rule: the operations' results are not nodes of the tree, its successors
    are."""
    indices = []
    node = state.tree
    while node is not None:
        indices.append(node[1])
        node = node[0]
    return "".join(f"{k};" for k in reversed(indices))


def _edge_attribute(kind: str, default: object, shown: str):
    """edgeAttr.getFloat|getString|getBool(name) (func_edgeAttr): the initial shape's edge
    attribute ``/edgeattr/name`` sampled on the shape. shapegen's lots carry no edge attributes,
    and for an attribute that does not exist the reference gives the default (0, "", false):
    that, with a warning, since a lot drawn in CityEngine may have them."""

    def read(state, name: object) -> object:
        if type(name) is not str:
            raise ValueError("the attribute name must be a string")
        state.run.warn(
            f"edgeAttr.{kind}({name!r}): shapegen's lots have no edge attributes, so it gives "
            f"the default {shown} (rules: {format_chain(state.rule_path)})"
        )
        return default

    return read


def _material_array(state, source: object = None, mode: object = None):
    """getMaterial(used|shape|geometry, changed|all) (func_getMaterial): the material as a 2D
    string array of ``name, value`` rows, which setMaterial() takes. shapegen's geometry carries
    no material of its own (an inserted asset's materials are not kept): ``geometry`` is the
    default material, ``used`` the shape's; for an inserted asset a warning says so."""
    from shapegen.engine.expressions.arrays import Array, format_value
    from shapegen.model.appearance import MATERIAL_ATTRIBUTES, material_value

    if source not in ("used", "shape", "geometry") or mode not in ("changed", "all"):
        raise ValueError("takes (used|shape|geometry, changed|all)")
    if source != "shape" and state.shape.kind == "insert":
        state.run.warn(
            f"getMaterial({source}, {mode}): shapegen keeps no material of an inserted asset, "
            f"so the asset's own material is not in it (rules: {format_chain(state.rule_path)})"
        )
    look = None if source == "geometry" else state.appearance
    cells: list[str] = []
    for name, (_, default) in MATERIAL_ATTRIBUTES.items():
        if name == "color.rgb":
            continue  # color.r, color.g and color.b say it
        value = material_value(look, name)
        if mode == "changed" and value == default:
            continue
        cells += [name, format_value(value)]
    return Array(tuple(cells), len(cells) // 2, 2)


#: Builtins of the shape being derived: ``name -> f(state, *values)``.
STATE_FUNCTIONS: dict[str, Callable[..., object]] = {
    "uid": _uid,
    "getGeoCoord": _geo_coordinate,
    "getTreeKey": _tree_key,
    "getMaterial": _material_array,
    "edgeAttr.getFloat": _edge_attribute("getFloat", 0.0, "0"),
    "edgeAttr.getString": _edge_attribute("getString", "", '""'),
    "edgeAttr.getBool": _edge_attribute("getBool", False, "false"),
}

#: Builtins answered with a difference from the reference: name -> what differs.
PARTIAL_FUNCTIONS: dict[str, str] = {
    "getGeoCoord": "no georeference: X and Y are scene metres (east, north), lon and lat nan",
    "getMaterial": "shapegen's geometry has no material of its own: geometry is the default "
    "material, used the shape's (an inserted asset's materials are not kept)",
    "geometry.materials": f"one material, {DEFAULT_GEOMETRY_MATERIAL!r}, with a warning: "
    "shapegen's geometry has one material (an inserted asset's own materials are not kept)",
    **dict.fromkeys(
        ("edgeAttr.getFloat", "edgeAttr.getString", "edgeAttr.getBool"),
        'lots have no edge attributes: the default (0, "", false), with a warning',
    ),
}


# convert() (func_convert) ---------------------------------------------------------------------


def convert_value(state, *values):
    """``convert(coordinate, from, to, type, x, y, z)`` (one float) or ``convert(from, to, type,
    [x, y, z])`` (an array): a position (``pos``, metres) or an orientation (``orient``, CGA
    Euler angles in degrees) given in one of the shape's frames, in another."""
    from shapegen.engine.expressions.arrays import Array

    if len(values) == 7:
        coordinate, source, target, kind, *triple = values
        if coordinate not in ("x", "y", "z"):
            raise ValueError(f"the coordinate is x, y or z, got {coordinate!r}")
    elif len(values) == 4:
        coordinate, (source, target, kind, array) = None, values
        if not isinstance(array, Array) or array.size != 3:
            raise ValueError("the coordinates are an array of 3 numbers")
        triple = list(array.values)
    else:
        raise ValueError(f"takes 4 or 7 arguments, got {len(values)}")
    if any(type(v) is not float for v in triple):
        raise ValueError("the coordinates are numbers")
    origin_from, rotation_from = frame_of(state, source)
    origin_to, rotation_to = frame_of(state, target)
    if kind == "pos":
        world = origin_from + rotation_from @ np.asarray(triple, float)
        result = [float(v) for v in rotation_to.T @ (world - origin_to)]
    elif kind == "orient":
        result = euler_angles(rotation_to.T @ rotation_from @ euler_matrix(triple))
    else:
        raise ValueError(f"the type is pos or orient, got {kind!r}")
    if coordinate is not None:
        return result["xyz".index(coordinate)]
    return Array(tuple(result), 3, 1)


def _geometry_materials(state, *args):
    """``geometry.materials()`` (func_geometry): the names of the geometry's materials, in
    ``comp(m)``'s order. shapegen's geometry is one material, as comp(m) makes one component of
    it; an asset's own materials are not kept, which the warning says."""
    from shapegen.engine.expressions.arrays import Array

    if args:
        raise ValueError("takes no arguments")
    state.run.warn(
        f"geometry.materials: shapegen's geometry has one material, {DEFAULT_GEOMETRY_MATERIAL!r} "
        "(CityEngine's name for it); an inserted asset's own materials are not kept"
    )
    if state.shape.mesh().n_faces == 0:
        return Array((), 0, 0, str)
    return Array((DEFAULT_GEOMETRY_MATERIAL,), 1, 1)


def _said_to_stand_in(field: str, read: Reader) -> Reader:
    """``read`` with a warning: a texture-coordinate query (``geometry.uMin``..., ``du``/``dv``
    outside unitSpace) answers from the scope, as shapegen keeps no texture coordinates."""

    def texture_query(state, *args):
        if field in TEXTURE_BOUNDS or len(args) < 2 or str(args[1]) != "unitSpace":
            state.run.warn(
                f"geometry.{field}: shapegen keeps no texture coordinates; uv is taken as 0..1 "
                "over the scope (u along x, v along y)"
            )
        return read(state, *args)

    return texture_query
