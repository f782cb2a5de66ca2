"""The reduced interior point method's linear algebra, in the per-vertex layout.

Points, residuals and the per-vertex Hessian blocks of :mod:`~shapegen.statics.solvers.reduced`,
and :class:`KktSystem`: the problem's operators, the batched 3x3 inverses, the factored
block-level normal equations and the refined Newton solves.
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

from shapegen.statics.solvers.normal_equations import NormalEquations

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

    def moved(self, step: Point, alpha: float, alpha_dual: float | None = None) -> Point:
        """The point after a step (primal part x, s by ``alpha``; y, z by ``alpha_dual``)."""
        beta = alpha if alpha_dual is None else alpha_dual
        return Point(
            self.x_cut + alpha * step.x_cut,
            self.x_s + alpha * step.x_s,
            self.y + beta * step.y,
            self.slack_cut + alpha * step.slack_cut,
            self.slack_s + alpha * step.slack_s,
            self.dual_cut + beta * step.dual_cut,
            self.dual_s + beta * step.dual_s,
        )


@dataclass
class Residuals:
    dual_cut: np.ndarray
    dual_s: np.ndarray
    primal: np.ndarray
    ineq_cut: np.ndarray
    ineq_s: np.ndarray


@dataclass
class Hessian:
    inverse_cut: np.ndarray  # (m, 3, 3)
    diagonal_s: np.ndarray  # (m,)
    weight_cut: np.ndarray  # (m, k) Z / S
    weight_s: np.ndarray  # (m,)


class KktSystem:
    """The problem's operators in the per-vertex layout used by the iterations."""

    def __init__(self, problem, factorization: str = "auto"):
        m = problem.n_vertices
        self.m = m
        self.a = problem.equality
        self.at = self.a.T.tocsr()
        self.w = problem.load
        self.cone = problem.cone
        quadratic = problem.quadratic.reshape(4, m)
        linear = problem.linear.reshape(4, m)
        self.p_cut, self.p_s = quadratic[_CUT].T.copy(), quadratic[1]
        self.q_cut, self.q_s = linear[_CUT].T.copy(), linear[1]
        self.normal = NormalEquations(problem, factorization)
        self.factor_seconds = 0.0

    def split(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        groups = flat.reshape(4, self.m)
        return groups[_CUT].T, groups[1]

    def join(self, cut: np.ndarray, s: np.ndarray) -> np.ndarray:
        return np.concatenate([cut[:, 0], s, cut[:, 1], cut[:, 2]])

    def factor(self, weight_cut: np.ndarray, weight_s: np.ndarray) -> Hessian:
        """Per-vertex inverse Hessians and the factored normal equations."""
        cone = self.cone
        h = np.einsum("ki,vk,kj->vij", cone, weight_cut, cone)
        h[:, [0, 1, 2], [0, 1, 2]] += self.p_cut
        # symmetric diagonal equilibration before the batched inverse (unit diagonal); the tiny
        # shift keeps rank-deficient limits invertible and the refinement removes its effect
        d = 1.0 / np.sqrt(np.einsum("vii->vi", h))
        scale = d[:, :, None] * d[:, None, :]
        inverse = symmetric_inverse(h * scale + 1e-14 * np.eye(3)) * scale
        diagonal_s = self.p_s + weight_s
        local = inverse.copy()
        local[:, 0, 0] += 1.0 / diagonal_s  # the s column of A is minus the c column
        start = time.perf_counter()
        self.normal.assemble(local, 1e-13)
        self.factor_seconds += time.perf_counter() - start
        return Hessian(inverse, diagonal_s, weight_cut, weight_s)

    def newton(self, hessian: Hessian, rhs_cut, rhs_s, r_p, passes: int = 4):
        """Solve ``H dx + A^T dy = rhs``, ``A dx = -r_p`` with refinement on the exact system."""
        cone, a = self.cone, self.a
        e_cut, e_s, e_p = rhs_cut, rhs_s, -r_p
        dx_cut, dx_s, dy = np.zeros_like(rhs_cut), np.zeros_like(rhs_s), np.zeros(a.shape[0])
        scale = max(
            float(np.abs(rhs_cut).max()),
            float(np.abs(rhs_s).max()),
            float(np.abs(r_p).max()),
            1e-300,
        )
        aty_cut, aty_s = np.zeros_like(rhs_cut), np.zeros_like(rhs_s)  # A^T dy, accumulated
        for done in range(1, passes + 1):
            hx_cut = np.einsum("vij,vj->vi", hessian.inverse_cut, e_cut)
            hx_s = e_s / hessian.diagonal_s
            delta_y = self.normal.solve(a @ self.join(hx_cut, hx_s) - e_p)
            delta_cut, delta_s = self.split(self.at @ delta_y)
            dx_cut = dx_cut + hx_cut - np.einsum("vij,vj->vi", hessian.inverse_cut, delta_cut)
            dx_s = dx_s + hx_s - delta_s / hessian.diagonal_s
            dy = dy + delta_y
            if done == passes:
                break  # no refinement left: the residual would not be used
            aty_cut, aty_s = aty_cut + delta_cut, aty_s + delta_s
            h_dx_cut = self.p_cut * dx_cut + from_rows(
                to_rows(dx_cut, cone) * hessian.weight_cut, cone
            )
            e_cut = rhs_cut - h_dx_cut - aty_cut
            e_s = rhs_s - hessian.diagonal_s * dx_s - aty_s
            e_p = -r_p - a @ self.join(dx_cut, dx_s)
            error = max(
                float(np.abs(e_cut).max()), float(np.abs(e_s).max()), float(np.abs(e_p).max())
            )
            if error <= 1e-12 * scale:
                break
        return dx_cut, dx_s, dy

    def residuals(self, point: Point) -> Residuals:
        aty_cut, aty_s = self.split(self.at @ point.y)
        cone = self.cone
        return Residuals(
            dual_cut=self.p_cut * point.x_cut
            + self.q_cut
            + aty_cut
            + from_rows(point.dual_cut, cone),
            dual_s=self.p_s * point.x_s + self.q_s + aty_s - point.dual_s,
            primal=self.a @ self.join(point.x_cut, point.x_s) + self.w,
            ineq_cut=to_rows(point.x_cut, cone) + point.slack_cut,
            ineq_s=-point.x_s + point.slack_s,
        )

    def direction(
        self, point: Point, hessian: Hessian, res: Residuals, rc_cut, rc_s, passes: int = 4
    ):
        """Newton direction for complementarity residuals ``rc = S Z - target`` (``passes``:
        the most solves spent refining it)."""
        cone = self.cone
        v_cut = (-rc_cut + point.dual_cut * res.ineq_cut) / point.slack_cut
        v_s = (-rc_s + point.dual_s * res.ineq_s) / point.slack_s
        rhs_cut = -res.dual_cut - from_rows(v_cut, cone)
        rhs_s = -res.dual_s + v_s
        dx_cut, dx_s, dy = self.newton(hessian, rhs_cut, rhs_s, res.primal, passes)
        ds_cut = -res.ineq_cut - to_rows(dx_cut, cone)
        ds_s = -res.ineq_s + dx_s
        dz_cut = (-rc_cut - point.dual_cut * ds_cut) / point.slack_cut
        dz_s = (-rc_s - point.dual_s * ds_s) / point.slack_s
        return Point(dx_cut, dx_s, dy, ds_cut, ds_s, dz_cut, dz_s)


def max_steps(point: Point, step: Point) -> tuple[float, float]:
    """Largest primal (slack) and dual steps that keep slacks and duals non-negative."""
    primal = min(
        step_to_boundary(point.slack_cut.ravel(), step.slack_cut.ravel()),
        step_to_boundary(point.slack_s, step.slack_s),
    )
    dual = min(
        step_to_boundary(point.dual_cut.ravel(), step.dual_cut.ravel()),
        step_to_boundary(point.dual_s, step.dual_s),
    )
    return primal, dual


def complementarity(point: Point) -> float:
    return float(
        np.einsum("vk,vk->", point.slack_cut, point.dual_cut)
        + np.einsum("v,v->", point.slack_s, point.dual_s)
    )
