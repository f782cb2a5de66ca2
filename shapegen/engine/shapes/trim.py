"""Trim planes on shapes: made by ``comp(f)`` in CityEngine rule files, applied by inserts.

``comp(f) { sel : X }`` (the ``:`` operator only; op_comp) gives each face's shape the planes
bisecting the angles at the edges it shares with the other faces
(:mod:`shapegen.geometry.trim`); the shape's successors inherit them, and a later ``comp(f)``
gives its faces their own. ``i()``, the primitives and ``trim()`` cut the shape's geometry to
the planes ``trim.vertical`` / ``trim.horizontal`` enable (vertical ones by default), and the
scope is fitted to what is left (in its own axes). Rule files
in shapegen's own ``.grammar`` dialect make no trim planes, so their blocks are never cut.
"""

from __future__ import annotations

__all__ = ["apply_trim", "comp_trim_planes"]

import numpy as np

from shapegen.engine.shapes.shape import Shape
from shapegen.geometry.scope_frames import fitted_scope
from shapegen.geometry.trim import deferred_face_trim_planes, moved_cut, trimmed


def comp_trim_planes(shape: Shape, faces: list[Shape]) -> list[tuple]:
    """The trim planes of each face of ``shape``'s geometry, whose ``comp(f)`` components are
    ``faces`` (in the geometry's face order): classified in each face's own frame."""
    mesh = shape.mesh()
    ups = np.array([face.scope.axis(1) for face in faces])
    return deferred_face_trim_planes(shape.scope.to_world(mesh.vertices), mesh.faces, ups)


def apply_trim(state) -> bool:
    """Cut ``state.shape`` to its enabled trim planes; False when nothing of it is left."""
    planes = state.trim_planes
    if not planes:
        return True
    vertical = state.attrs.get("trim.vertical", True)
    horizontal = state.attrs.get("trim.horizontal", False)
    active = [p for p in planes if (horizontal if p.horizontal else vertical)]
    if not active:
        return True
    shape = state.shape
    mesh = shape.mesh()
    cut = trimmed(mesh, shape.scope.o, shape.scope.r, active)
    if cut is None:
        return False
    if cut is not mesh:
        # the scope fitted to what the cut left, in its axes: PyPRT's parthenon splits its
        # raking simas, cubes cut at the ridge, over the cut's length (two pieces of 2.55 m
        # on 5.10 m), not over the cube's 5.46 m (three pieces)
        world = shape.scope.to_world(cut.vertices)
        scope, local = fitted_scope(world, shape.scope.rotation)
        cut = moved_cut(cut, local)
        state.shape = Shape.with_geometry(scope, cut, shape.kind, shape.normal_axis)
    return True
