"""The reserve a design is judged with, and the forces that stood with it moved to the full joints.

A reserve (a margin ``M`` in [0, 1)) is kept against both ways a joint fails
(:func:`with_reserve`): every joint polygon is shrunk about its area centroid to ``1 - M`` of its
size (the kern: against hinging, the resultant stays inside a smaller polygon), and the friction
coefficient is lowered to ``1 - M`` of itself (against sliding: the joint shrinking leaves the
friction a joint can hold unchanged, so a design that stands with a reserve could still stand
on the edge of sliding). A design that stands with a reserve stands without one.

Forces that stand with a reserve certify the design without it, without a solve
(:func:`widened_forces`). A shrunk vertex
``p' = c + r (p - c)`` (``r`` the ratio of the two kerns, at most 1) is a convex combination of
the wider polygon's vertices, ``p' = r p + (1 - r) c`` with the centroid itself a convex
combination of the vertices (fan triangles: each triangle's area over three to each of its
corners). A force at ``p'`` spread over the vertices with those weights keeps its resultant and
its moment, and since every vertex of a joint shares the joint's frame, compression stays
compression and friction stays inside the pyramid (or the cone), which only widens with the
full friction coefficient. So the forces that showed the design standing with the reserve
are moved, not solved for again.
"""

from __future__ import annotations

__all__ = ["widened_forces", "with_reserve"]

import dataclasses

import numpy as np

from shapegen.statics.assembly import StaticsProblem
from shapegen.statics.statics_options import Reserve, StaticsOptions


def with_reserve(
    options: StaticsOptions, margin: Reserve | float, friction: float
) -> StaticsOptions:
    """``options`` judging with a reserve ``margin`` (a
    :class:`~shapegen.statics.statics_options.Reserve`, or a number in [0, 1) made one): every
    joint shrunk to ``1 - margin`` of the kern and the friction coefficient
    (``options.friction``, else the model's ``friction``) lowered to ``1 - margin`` of itself.

    >>> reserved = with_reserve(StaticsOptions(), 0.1, friction=0.7)
    >>> round(reserved.kern, 3), round(reserved.friction, 3)
    (0.9, 0.63)
    """
    margin = Reserve.of(margin)
    if margin == 0:
        return options
    mu = options.friction if options.friction is not None else friction
    return dataclasses.replace(options.shrunk(margin), friction=(1.0 - margin) * float(mu))


def widened_forces(
    narrow: StaticsProblem, wide: StaticsProblem, x: np.ndarray
) -> np.ndarray | None:
    """The variables ``x`` of ``narrow`` (scaled ``[c, s, u, t]``) moved to ``wide``'s vertices.

    Both problems must come from the same model and interfaces with ``narrow.kern <=
    wide.kern`` and ``narrow.friction <= wide.friction`` (same vertices in the same order, the
    same pyramid or cone); otherwise None.
    """
    m = wide.n_vertices
    if (
        narrow.n_vertices != m
        or narrow.kern > wide.kern
        or narrow.pyramid != wide.pyramid
        or narrow.friction > wide.friction
        or not np.array_equal(narrow.vertex_interface, wide.vertex_interface)
        or narrow.weight != wide.weight
    ):
        return None
    if m == 0:
        return np.asarray(x, float).copy()
    ratio = narrow.kern / wide.kern
    owner = wide.vertex_interface
    ni = int(owner[-1]) + 1
    beta = _centroid_weights(wide.vertex_points, wide.vertex_interface, ni, wide.interfaces)
    forces = np.asarray(x, float).reshape(4, m)
    totals = np.stack([np.bincount(owner, row, minlength=ni) for row in forces])  # (4, ni)
    return (ratio * forces + (1.0 - ratio) * beta[None, :] * totals[:, owner]).ravel()


def _centroid_weights(points: np.ndarray, owner: np.ndarray, ni: int, interfaces) -> np.ndarray:
    """Per vertex, its weight in its polygon's area centroid (the weights of a polygon sum to
    one; the plain mean for a degenerate polygon, as ``polygon_centroids``)."""
    m = len(points)
    counts = np.bincount(owner, minlength=ni)
    starts = np.concatenate([[0], np.cumsum(counts)])
    normals = np.array([i.normal for i in interfaces], float).reshape(-1, 3)
    apex_index = starts[:-1][owner]
    nxt = np.arange(m) + 1
    nxt[starts[1:] - 1] = starts[:-1]
    apex = points[apex_index]
    b, c = points, points[nxt]
    area = np.einsum("ij,ij->i", np.cross(b - apex, c - apex), normals[owner])  # twice, per fan
    total = np.bincount(owner, area, minlength=ni)
    weights = np.bincount(apex_index, area, minlength=m)
    weights += area + np.bincount(nxt, area, minlength=m)
    good = total > 0
    beta = np.empty(m)
    usable = good[owner]
    beta[usable] = weights[usable] / (3.0 * total[owner][usable])
    beta[~usable] = 1.0 / counts[owner][~usable]
    return beta
