"""``set()`` of the shape attributes CityEngine lets a rule write (op_set: "Not all shape
attributes are writable"): the scope (attr_scope: "This attribute can be both read and
written"; ``scope.elevation`` cannot be set) and the pivot (attr_pivot).

- ``scope.t{x|y|z}``: the scope's origin in pivot coordinates, as ``scope.t*`` reads it in a
  ``.cga`` rule; the geometry moves with the scope;
- ``scope.r{x|y|z}``: the scope's Euler angles (cga_eulerAngles) relative to the pivot, about the
  scope's origin; the geometry turns with the scope;
- ``scope.s{x|y|z}``: the size along one axis, as ``s()`` sets it (the geometry scaled; a
  negative size mirrors);
- ``pivot.p{x|y|z}`` and ``pivot.o{x|y|z}``: the pivot's origin and Euler angles in object
  coordinates; the shape stays where it is (only what ``scope.t*``/``scope.r*`` read changes),
  as ``setPivot`` keeps it.
"""

from __future__ import annotations

__all__ = ["WRITABLE", "compile_shape_write", "write_shape_attribute"]

import numpy as np

from shapegen.engine.shapes.frames import (
    euler_angles,
    euler_matrix,
    in_frame,
    object_frame,
    pivot_frame,
)
from shapegen.model.scope import Scope

_AXES = "xyz"
WRITABLE: frozenset[str] = frozenset(
    [f"scope.{kind}{axis}" for kind in "trs" for axis in _AXES]
    + [f"pivot.{kind}{axis}" for kind in "po" for axis in _AXES]
)


def write_shape_attribute(state, attribute: str, value: float) -> None:
    """Set ``attribute`` (one of :data:`WRITABLE`) of ``state``'s shape to ``value``."""
    frame_name, field = attribute.split(".")
    kind, k = field[0], _AXES.index(field[1])
    shape = state.shape
    scope = shape.scope
    if frame_name == "scope" and kind == "s":
        size = np.asarray(scope.size, float).copy()
        size[k] = value
        state.shape = shape.resized(size)
        return
    if frame_name == "scope":
        frame_origin, frame_axes = pivot_frame(state)
        position, angles = in_frame((frame_origin, frame_axes), scope.origin, scope.rotation)
        origin, rotation = np.asarray(scope.origin, float), np.asarray(scope.rotation, float)
        if kind == "t":
            position = np.asarray(position, float).copy()
            position[k] = value
            origin = frame_origin + frame_axes @ position
        else:
            angles = list(angles)
            angles[k] = value
            rotation = frame_axes @ euler_matrix(angles)
        state.shape = shape.with_scope(Scope(origin, rotation, scope.size))
        return
    object_origin, object_axes = object_frame(state)
    pivot_origin, pivot_axes = pivot_frame(state)
    if kind == "p":
        position = object_axes.T @ (np.asarray(pivot_origin, float) - object_origin)
        position[k] = value
        pivot_origin = object_origin + object_axes @ position
    else:
        angles = euler_angles(object_axes.T @ np.asarray(pivot_axes, float))
        angles[k] = value
        pivot_axes = object_axes @ euler_matrix(angles)
    state.pivot = (np.asarray(pivot_origin, float), np.asarray(pivot_axes, float))


def compile_shape_write(program, node, params):
    """The operation of ``set(scope.tx, v)``, ``set(pivot.ox, v)``... (``node.attribute`` one of
    :data:`WRITABLE`)."""
    attribute = node.attribute
    value = program.number(node, node.value, params, f"set({attribute}, ...)'s value")

    def set_shape(state, args, out):
        write_shape_attribute(state, attribute, value(args, state))
        return True

    return set_shape
