"""Exact mass properties of a convex block: the inertia tensor and its principal frame.

The tensor is integrated in closed form over a tetrahedral decomposition: every face triangle
forms a tetrahedron with the block's centroid, and the second moment of a tetrahedron with one
vertex at the origin and edge vectors ``a, b, c`` is

    integral of x x^T dV = det[a b c] / 120 * (a a^T + b b^T + c c^T + s s^T),   s = a + b + c

(the canonical tetrahedron's covariance ``(I + 1 1^T) / 120`` mapped by the matrix ``[a b c]``).
Signed determinants make the sum exact for any closed polyhedron with outward faces.
"""

from __future__ import annotations

__all__ = ["PrincipalInertia", "inertia_tensor", "principal_inertia"]

from dataclasses import dataclass

import numpy as np

from shapegen.model.block import Block


@dataclass(frozen=True)
class PrincipalInertia:
    """A block's mass properties in its principal frame.

    Attributes
    ----------
    mass
        kg.
    centroid
        Centre of mass, metres (world).
    moments
        ``(3,)`` principal moments of inertia about the centroid, kg m^2, ascending.
    axes
        ``(3, 3)`` rotation whose columns are the principal axes in world coordinates
        (a proper rotation: determinant +1). A point's body coordinates are
        ``axes.T @ (x - centroid)``.
    """

    mass: float
    centroid: np.ndarray
    moments: np.ndarray
    axes: np.ndarray


def inertia_tensor(block: Block) -> np.ndarray:
    """The ``(3, 3)`` inertia tensor of ``block`` about its centroid, world axes, kg m^2.

    Uses the block's density (kg/m^3); exact for the polyhedron.
    """
    triangles = block.fan_triangles - block.centroid  # (t, 3 corners, 3 coordinates)
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    determinants = np.einsum("ij,ij->i", a, np.cross(b, c))
    s = a + b + c
    second_moment = np.einsum(
        "t,tij->ij",
        determinants / 120.0,
        np.einsum("ti,tj->tij", a, a)
        + np.einsum("ti,tj->tij", b, b)
        + np.einsum("ti,tj->tij", c, c)
        + np.einsum("ti,tj->tij", s, s),
    )
    second_moment *= block.density
    return np.trace(second_moment) * np.eye(3) - second_moment


def principal_inertia(block: Block) -> PrincipalInertia:
    """The block's mass, centroid, principal moments (kg m^2) and principal axes."""
    moments, axes = np.linalg.eigh(inertia_tensor(block))
    if np.linalg.det(axes) < 0:  # eigenvectors have arbitrary signs; keep a right-handed frame
        axes[:, 2] = -axes[:, 2]
    return PrincipalInertia(
        mass=float(block.mass),
        centroid=np.asarray(block.centroid, float).copy(),
        moments=np.maximum(moments, 0.0),
        axes=axes,
    )
