"""Even ridges: CityEngine's ``even`` option of roofHip and roofGable, which makes each ridge of
a skeleton roof level (op_roofHip: "the gable edges are forced to be horizontal ... non-planar
roof faces originate").

A ridge is where the planes of two edges facing each other meet: a skeleton arc between two
nodes inside the face whose two faces' edges have inward normals more than 120 degrees apart.
Ridges that share a node are one ridge; each gets the average height of its nodes. Measured
with PyPRT 1.12 (tests/data/prt_roofs.json): a trapezoid's sloping ridge is levelled, an L's
two ridges (2.5 and 3 m of wavefront) stay apart and as they are, and an L with skewed arms
levels its two ridges each on its own, where one average over every node would have joined
them. (On faces with holes PyPRT levels more than this; roofs.py refuses even roofs there.)
"""

from __future__ import annotations

__all__ = ["even_ridge_times"]

import numpy as np

from shapegen.geometry.skeleton import Skeleton

FACING = -0.5  # cos of the least angle between the inward normals of a ridge's two edges


def even_ridge_times(skeleton: Skeleton, normals: np.ndarray, eps: float) -> np.ndarray:
    """The skeleton's node times with each ridge's nodes at their average time.

    ``normals``: the ``(n, 2)`` inward unit normals of the edges of ``skeleton.faces``;
    ``eps``: the distance (the polygon's units) within which two nodes are one point.
    """
    # scipy.spatial costs a process ~0.17 s to import: loaded by the first even roof, not by
    # every rule that registers the roof operations (a city's worker and parent alike)
    from scipy.spatial import cKDTree

    nodes, times = skeleton.nodes, skeleton.times
    same = np.arange(len(nodes))  # each node's first coincident node
    for i, j in sorted(cKDTree(nodes).query_pairs(eps)):
        same[j] = min(same[j], same[i])
    group = np.arange(len(nodes))

    def find(k: int) -> int:
        while group[k] != k:
            group[k] = group[group[k]]
            k = group[k]
        return k

    inside = times > eps
    sides: dict[tuple[int, int], list[int]] = {}
    for k, face in enumerate(skeleton.faces):
        ring = [int(same[i]) for i in face]
        ring = [p for j, p in enumerate(ring) if p != ring[j - 1]]
        for a, b in zip(ring, ring[1:] + ring[:1], strict=True):
            sides.setdefault((min(a, b), max(a, b)), []).append(k)
    for (a, b), faces in sides.items():
        if len(faces) == 2 and inside[a] and inside[b] and a != b:
            if normals[faces[0]] @ normals[faces[1]] < FACING:
                group[find(a)] = find(b)
    roots = np.array([find(int(same[k])) for k in range(len(nodes))])
    out = times.copy()
    for root in np.unique(roots[inside]):
        members = np.unique(same[(roots == root) & inside])
        out[(roots == root) & inside] = times[members].mean()
    return out
