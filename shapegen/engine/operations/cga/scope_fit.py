"""``alignScopeToGeometryBBox(alignAxes)`` (op_alignScopeToGeometryBBox): two scope axes turned
about the third so that they span the minimum-area rectangle around the geometry as seen along
the third axis, which stays as it is. The first named axis (``x`` of ``xz``, ``z`` of ``zx``)
runs along the rectangle's longer side, in the direction closest to where it pointed (the
reference leaves the sign open); the geometry stays in place, the scope is fitted to it and the
pivot is put at the scope's origin.
"""

from __future__ import annotations

__all__ = ["minimum_rectangle_direction"]

import numpy as np

from shapegen.engine.operations.cga.arguments import choice, plain_arguments
from shapegen.engine.operations.cga.scope_ops import (
    refit,
    set_scope_pivot,
    shape_with_faces,
)
from shapegen.engine.operations.registry import operation
from shapegen.tolerances import ROUNDOFF_REL

_AXIS_PAIRS = ("xy", "yx", "xz", "zx", "yz", "zy")


def minimum_rectangle_direction(points: np.ndarray) -> np.ndarray:
    """The unit direction (2D) of the longer side of the minimum-area rectangle enclosing
    ``points`` ``(n, 2)`` (rotating calipers over the convex hull's edges); for points on a
    line, that line's direction; ``(1, 0)`` for a single point."""
    # scipy.spatial takes 0.3-0.6 s to import: loaded when a rule first aligns a scope to its
    # geometry, not with every build
    from scipy.spatial import ConvexHull, QhullError

    points = np.asarray(points, float)
    spread = points - points.mean(axis=0)
    if np.abs(spread).max(initial=0.0) == 0.0:
        return np.array([1.0, 0.0])
    try:
        hull = points[ConvexHull(points).vertices]
    except QhullError:  # collinear: the principal direction
        _, _, vt = np.linalg.svd(spread, full_matrices=False)
        return vt[0]
    edges = np.roll(hull, -1, axis=0) - hull
    lengths = np.linalg.norm(edges, axis=1)
    edges, lengths = edges[lengths > 0], lengths[lengths > 0]
    best = None
    for direction in edges / lengths[:, None]:
        normal = np.array([-direction[1], direction[0]])
        along, across = hull @ direction, hull @ normal
        width, depth = np.ptp(along), np.ptp(across)
        area = width * depth
        if best is None or area < best[0] * (1 - ROUNDOFF_REL):
            best = (area, direction if width >= depth else normal)
    return best[1]


@operation("alignScopeToGeometryBBox")
def compile_align_scope_to_geometry_bbox(program, node, params):
    (pair,) = plain_arguments(program, node, (1,))
    first, second = ("xyz".index(c) for c in choice(program, node, pair, _AXIS_PAIRS, "the axes"))
    fixed = 3 - first - second

    def align(state, args, out):
        shape = shape_with_faces(program, node, state)
        old = shape.scope.rotation
        world = shape.scope.to_world(shape.mesh().vertices)
        low, high = sorted((first, second))  # the plane's coordinates, in scope order
        flat = np.column_stack([world @ old[:, low], world @ old[:, high]])
        d = minimum_rectangle_direction(flat)
        longer = d[0] * old[:, low] + d[1] * old[:, high]
        if float(longer @ old[:, first]) < 0:
            longer = -longer  # the turn closest to the axis it replaces
        axes = np.zeros((3, 3))
        axes[:, first] = longer
        axes[:, fixed] = old[:, fixed]
        cyclic = (second - first) % 3 == 1  # x->y, y->z, z->x: second = fixed x first
        axes[:, second] = (
            np.cross(axes[:, fixed], longer) if cyclic else np.cross(longer, axes[:, fixed])
        )
        state.shape = refit(shape, axes)
        set_scope_pivot(state)
        return True

    return align
