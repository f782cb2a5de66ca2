"""Contact interfaces between blocks (or a block and a support)."""

from __future__ import annotations

__all__ = ["Interface", "GROUND"]

from dataclasses import dataclass
from functools import cached_property

import numpy as np

GROUND = -1  # the ``second`` index of a contact with the ground plane


@dataclass(frozen=True, eq=False)
class Interface:
    """The contact polygon between block ``first`` and block ``second`` (indices into
    ``model.blocks``; ``second`` is :data:`GROUND` for the ground plane).

    ``normal`` is the unit normal pointing from ``first`` into ``second``; a compressive force
    pushes ``second`` along ``+normal``. ``tangent1``, ``tangent2`` complete a right-handed frame
    (tangent1 x tangent2 = normal). ``vertices`` is the ``(k, 3)`` convex polygon (m),
    counter-clockwise about ``normal``.
    """

    first: int
    second: int
    normal: np.ndarray
    tangent1: np.ndarray
    tangent2: np.ndarray
    vertices: np.ndarray

    @cached_property
    def area(self) -> float:
        """m^2."""
        p = self.vertices - self.vertices[0]  # relative: far-away coordinates cancel badly
        return 0.5 * float(np.dot(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0), self.normal))

    @cached_property
    def centroid(self) -> np.ndarray:
        """Area centroid of the polygon, m."""
        p = self.vertices
        a, b, c = p[0], p[1:-1], p[2:]
        w = np.einsum("ij,j->i", np.cross(b - a, c - a), self.normal)
        if w.sum() <= 0:
            return p.mean(axis=0)
        return (w[:, None] * (a + b + c)).sum(axis=0) / (3 * w.sum())

    def scaled(self, factor: float) -> Interface:
        """The polygon scaled about its centroid by ``factor`` (the kern: 1/3 = middle third)."""
        c = self.centroid
        return Interface(
            self.first, self.second, self.normal, self.tangent1, self.tangent2,
            c + factor * (self.vertices - c),
        )  # fmt: skip


def tangent_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents with t1 x t2 = normal, chosen deterministically from the normal."""
    n0, n1, n2 = (float(v) for v in normal)
    # the cross products written out as numpy's cross computes them (the same roundings):
    # its call costs ten times these few products, once per distinct normal of a model
    if abs(n0) < 0.9:  # helper (1, 0, 0)
        t1 = np.array([0.0 * n2 - 0.0 * n1, 0.0 * n0 - 1.0 * n2, 1.0 * n1 - 0.0 * n0])
    else:  # helper (0, 0, 1)
        t1 = np.array([0.0 * n2 - 1.0 * n1, 1.0 * n0 - 0.0 * n2, 0.0 * n1 - 0.0 * n0])
    t1 /= np.linalg.norm(t1)
    a0, a1, a2 = t1.tolist()
    t2 = np.array([n1 * a2 - n2 * a1, n2 * a0 - n0 * a2, n0 * a1 - n1 * a0])
    return t1, t2
