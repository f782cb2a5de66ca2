"""The compression-only part of a solution of the block QP: the forces a certificate is made of.

Tensions are dropped, compressions clipped at zero and each vertex's friction shrunk radially
into its pyramid (or its cone), so what is left obeys the joints' laws exactly; whether it still
holds the blocks in equilibrium is what :func:`~shapegen.statics.analysis.certify` measures.
"""

from __future__ import annotations

__all__ = ["compression_only"]

import numpy as np


def compression_only(problem, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(forces, compression, reserve)``: ``x`` (the QP's ``[c, s, u, t]`` per vertex) with its
    tensions dropped, compressions clipped and friction shrunk into the pyramid or cone of
    ``problem``; each vertex's compression (N) and what its friction could still take (N)."""
    m = problem.n_vertices
    c, _, u, t = x.reshape(4, m)
    c = np.maximum(c, 0.0)
    if problem.second_order:
        capacity = problem.friction * c
        demand = np.hypot(u, t)
    else:
        sides = problem.cone[:-1]
        capacity = -sides[0, 0] * c  # mu cos(pi/K) c, the same for every side
        demand = np.max(np.outer(u, sides[:, 1]) + np.outer(t, sides[:, 2]), axis=1) if m else c
    with np.errstate(divide="ignore", invalid="ignore"):
        shrink = np.where(demand > capacity, capacity / np.where(demand > 0, demand, 1.0), 1.0)
    shrink = np.clip(shrink, 0.0, 1.0)
    reserve = np.maximum(capacity - demand * shrink, 0.0)
    return np.concatenate([c, np.zeros(m), u * shrink, t * shrink]), c, reserve
