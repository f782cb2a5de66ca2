"""Connected components of an undirected graph given by its edges, in numpy.

The statics (a model's bodies, the blocks the ground carries) and the mesh reader each ask for
one labelling of a few thousand nodes per run. scipy's ``csgraph`` answers it, but importing it
brings ``scipy.sparse.linalg`` and costs about 0.15 s of CPU a process, more than the search
itself; this one is a few vectorised passes (hooking each root to the smaller root of an edge's
other end, then halving the paths until every node points at its root).

>>> count, label = connected_components(5, [0, 3], [1, 4])
>>> int(count), label.tolist()
(3, [0, 0, 1, 2, 2])
"""

from __future__ import annotations

__all__ = ["connected_components"]

import numpy as np


def connected_components(n: int, first, second) -> tuple[int, np.ndarray]:
    """The components of the graph of nodes ``0 .. n - 1`` with the edges ``first[k]`` --
    ``second[k]`` (the direction does not matter, self loops and repeated edges are fine).

    Returns
    -------
    tuple
        ``(count, label)``: the number of components and ``(n,)`` the component of each node,
        numbered ``0 .. count - 1`` in the order of their lowest node (scipy's numbering).
    """
    first = np.asarray(first, dtype=np.int64).ravel()
    second = np.asarray(second, dtype=np.int64).ravel()
    root = np.arange(n, dtype=np.int64)
    while len(first):
        a, b = root[first], root[second]
        apart = a != b
        if not np.any(apart):
            break
        a, b = a[apart], b[apart]
        # hook the larger root under the smaller: a node's root is never above the node, so
        # the roots only fall and the loop ends
        np.minimum.at(root, np.maximum(a, b), np.minimum(a, b))
        while True:  # halve the paths until each node points at its root
            jumped = root[root]
            if np.array_equal(jumped, root):
                break
            root = jumped
        first, second = first[apart], second[apart]
    roots, label = np.unique(root, return_inverse=True)
    return len(roots), label.ravel()
