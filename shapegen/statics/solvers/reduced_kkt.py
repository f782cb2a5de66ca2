"""The reduced interior point method's linear algebra, in the per-vertex layout.

Points, residuals and the per-vertex Hessian blocks of :mod:`~shapegen.statics.solvers.reduced`,
and :class:`KktSystem`: the problem's operators, the batched 3x3 inverses, the factored
block-level normal equations and the refined Newton solves.

With the exact friction cone each vertex also has a second-order cone ``G_q x_v + s_q = 0``,
``s_q`` in Q, with ``G_q = -diag(mu, 1, 1)`` on ``(c, u, t)``; its Nesterov-Todd block
``G_q^T W^-2 G_q`` (:mod:`~shapegen.statics.solvers.second_order`) adds to the vertex's 3x3
Hessian block, so the elimination and the normal equations are those of the pyramids.
"""

from __future__ import annotations

__all__ = [
    "Point",
    "Residuals",
    "Hessian",
    "KktSystem",
    "to_rows",
    "from_rows",
    "objective_value",
    "symmetric_inverse",
    "max_steps",
    "complementarity",
]

import time
from dataclasses import dataclass

import numpy as np

from shapegen.statics.solvers import second_order as soc
from shapegen.statics.solvers.normal_equations import NormalEquations
from shapegen.tolerances import DIVISION_FLOOR

# Solver settings. The shift added to each equilibrated 3x3 block before its inverse (rank-
# deficient limits stay invertible; the refinement removes it), the one added to the normal
# equations' diagonal relative to its mean, and the residual, relative to the right-hand side,
# at which iterative refinement stops.
_EQUILIBRATION_SHIFT = 1e-14
_NORMAL_SHIFT = 1e-13
_REFINED = 1e-12

_CUT = [0, 2, 3]  # positions of c, u, t among the variable groups x = [c, s, u, t]


# The per-vertex products with the small cone matrix use einsum, not "@": "(m, 3) @ (3, k)" goes to
# a BLAS gemm whose threads cost more than the work (15 ms per call on a busy machine for 40 000
# vertices, against well under 1 ms).
def to_rows(x_cut: np.ndarray, cone: np.ndarray) -> np.ndarray:
    """``G_v x_v`` per vertex: ``(m, 3) -> (m, k)``."""
    return np.einsum("vi,ki->vk", x_cut, cone)


def from_rows(values: np.ndarray, cone: np.ndarray) -> np.ndarray:
    """``G_v^T z_v`` per vertex: ``(m, k) -> (m, 3)``."""
    return np.einsum("vk,ki->vi", values, cone)


# Dot products of long vectors are written with einsum on purpose: "a @ b" on 1-D arrays calls
# BLAS ddot, which OpenBLAS threads; on a busy machine each call stalled for ~10 ms.
def objective_value(problem, x: np.ndarray) -> float:
    return float(
        0.5 * np.einsum("i,i,i->", problem.quadratic, x, x) + np.einsum("i,i->", problem.linear, x)
    )


def symmetric_inverse(h: np.ndarray) -> np.ndarray:
    """Inverses of symmetric ``(m, 3, 3)`` matrices by their cofactors (equilibrated by the
    caller): a fifth of the time of LAPACK's batched ``inv`` on 10 000 vertices and more."""
    a00, a01, a02 = h[:, 0, 0], h[:, 0, 1], h[:, 0, 2]
    a11, a12, a22 = h[:, 1, 1], h[:, 1, 2], h[:, 2, 2]
    out = np.empty_like(h)
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    inverse_det = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    out[:, 0, 0] = c00 * inverse_det
    out[:, 0, 1] = out[:, 1, 0] = c01 * inverse_det
    out[:, 0, 2] = out[:, 2, 0] = c02 * inverse_det
    out[:, 1, 1] = (a00 * a22 - a02 * a02) * inverse_det
    out[:, 1, 2] = out[:, 2, 1] = (a01 * a02 - a00 * a12) * inverse_det
    out[:, 2, 2] = (a00 * a11 - a01 * a01) * inverse_det
    return out


