"""Reading the current shape's attributes in expressions: ``scope.*``, ``split.*``, ``comp.*``,
``geometry.*`` (asked of :func:`shapegen.engine.shape.shape_geometry_value`), ``material.*``
(:func:`shapegen.model.appearance.material_value`), ``initialShape.*``, ``pivot.*``, ``trim.*``
and ``seedian``.

:func:`shape_reader` gives, at compile time, a reader ``value(state, *args)`` for one of them.
"""

from __future__ import annotations

__all__ = ["convert_value", "shape_reader"]

import math
from collections.abc import Callable

import numpy as np

from shapegen.grammar.names import GEOMETRY_FUNCTIONS, SHAPE_ATTRIBUTES

Reader = Callable[..., object]


def _euler(state, k: int) -> float:
    r = state.shape.scope.rotation
    # Angles of rotation_matrix(): R = Rz @ Ry @ Rx, in degrees.
    if k == 0:
        return math.degrees(math.atan2(r[2, 1], r[2, 2]))
    if k == 1:
        return math.degrees(-math.asin(max(-1.0, min(1.0, float(r[2, 0])))))
    return math.degrees(math.atan2(r[1, 0], r[0, 0]))


def _no_arguments(reader: Callable[[object], object]) -> Reader:
    def read(state, *args):
        if args:
            raise ValueError("takes no arguments")
        return reader(state)

    return read


def _seedian(state) -> float:
    # the seed of the random numbers (attr_seedian): the derivation's --seed, as PyPRT prints
    # the initial shape's seed (0 by default) for print(seedian)
    return float(state.run.seed)


_READERS: dict[str, Callable[[object], object]] = {
    "scope.sx": lambda state: float(state.shape.scope.size[0]),
    "scope.sy": lambda state: float(state.shape.scope.size[1]),
    "scope.sz": lambda state: float(state.shape.scope.size[2]),
    "scope.tx": lambda state: float(state.shape.scope.origin[0]),
    "scope.ty": lambda state: float(state.shape.scope.origin[1]),
    "scope.tz": lambda state: float(state.shape.scope.origin[2]),
    "scope.rx": lambda state: _euler(state, 0),
    "scope.ry": lambda state: _euler(state, 1),
    "scope.rz": lambda state: _euler(state, 2),
    # the height of the scope's origin above the ground plane y = 0 (world coordinates)
    "scope.elevation": lambda state: float(state.shape.scope.origin[1]),
    "split.index": lambda state: float(state.split_index),
    "split.total": lambda state: float(state.split_total),
    "comp.index": lambda state: float(state.comp_index),
    "comp.total": lambda state: float(state.comp_total),
    # the selector that took the component, as written (attr_comp: "" before any comp)
    "comp.sel": lambda state: state.comp_sel,
    # shapegen derives one initial shape, its lot, placed at the origin with identity axes
    **{f"initialShape.origin.{k}": (lambda state: 0.0) for k in ("px", "py", "pz")},
    **{f"initialShape.origin.{k}": (lambda state: 0.0) for k in ("ox", "oy", "oz")},
    "initialShape.name": lambda state: "Lot",
    "seedian": _seedian,
    # as set() left them in the shape's past, else attr_trim's defaults (names.SETTABLE_...)
    "trim.horizontal": lambda state: state.attrs.get("trim.horizontal", False),
    "trim.vertical": lambda state: state.attrs.get("trim.vertical", True),
}


def shape_reader(obj: str, field: str, grammar) -> Reader | None:
    """The reader of ``obj.field`` (``field`` empty for ``seedian``), or None when shapegen does
    not evaluate it. Raises ``ValueError`` for a name CGA does not have."""
    key = f"{obj}.{field}" if field else obj
    if obj == "geometry":
        if field not in GEOMETRY_FUNCTIONS:
            raise ValueError(f"unknown geometry function {key!r}")

        def geometry(state, *args):
            from shapegen.engine.shape import shape_geometry_value

            return shape_geometry_value(state, field, *args)

        return geometry
    if obj == "material":
        from shapegen.model.appearance import material_value

        def material(state, *args):
            if args:
                raise ValueError("takes no arguments")
            return material_value(state.appearance, field)

        return material
    if key == "initialShape.startRule":
        start = grammar.start_rule
        name = start.name if start is not None else ""
        return _no_arguments(lambda state: name)
    reader = _READERS.get(key)
    if reader is not None:
        return _no_arguments(reader)
    if obj in SHAPE_ATTRIBUTES and field in SHAPE_ATTRIBUTES[obj]:
        return None  # CGA has it; shapegen does not evaluate it
    raise ValueError(f"unknown shape attribute {key!r}")


# convert() (func_convert) ---------------------------------------------------------------------


def _euler_matrix(angles) -> np.ndarray:
    """CGA's Euler angles (degrees) as a rotation matrix: Rz(c) Ry(b) Rx(a), cga_eulerAngles."""
    a, b, c = (math.radians(float(v)) for v in angles)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _euler_angles(r: np.ndarray) -> list[float]:
    return [
        math.degrees(math.atan2(r[2, 1], r[2, 2])),
        math.degrees(-math.asin(max(-1.0, min(1.0, float(r[2, 0]))))),
        math.degrees(math.atan2(r[1, 0], r[0, 0])),
    ]


def _frame(state, system: object) -> tuple[np.ndarray, np.ndarray]:
    if system == "scope":
        scope = state.shape.scope
        return np.asarray(scope.origin, float), np.asarray(scope.rotation, float)
    if system == "world":
        return np.zeros(3), np.eye(3)
    if system == "object":  # the lot's frame, placed at the origin
        rotation = getattr(state.run, "object_rotation", None)
        return np.zeros(3), np.eye(3) if rotation is None else np.asarray(rotation, float)
    if system == "pivot":
        raise ValueError("the pivot frame is not supported by shapegen")
    raise ValueError(f"the coordinate systems are scope, pivot, object and world, got {system!r}")


def convert_value(state, *values):
    """``convert(coordinate, from, to, type, x, y, z)`` (one float) or ``convert(from, to, type,
    [x, y, z])`` (an array): a position (``pos``, metres) or an orientation (``orient``, CGA
    Euler angles in degrees) given in one of the shape's frames, in another."""
    from shapegen.engine.functions_arrays import Array

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
    origin_from, rotation_from = _frame(state, source)
    origin_to, rotation_to = _frame(state, target)
    if kind == "pos":
        world = origin_from + rotation_from @ np.asarray(triple, float)
        result = [float(v) for v in rotation_to.T @ (world - origin_to)]
    elif kind == "orient":
        result = _euler_angles(rotation_to.T @ rotation_from @ _euler_matrix(triple))
    else:
        raise ValueError(f"the type is pos or orient, got {kind!r}")
    if coordinate is not None:
        return result["xyz".index(coordinate)]
    return Array(tuple(result), 3, 1)
