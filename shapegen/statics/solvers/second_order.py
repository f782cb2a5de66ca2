"""Three-dimensional second-order cones in batch: the exact friction cone of every vertex.

A vector ``x = (x0, x1, x2)`` is in the cone Q when ``x0 >= ||(x1, x2)||``. The interior point
method of :mod:`~shapegen.statics.solvers.reduced` keeps one slack ``s_v`` and one dual ``z_v``
in Q per vertex and linearises their complementarity ``s_v o z_v = mu e`` (the Jordan product
``x o y = (x . y, x0 y1 + y0 x1)``, identity ``e = (1, 0, 0)``) in the Nesterov-Todd scaling:
the symmetric ``W_v`` with ``W_v z_v = W_v^-1 s_v = lambda_v`` (Nesterov, Todd 1997; the formulas
as in Vandenberghe's CVXOPT notes, "The CVXOPT linear and quadratic cone program solvers",
2010). Its ``W_v^-2`` is a 3x3 block that joins the per-vertex Hessian block of ``(c, u, t)``, so
the normal equations keep their sparsity pattern.

All functions take ``(m, 3)`` arrays (one cone per row) and are vectorised with numpy.
"""

from __future__ import annotations

__all__ = [
    "Scaling",
    "cone_det",
    "scaling",
    "jordan_product",
    "jordan_divide",
    "step_to_boundary",
    "interior",
]

from dataclasses import dataclass

import numpy as np

_J = np.array([1.0, -1.0, -1.0])  # the cone's reflection: x . J x = x0^2 - ||x1||^2


def cone_det(x: np.ndarray) -> np.ndarray:
    """``x0^2 - ||(x1, x2)||^2`` per row, as a product of two factors (no cancellation of
    squares when ``x`` is near the boundary)."""
    radius = np.hypot(x[:, 1], x[:, 2])
    return (x[:, 0] - radius) * (x[:, 0] + radius)


_HALF = np.sqrt(0.5)


@dataclass
class Scaling:
    """Nesterov-Todd scaling of one cone per row, kept in its eigenvectors.

    ``W = V diag(values) V^T`` with the orthonormal ``V`` known in closed form, columns
    ``(1, n) / sqrt 2``, ``(1, -n) / sqrt 2`` and ``(0, n_perp)``: near the optimum ``W^-2`` spans
    twenty orders of magnitude, and a product with the assembled matrix would lose its small
    eigenvalues (the directions the cone leaves free) to cancellation, while in this form each
    direction keeps its own digits. The products are written out per component: a batched
    3x3 ``einsum`` costs several times as much on 100 000 vertices.

    Attributes
    ----------
    direction
        ``(m, 2)`` the unit vector ``n``.
    values
        ``(m, 3)`` the eigenvalues of ``W``: ``eta (w0 + |w1|)``, ``eta / (w0 + |w1|)``,
        ``eta``.
    lam
        ``(m, 3)`` ``lambda = W z = W^-1 s``, the scaled point (in the interior of Q).
    """

    direction: np.ndarray
    values: np.ndarray
    lam: np.ndarray

    def __post_init__(self) -> None:
        inverse = 1.0 / self.values
        self._powers = {1: self.values, -1: inverse, -2: inverse * inverse}

    def power_values(self, power: int) -> np.ndarray:
        """``(m, 3)`` eigenvalues of ``W^power`` (``power`` 1, -1 or -2)."""
        return self._powers[power]

    def to_basis(self, x: np.ndarray) -> np.ndarray:
        """``V^T x`` per row."""
        n = self.direction
        along = n[:, 0] * x[:, 1] + n[:, 1] * x[:, 2]
        out = np.empty_like(x)
        out[:, 0] = _HALF * (x[:, 0] + along)
        out[:, 1] = _HALF * (x[:, 0] - along)
        out[:, 2] = n[:, 0] * x[:, 2] - n[:, 1] * x[:, 1]
        return out

    def from_basis(self, local: np.ndarray) -> np.ndarray:
        """``V local`` per row."""
        n = self.direction
        out = np.empty_like(local)
        out[:, 0] = _HALF * (local[:, 0] + local[:, 1])
        radial = _HALF * (local[:, 0] - local[:, 1])
        out[:, 1] = radial * n[:, 0] - local[:, 2] * n[:, 1]
        out[:, 2] = radial * n[:, 1] + local[:, 2] * n[:, 0]
        return out

    def basis(self) -> np.ndarray:
        """``(m, 3, 3)`` ``V`` itself."""
        n = self.direction
        out = np.zeros((len(n), 3, 3))
        out[:, 0, 0] = out[:, 0, 1] = _HALF
        out[:, 1:, 0] = _HALF * n
        out[:, 1:, 1] = -_HALF * n
        out[:, 1, 2], out[:, 2, 2] = -n[:, 1], n[:, 0]
        return out

    def apply(self, power: int, x: np.ndarray) -> np.ndarray:
        """``W^power x`` per row (``power`` 1, -1 or -2)."""
        return self.from_basis(self.to_basis(x) * self._powers[power])