def _symmetric_times(matrix: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``matrix[v] @ x[v]`` for symmetric ``(m, 3, 3)`` matrices, written out (a batched
    ``einsum`` of 3x3 blocks costs more than its nine products)."""
    out = np.empty_like(x)
    for i in range(3):
        out[:, i] = (
            matrix[:, i, 0] * x[:, 0] + matrix[:, i, 1] * x[:, 1] + matrix[:, i, 2] * x[:, 2]
        )
    return out


def _from_basis_matrix(middle: np.ndarray, n: np.ndarray) -> np.ndarray:
    """``V M V^T`` per vertex for the cone's eigenvectors ``V`` (columns ``(1, n) / sqrt 2``,
    ``(1, -n) / sqrt 2``, ``(0, p)`` with ``p`` = ``n`` turned by 90 degrees) and symmetric
    ``M``, written out from those columns."""
    maa, mbb, mcc = middle[:, 0, 0], middle[:, 1, 1], middle[:, 2, 2]
    mab, mac, mbc = middle[:, 0, 1], middle[:, 0, 2], middle[:, 1, 2]
    p = np.stack([-n[:, 1], n[:, 0]], axis=1)
    out = np.empty_like(middle)
    out[:, 0, 0] = 0.5 * (maa + mbb) + mab
    top = 0.5 * (maa - mbb)[:, None] * n + np.sqrt(0.5) * (mac + mbc)[:, None] * p
    out[:, 0, 1:] = out[:, 1:, 0] = top
    radial = 0.5 * (maa + mbb) - mab
    mixed = np.sqrt(0.5) * (mac - mbc)
    for i in (0, 1):
        for j in (0, 1):
            out[:, 1 + i, 1 + j] = (
                radial * n[:, i] * n[:, j]
                + mixed * (n[:, i] * p[:, j] + p[:, i] * n[:, j])
                + mcc * p[:, i] * p[:, j]
            )
    return out


def step_to_boundary(value: np.ndarray, step: np.ndarray) -> float:
    """Largest alpha in (0, 1] with ``value + alpha step >= 0`` (``value > 0``)."""
    negative = step < 0
    if not np.any(negative):
        return 1.0
    return float(min(1.0, np.min(-value[negative] / step[negative])))


@dataclass
class Point:
    """Primal ``(c, u, t)`` and ``s``, equality multipliers, slacks and inequality duals."""

    x_cut: np.ndarray  # (m, 3)
    x_s: np.ndarray  # (m,)
    y: np.ndarray  # (6 nf,)
    slack_cut: np.ndarray  # (m, k)
    slack_s: np.ndarray  # (m,)
    dual_cut: np.ndarray  # (m, k)
    dual_s: np.ndarray  # (m,)
    slack_q: np.ndarray | None = None  # (m, 3) the friction cone's slack (mu c, u, t), in Q
    dual_q: np.ndarray | None = None  # (m, 3) its dual, in Q

    def moved(self, step: Point, alpha: float, alpha_dual: float | None = None) -> Point:
        """The point after a step (primal part x, s by ``alpha``; y, z by ``alpha_dual``)."""
        beta = alpha if alpha_dual is None else alpha_dual
        cones = self.slack_q is not None
        return Point(
            self.x_cut + alpha * step.x_cut,
            self.x_s + alpha * step.x_s,
            self.y + beta * step.y,
            self.slack_cut + alpha * step.slack_cut,
            self.slack_s + alpha * step.slack_s,
            self.dual_cut + beta * step.dual_cut,
            self.dual_s + beta * step.dual_s,
            self.slack_q + alpha * step.slack_q if cones else None,
            self.dual_q + beta * step.dual_q if cones else None,
        )


@dataclass
class Residuals:
    dual_cut: np.ndarray
    dual_s: np.ndarray
    primal: np.ndarray
    ineq_cut: np.ndarray
    ineq_s: np.ndarray
    ineq_q: np.ndarray | None = None  # (m, 3) G_q x + s_q


@dataclass
class Hessian:
    inverse_cut: np.ndarray  # (m, 3, 3)
    diagonal_s: np.ndarray  # (m,)
    weight_cut: np.ndarray  # (m, k) Z / S
    weight_s: np.ndarray  # (m,)
    scaling: soc.Scaling | None = None  # the friction cones' Nesterov-Todd scaling
    middle: np.ndarray | None = None  # (m, 3, 3) N^-1 of :meth:`KktSystem._cone_inverse`


class KktSystem:
    """The problem's operators in the per-vertex layout used by the iterations."""

    def __init__(self, problem, factorization: str = "auto"):
        m = problem.n_vertices
        self.m = m
        self.a = problem.equality
        # A^T, kept with the problem: phase one, the QP and the least-norm forces share it
        self.at = problem.cache.get("equality_transposed")
        if self.at is None:
            self.at = problem.cache["equality_transposed"] = self.a.T.tocsr()
        self.w = problem.load
        self.second_order = bool(problem.second_order)
        # with the exact cone (and mu > 0) c >= 0 follows from ||(u, t)|| <= mu c: no linear row
        self.cone = problem.cone[:0] if self.second_order else problem.cone
        quadratic = problem.quadratic.reshape(4, m)
        linear = problem.linear.reshape(4, m)
        self.p_cut, self.p_s = quadratic[_CUT].T.copy(), quadratic[1]
        self.q_cut, self.q_s = linear[_CUT].T.copy(), linear[1]
        self.normal = NormalEquations(problem, factorization)
        self.factor_seconds = 0.0
        # G_q = -diag(mu, 1, 1): the cone's slack is (mu c, u, t)
        self.cone_diagonal = np.array([problem.friction, 1.0, 1.0])

    def split(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        groups = flat.reshape(4, self.m)
        return groups[_CUT].T, groups[1]

    def join(self, cut: np.ndarray, s: np.ndarray) -> np.ndarray:
        return np.concatenate([cut[:, 0], s, cut[:, 1], cut[:, 2]])

    def factor(
        self, weight_cut: np.ndarray, weight_s: np.ndarray, scaling: soc.Scaling | None = None
    ) -> Hessian:
        """Per-vertex inverse Hessians and the factored normal equations (``scaling``: the
        friction cones' Nesterov-Todd scaling, with the exact cone)."""
        cone = self.cone
        h = np.einsum("ki,vk,kj->vij", cone, weight_cut, cone)
        h[:, [0, 1, 2], [0, 1, 2]] += self.p_cut
        middle = None
        if scaling is not None:
            inverse, middle = self._cone_inverse(np.einsum("vii->vi", h), scaling)
        else:
            # symmetric diagonal equilibration before the batched inverse (unit diagonal); the
            # tiny shift keeps rank-deficient limits invertible and the refinement removes it
            d = 1.0 / np.sqrt(np.einsum("vii->vi", h))
            scale = d[:, :, None] * d[:, None, :]
            inverse = symmetric_inverse(h * scale + _EQUILIBRATION_SHIFT * np.eye(3)) * scale
        diagonal_s = self.p_s + weight_s
        local = inverse.copy()
        local[:, 0, 0] += 1.0 / diagonal_s  # the s column of A is minus the c column
        start = time.perf_counter()
        self.normal.assemble(local, _NORMAL_SHIFT)
        self.factor_seconds += time.perf_counter() - start
        return Hessian(inverse, diagonal_s, weight_cut, weight_s, scaling, middle)

    def _cone_inverse(
        self, diagonal: np.ndarray, scaling: soc.Scaling
    ) -> tuple[np.ndarray, np.ndarray]:
        """``H^-1 = (B + D W^-2 D)^-1`` per vertex for the diagonal ``B`` (``diagonal``
        ``(m, 3)``, the objective's) and ``D = diag(mu, 1, 1)``: with ``W^-2 = V L V^T`` in its
        eigenvectors, ``H^-1 = D^-1 V N^-1 V^T D^-1`` with ``N = L + V^T (B / D^2) V``.

        Near the optimum ``L`` spans twenty orders of magnitude: ``N`` is nearly diagonal in
        that basis and its equilibrated inverse keeps every direction's digits, where inverting
        the assembled ``B + D W^-2 D`` would lose the large eigenvalues of the inverse (the
        directions the cone leaves free) to cancellation. Returns the assembled ``H^-1`` (for
        the normal equations) and ``N^-1`` (for the products, :meth:`_times_inverse`).
        """
        d = self.cone_diagonal
        c = diagonal / (d * d)  # B / D^2, diagonal
        n = scaling.direction
        # V^T diag(c) V written out for V's columns (1, n)/sqrt 2, (1, -n)/sqrt 2, (0, n_perp)
        along = c[:, 1] * n[:, 0] ** 2 + c[:, 2] * n[:, 1] ** 2
        across = c[:, 1] * n[:, 1] ** 2 + c[:, 2] * n[:, 0] ** 2
        mixed = np.sqrt(0.5) * n[:, 0] * n[:, 1] * (c[:, 2] - c[:, 1])
        middle = np.empty((len(c), 3, 3))
        middle[:, 0, 0] = middle[:, 1, 1] = 0.5 * (c[:, 0] + along)
        middle[:, 0, 1] = middle[:, 1, 0] = 0.5 * (c[:, 0] - along)
        middle[:, 0, 2] = middle[:, 2, 0] = mixed
        middle[:, 1, 2] = middle[:, 2, 1] = -mixed
        middle[:, 2, 2] = across
        middle[:, [0, 1, 2], [0, 1, 2]] += scaling.power_values(-2)
        e = 1.0 / np.sqrt(np.einsum("vii->vi", middle))
        scale = e[:, :, None] * e[:, None, :]
        middle = symmetric_inverse(middle * scale) * scale
        return _from_basis_matrix(middle, n) / np.outer(d, d), middle

    def _times_inverse(self, hessian: Hessian, e: np.ndarray) -> np.ndarray:
        """``H^-1 e`` per vertex (in the cone's eigenvectors with the exact cone)."""
        if hessian.middle is None:
            return np.einsum("vij,vj->vi", hessian.inverse_cut, e)
        d, scaling = self.cone_diagonal, hessian.scaling
        local = _symmetric_times(hessian.middle, scaling.to_basis(e / d))
        return scaling.from_basis(local) / d

    def _times_hessian(self, hessian: Hessian, dx: np.ndarray) -> np.ndarray:
        """``H dx`` per vertex: the objective, the linear rows' barrier and the cone's."""
        product = self.p_cut * dx + from_rows(
            to_rows(dx, self.cone) * hessian.weight_cut, self.cone
        )
        if hessian.scaling is not None:
            d = self.cone_diagonal
            product += d * hessian.scaling.apply(-2, d * dx)
        return product

    def newton(self, hessian: Hessian, rhs_cut, rhs_s, r_p, passes: int = 4):
        """Solve ``H dx + A^T dy = rhs``, ``A dx = -r_p`` with refinement on the exact system."""
        a = self.a
        e_cut, e_s, e_p = rhs_cut, rhs_s, -r_p
        dx_cut, dx_s, dy = np.zeros_like(rhs_cut), np.zeros_like(rhs_s), np.zeros(a.shape[0])
        scale = max(
            float(np.abs(rhs_cut).max()),
            float(np.abs(rhs_s).max()),
            float(np.abs(r_p).max()),
            DIVISION_FLOOR,
        )
        aty_cut, aty_s = np.zeros_like(rhs_cut), np.zeros_like(rhs_s)  # A^T dy, accumulated
        for done in range(1, passes + 1):
            hx_cut = self._times_inverse(hessian, e_cut)
            hx_s = e_s / hessian.diagonal_s
            delta_y = self.normal.solve(a @ self.join(hx_cut, hx_s) - e_p)
            delta_cut, delta_s = self.split(self.at @ delta_y)
            dx_cut = dx_cut + hx_cut - self._times_inverse(hessian, delta_cut)
            dx_s = dx_s + hx_s - delta_s / hessian.diagonal_s
            dy = dy + delta_y
            if done == passes:
                break  # no refinement left: the residual would not be used
            aty_cut, aty_s = aty_cut + delta_cut, aty_s + delta_s
            e_cut = rhs_cut - self._times_hessian(hessian, dx_cut) - aty_cut
            e_s = rhs_s - hessian.diagonal_s * dx_s - aty_s
            e_p = -r_p - a @ self.join(dx_cut, dx_s)
            error = max(
                float(np.abs(e_cut).max()), float(np.abs(e_s).max()), float(np.abs(e_p).max())
            )
            if error <= _REFINED * scale:
                break
        return dx_cut, dx_s, dy

    def residuals(self, point: Point) -> Residuals:
        aty_cut, aty_s = self.split(self.at @ point.y)
        cone = self.cone
        dual_cut = self.p_cut * point.x_cut + self.q_cut + aty_cut + from_rows(point.dual_cut, cone)
        ineq_q = None
        if self.second_order:
            dual_cut -= self.cone_diagonal * point.dual_q  # G_q^T z_q
            ineq_q = point.slack_q - self.cone_diagonal * point.x_cut
        return Residuals(
            dual_cut=dual_cut,
            dual_s=self.p_s * point.x_s + self.q_s + aty_s - point.dual_s,
            primal=self.a @ self.join(point.x_cut, point.x_s) + self.w,
            ineq_cut=to_rows(point.x_cut, cone) + point.slack_cut,
            ineq_s=-point.x_s + point.slack_s,
            ineq_q=ineq_q,
        )

    def direction(
        self,
        point: Point,
        hessian: Hessian,
        res: Residuals,
        rc_cut,
        rc_s,
        rc_q=None,
        passes: int = 4,
    ):
        """Newton direction for complementarity residuals ``rc = S Z - target`` (``passes``:
        the most solves spent refining it). For the friction cones ``rc_q`` is the scaled
        residual ``lambda o lambda - target``: the step solves
        ``lambda o (W^-1 ds_q + W dz_q) = -rc_q``."""
        cone = self.cone
        v_cut = (-rc_cut + point.dual_cut * res.ineq_cut) / point.slack_cut
        v_s = (-rc_s + point.dual_s * res.ineq_s) / point.slack_s
        rhs_cut = -res.dual_cut - from_rows(v_cut, cone)
        rhs_s = -res.dual_s + v_s
        scaling = hessian.scaling
        if scaling is not None:
            w_inverse_u = scaling.apply(-1, soc.jordan_divide(scaling.lam, rc_q))
            v_q = scaling.apply(-2, res.ineq_q) - w_inverse_u
            rhs_cut += self.cone_diagonal * v_q  # -G_q^T v_q
        dx_cut, dx_s, dy = self.newton(hessian, rhs_cut, rhs_s, res.primal, passes)
        ds_cut = -res.ineq_cut - to_rows(dx_cut, cone)
        ds_s = -res.ineq_s + dx_s
        dz_cut = (-rc_cut - point.dual_cut * ds_cut) / point.slack_cut
        dz_s = (-rc_s - point.dual_s * ds_s) / point.slack_s
        ds_q = dz_q = None
        if scaling is not None:
            ds_q = -res.ineq_q + self.cone_diagonal * dx_cut
            dz_q = -w_inverse_u - scaling.apply(-2, ds_q)
        return Point(dx_cut, dx_s, dy, ds_cut, ds_s, dz_cut, dz_s, ds_q, dz_q)


def max_steps(point: Point, step: Point) -> tuple[float, float]:
    """Largest primal (slack) and dual steps that keep slacks and duals non-negative (and the
    friction cones' slacks and duals in their cones)."""
    primal = min(
        step_to_boundary(point.slack_cut.ravel(), step.slack_cut.ravel()),
        step_to_boundary(point.slack_s, step.slack_s),
    )
    dual = min(
        step_to_boundary(point.dual_cut.ravel(), step.dual_cut.ravel()),
        step_to_boundary(point.dual_s, step.dual_s),
    )
    if point.slack_q is not None:
        primal = min(primal, soc.step_to_boundary(point.slack_q, step.slack_q))
        dual = min(dual, soc.step_to_boundary(point.dual_q, step.dual_q))
    return primal, dual


def complementarity(point: Point) -> float:
    gap = float(
        np.einsum("vk,vk->", point.slack_cut, point.dual_cut)
        + np.einsum("v,v->", point.slack_s, point.dual_s)
    )
    if point.slack_q is not None:
        gap += float(np.einsum("vi,vi->", point.slack_q, point.dual_q))
    return gap
