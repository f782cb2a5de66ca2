"""CGA's coordinate systems: the world, object, pivot and scope frames of a shape, and CGA's
Euler angles (cga_eulerAngles). ``convert()``, ``translate()``, ``rotate()``, ``pivot.*``,
``initialShape.origin.*`` and (in ``.cga`` files) ``scope.t*`` / ``scope.r*`` read them.

A frame is ``(origin, axes)`` in world coordinates (m): a point and a 3 x 3 matrix whose columns
are the frame's x, y and z axes.

- world: the scene's origin and axes (y up);
- object: the initial shape's, "placed at the first point of the initial shape's first edge",
  x along that edge, y along its normal (``initialShape.origin``); for ``lot=(w, d)`` the
  first edge runs from (0, 0, d) along +x, as in the lots the corpus references were made on;
- pivot: the shape's own (attr_pivot). ``comp`` puts it at a component's first vertex with the
  component's axes, ``setPivot``, ``alignScopeToAxes``, ``alignScopeToGeometry`` and
  ``alignScopeToGeometryBBox`` at the new scope's origin and axes, ``resetGeometry`` back to
  the object frame; the other operations keep it. Until one of them runs it is the object
  frame;
- scope: the shape's scope origin and axes.
"""

from __future__ import annotations

__all__ = [
    "FRAMES",
    "euler_angles",
    "euler_matrix",
    "frame_of",
    "in_frame",
    "object_frame",
    "pivot_frame",
]

import math
from collections.abc import Sequence

import numpy as np

from shapegen.model.scope import Scope

Frame = tuple[np.ndarray, np.ndarray]

#: The coordinate systems a rule names (func_convert, op_translate, op_rotate).
FRAMES = ("scope", "pivot", "object", "world")


def euler_matrix(angles: Sequence[float]) -> np.ndarray:
    """The rotation of CGA's Euler angles (degrees): about x, then y, then z, fixed axes
    (cga_eulerAngles' matrix, ``Rz(c) Ry(b) Rx(a)``)."""
    a, b, c = (math.radians(float(v)) for v in angles)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def euler_angles(rotation: np.ndarray) -> list[float]:
    """CGA's Euler angles (degrees) of a rotation matrix, the inverse of :func:`euler_matrix`
    (the y angle in [-90, 90])."""
    r = np.asarray(rotation, float)
    return [
        math.degrees(math.atan2(r[2, 1], r[2, 2])),
        math.degrees(-math.asin(max(-1.0, min(1.0, float(r[2, 0]))))),
        math.degrees(math.atan2(r[1, 0], r[0, 0])),
    ]


def object_frame(state) -> Frame:
    """The object frame of the derivation of ``state``: the initial shape's first vertex and
    its scope's axes (x along the first edge, y up)."""
    run = state.run
    start = getattr(run, "start_shape", None)
    if start is None:  # attrs evaluated outside a derivation: the lot's rectangle
        start = state.shape
    scope = start.scope
    first = start.mesh().vertices[0]
    return scope.to_world(first), np.asarray(scope.rotation, float)


def pivot_frame(state) -> Frame:
    """The pivot of ``state`` (the object frame until an operation set one)."""
    pivot = getattr(state, "pivot", None)
    if pivot is None:
        return object_frame(state)
    origin, axes = pivot
    if isinstance(axes, Scope):  # comp's: the component's first corner and scope, kept as
        return np.asarray(origin, float), axes.rotation  # given until a rule reads them
    return pivot


def frame_of(state, system: str) -> Frame:
    """The frame ``system`` (one of :data:`FRAMES`) of the shape ``state``. Raises
    ``ValueError`` for another name."""
    if system == "scope":
        scope = state.shape.scope
        return np.asarray(scope.origin, float), np.asarray(scope.rotation, float)
    if system == "pivot":
        return pivot_frame(state)
    if system == "object":
        return object_frame(state)
    if system == "world":
        return np.zeros(3), np.eye(3)
    raise ValueError(f"the coordinate systems are {', '.join(FRAMES)}, got {system!r}")


def in_frame(frame: Frame, origin: np.ndarray, axes: np.ndarray) -> tuple[np.ndarray, list]:
    """A world position and orientation given in ``frame``: its coordinates and its Euler
    angles (degrees)."""
    frame_origin, frame_axes = frame
    position = frame_axes.T @ (np.asarray(origin, float) - frame_origin)
    return position, euler_angles(frame_axes.T @ np.asarray(axes, float))