def scaling(s: np.ndarray, z: np.ndarray) -> Scaling:
    """The Nesterov-Todd scaling of slacks ``s`` and duals ``z`` (both in the interior of Q).

    With ``s_ = s / sqrt(det s)``, ``z_ = z / sqrt(det z)``, ``gamma = sqrt((1 + s_ . z_) / 2)``,
    ``w = (s_ + J z_) / (2 gamma)`` (so ``w . J w = 1``) and ``eta = (det s / det z)^(1/4)``:
    ``W = eta [[w0, w1^T], [w1, I + w1 w1^T / (1 + w0)]]``, whose eigenvalues are
    ``eta (w0 +- |w1|)`` along ``(1, +-n)`` (``n = w1 / |w1|``) and ``eta`` along ``(0, n_perp)``
    (``w0 - |w1| = 1 / (w0 + |w1|)``, without cancellation).
    """
    det_s, det_z = cone_det(s), cone_det(z)
    root_s, root_z = np.sqrt(det_s), np.sqrt(det_z)
    s_unit = s / root_s[:, None]
    z_unit = z / root_z[:, None]
    gamma = np.sqrt(0.5 * (1.0 + np.einsum("vi,vi->v", s_unit, z_unit)))
    w = (s_unit + z_unit * _J) / (2.0 * gamma[:, None])
    eta = np.sqrt(root_s / root_z)
    radius = np.hypot(w[:, 1], w[:, 2])
    safe = radius > 0
    n = np.where(safe[:, None], w[:, 1:] / np.where(safe, radius, 1.0)[:, None], [1.0, 0.0])
    big = w[:, 0] + radius
    values = eta[:, None] * np.stack([big, 1.0 / big, np.ones(len(s))], axis=1)
    # lambda from the normalised pair (CVXOPT's formula): W z itself would lose the small
    # components of lambda to cancellation near the boundary
    lam = np.empty_like(s)
    lam[:, 0] = gamma
    lam[:, 1:] = (
        (gamma + z_unit[:, 0])[:, None] * s_unit[:, 1:]
        + (gamma + s_unit[:, 0])[:, None] * z_unit[:, 1:]
    ) / (s_unit[:, 0] + z_unit[:, 0] + 2.0 * gamma)[:, None]
    lam *= np.sqrt(root_s * root_z)[:, None]
    return Scaling(n, values, lam)


def jordan_product(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``x o y = (x . y, x0 y1 + y0 x1)`` per row."""
    out = np.empty_like(x)
    out[:, 0] = np.einsum("vi,vi->v", x, y)
    out[:, 1:] = x[:, :1] * y[:, 1:] + y[:, :1] * x[:, 1:]
    return out


def jordan_divide(lam: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``u`` with ``lam o u = r`` per row (``lam`` in the interior of Q)."""
    lam0, lam1 = lam[:, 0], lam[:, 1:]
    r0, r1 = r[:, 0], r[:, 1:]
    u = np.empty_like(r)
    u[:, 0] = (lam0 * r0 - np.einsum("vi,vi->v", lam1, r1)) / cone_det(lam)
    u[:, 1:] = (r1 - lam1 * u[:, :1]) / lam0[:, None]
    return u


def step_to_boundary(x: np.ndarray, dx: np.ndarray) -> float:
    """Largest alpha in (0, 1] with ``x + alpha dx`` in Q for every row (``x`` interior).

    ``det(x + alpha dx) = a alpha^2 + 2 b alpha + c`` with ``c = det x > 0``; the path leaves Q
    at its smallest positive root (``x0 + alpha dx0`` cannot reach 0 before it). A path through
    the apex touches a double root that rounding may hide (a negative discriminant), so the
    step also stops where ``x0 + alpha dx0`` would reach 0.
    """
    if not len(x):
        return 1.0
    a = dx[:, 0] ** 2 - dx[:, 1] ** 2 - dx[:, 2] ** 2
    b = x[:, 0] * dx[:, 0] - x[:, 1] * dx[:, 1] - x[:, 2] * dx[:, 2]
    c = np.maximum(cone_det(x), 0.0)
    disc = b * b - a * c
    real = disc >= 0
    root = np.sqrt(np.where(real, disc, 0.0))
    # the two roots as q / a and c / q, without cancellation
    q = -(b + np.copysign(root, b))
    with np.errstate(divide="ignore", invalid="ignore"):
        first = np.where(a != 0, q / a, np.inf)
        second = np.where(q != 0, c / q, np.inf)
    first = np.where(real & (first > 0), first, np.inf)
    second = np.where(real & (second > 0), second, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        axis = np.where(dx[:, 0] < 0, -x[:, 0] / dx[:, 0], np.inf)
    return float(min(1.0, np.min(np.minimum(np.minimum(first, second), axis))))


def interior(x: np.ndarray, floor: float) -> np.ndarray:
    """``x`` with each row's first entry raised, where needed, to ``floor`` above the norm of
    the other two: a point strictly inside Q."""
    out = x.copy()
    out[:, 0] = np.maximum(out[:, 0], np.hypot(out[:, 1], out[:, 2]) + floor)
    return out
