"""``rectify(angle)`` (op_rectify): edges that are within ``angle`` degrees (0-45) of a scope
axis made parallel to it.

As the reference describes: of the scope's planes xy, yz and zx the one most parallel to the
shape (the largest component of the summed face area vectors) is the projection plane; an edge
whose projection on it is less than ``angle`` from one of the plane's two axes is aligned with
that axis, so the two vertices it joins take one coordinate across it. Edges aligned with the
same axis that share a vertex move together. Where the vertices go is not published: shapegen
gives each group of vertices the mean of their coordinates, and warns that the result may differ
from CityEngine's in where the aligned edges lie (their directions are the reference's). A flat
shape stays in its plane; the scope keeps its axes and is fitted to the new geometry.
"""

from __future__ import annotations

__all__ = ["rectified"]

import math

import numpy as np

from shapegen.engine.operations.cga.arguments import plain_arguments, typed
from shapegen.engine.operations.cga.scope_ops import refit, shape_with_faces
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.shape import Shape
from shapegen.geometry.mesh import Mesh
from shapegen.tolerances import COINCIDENT_REL, COSINE_SLACK


def _groups(count: int, pairs: list[tuple[int, int]]) -> np.ndarray:
    """The connected group of each of ``count`` items joined by ``pairs`` (union-find)."""
    parent = list(range(count))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b in pairs:
        parent[root(a)] = root(b)
    return np.array([root(i) for i in range(count)])


def rectified(mesh: Mesh, angle: float) -> Mesh:
    """``mesh`` (scope coordinates) with its edges within ``angle`` degrees of an axis of the
    projection plane made parallel to that axis."""
    vertices = np.array(mesh.vertices, float)
    normals = mesh.face_normals() * mesh.face_areas()[:, None]
    normal_axis = int(np.argmax(np.abs(normals.sum(axis=0))))
    u, v = (k for k in range(3) if k != normal_axis)
    limit = math.tan(math.radians(angle))
    along = {u: [], v: []}  # axis -> edges to make parallel to it
    for a, b in mesh.edges:
        d = vertices[b] - vertices[a]
        du, dv = abs(float(d[u])), abs(float(d[v]))
        if du > 0 and dv < du * limit:
            along[u].append((a, b))
        elif dv > 0 and du < dv * limit:
            along[v].append((a, b))
    for axis, other in ((u, v), (v, u)):  # parallel to u: one v coordinate, and the reverse
        groups = _groups(len(vertices), along[axis])
        for group in np.unique(groups):
            members = groups == group
            if members.sum() > 1:
                vertices[members, other] = vertices[members, other].mean()
    units = mesh.face_normals()
    if mesh.n_faces and np.allclose(units, units[0], atol=COSINE_SLACK):
        offsets = [float(units[0] @ mesh.vertices[f[0]]) for f in mesh.faces]
        n = units[0]
        if np.ptp(offsets) <= COINCIDENT_REL * max(1.0, mesh.size()) and abs(n[normal_axis]) > 0:
            # one plane: the vertices slide along it, off the projection plane's normal
            rest = vertices @ n - vertices[:, normal_axis] * n[normal_axis]
            vertices[:, normal_axis] = (offsets[0] - rest) / n[normal_axis]
    return Mesh(vertices, mesh.faces)


@operation(
    "rectify",
    partial="aligned edges take their vertices' mean coordinate (CityEngine's placement is "
    "not published), with a warning",
)
def compile_rectify(program, node, params):
    (angle,) = plain_arguments(program, node, (1,))
    angle_of = typed(program, node, angle, params, float, "the angle")

    def rectify(state, args, out):
        shape = shape_with_faces(program, node, state)
        angle = angle_of(args, state)
        if not 0 <= angle <= 45:
            warn_at(state, node, f"rectify(): the angle is in [0, 45] degrees; {angle:g} is "
                                 f"taken as {min(max(angle, 0.0), 45.0):g}")  # fmt: skip
            angle = min(max(angle, 0.0), 45.0)
        warn_at(state, node, "rectify(): the aligned edges' vertices take their mean coordinate; "
                             "CityEngine's placement is not published and may differ")  # fmt: skip
        mesh = rectified(shape.mesh(), angle)
        fitted = refit(Shape.with_geometry(shape.scope, mesh, shape.kind, shape.normal_axis),
                       shape.scope.rotation)  # fmt: skip
        state.shape = fitted
        return True

    return rectify
