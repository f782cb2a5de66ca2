"""A structure-exploiting primal-dual interior point method (Mehrotra predictor-corrector).

The problem (see :mod:`shapegen.statics.assembly`) is

    minimise  x P x / 2 + q x   s.t.  A x + w = 0,  G x <= 0

with diagonal ``P`` and inequalities that act on one vertex at a time. The Hessian of the
Lagrangian plus the barrier, ``H = P + G^T (Z / S) G``, is therefore block-diagonal: a 3x3 block
for ``(c, u, t)`` and a scalar for ``s`` per vertex, inverted in batch with numpy. Eliminating
``dx`` leaves the block-level normal equations ``A H^-1 A^T dy = r`` with six rows per free block
(:mod:`~shapegen.statics.solvers.normal_equations`). Each Newton solve is refined against the
exact operators, because near the solution the barrier weights spread over twenty orders of
magnitude and the assembled ``M`` alone loses digits.

The exact friction cone (``pyramid="cone"``) adds one second-order cone ``(mu c, u, t)`` in Q per
vertex, linearised in the Nesterov-Todd scaling (:mod:`~shapegen.statics.solvers.second_order`):
its 3x3 block joins the vertex's block of ``H``, so the same normal equations, with the same
pattern, are factored; Mehrotra's corrector takes the Jordan product of the affine step's
scaled parts, as the linear rows take the product of theirs.
"""

from __future__ import annotations

__all__ = ["ReducedBackend"]

import dataclasses
import time
from typing import TYPE_CHECKING

import numpy as np

from shapegen.limits import check_clock
from shapegen.statics.solvers import second_order as _soc
from shapegen.statics.solvers.base import Backend, Solution, SolveStatus, trivial_solution

# The KKT system and its factorisations (scipy.sparse.linalg, CHOLMOD) are imported when a
# solve starts: the class, and what it declares it takes, loads without them.
if TYPE_CHECKING:
    from shapegen.statics.solvers.reduced_kkt import KktSystem as _Kkt
    from shapegen.statics.solvers.reduced_kkt import Point as _Point

# Stopping rules, as multiples of ``tolerance`` (dimensionless). The primal residual stays tight
# because the certificate reads the forces themselves; the gap (1e-9 at the default tolerance)
# bounds the phase-one tensions 100 times below the certificate's 1e-7 and resolves y far below
# the screening threshold; the dual residual, relative to the size of the gradient terms, has a
# noise floor near 1e-8 (refined solves with barrier weights spanning twenty orders of magnitude).
_DUAL_FLOOR = 1e5  # an optimal point's dual residual, in tolerances of the dual scale
_GAP_TOLERANCES = 100  # an optimal point's complementarity gap, in tolerances
_GAP_REL = 1e-8  # ... plus this share of the objective
_FAIR = 1e3  # a point kept as the inaccurate answer: primal and gap within this many tolerances
_FAIR_DUAL = 1e7  # ... and its dual residual within this many tolerances of the dual scale
_FAIR_GAP_REL = 1e-6  # ... and its gap within this share of the objective
_STALLED_GAP = 1e-3  # a gap this many tolerances small: nothing left for the arithmetic to gain
_SCREEN_PRIMAL_REL = 1e-4  # screening needs the equations to hold to this share of the load
_MIN_STEP = 1e-10  # a shorter step than this (a fraction of the Newton step) is a breakdown
_STEP_BACK = 0.99  # each step stops this share of the way to the boundary of the cone
# Separate primal and dual step lengths only when the Hessian is below this (the phase-one
# problem's regularisation; the QP's tension weights are of order one).
_NEGLIGIBLE_HESSIAN = 1e-6
_WARM_SLACK_FLOOR = 1e-2  # a warm start's slacks are at least this share of the load scale
_FARKAS_SIZE = 1e6  # the duals' size from which an infeasibility certificate is looked for
_FARKAS_REL = 1e-7  # its stationarity and its strict separation, relative to that size
_SCALE_FLOOR = 1e-12  # the load scale of a start that carries no load
_TOLERANCE = 1e-11  # the default tolerance the stopping rules are multiples of
_ACCEPT_BELOW = 1e-6  # the default objective below which an accepted point ends the solve
# the friction cone with mu = 0 as linear rows on (c, u, t): u = t = 0 and c >= 0 (the rows of
# assembly.friction_cone("4", 0.0))
_CLOSED_CONE = np.array(
    [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]]
)


class ReducedBackend(Backend):
    """Mehrotra predictor-corrector on the block-level normal equations.

    Parameters
    ----------
    tolerance
        Stopping tolerance on the scaled residuals (forces / W, torques / (W L)) and on the
        total complementarity gap, dimensionless.
    max_iter
        Iteration limit.
    verbose
        Print one line per iteration.
    stop_above
        Stop early (status ``optimal_inaccurate``, ``info["early_stop"]``) once the optimal value
        is certainly above this scaled value: the phase-one problem only has to tell zero from
        clearly positive.
    factorization
        How the normal equations are factored: ``"auto"`` (PARDISO when Intel MKL is installed,
        the optional ``shapegen[pardiso]``; else CHOLMOD through cvxopt when it imports; else
        SuperLU), ``"cholmod"``, ``"pardiso"`` or ``"superlu"``. A name that is unknown or
        whose library is not installed raises :class:`~shapegen.errors.OptionError` here, in
        one line.
    accept
        A test of the primal solution ``x`` (e.g. the feasibility certificate) that, once it
        holds, ends the solve: the question the caller asks is answered (``info["accepted"]``).
        It is tried once the objective is small (``accept_below``) and the equations hold.
    accept_below
        The objective below which ``accept`` is tried.
    warm_start
        (attribute) Forces ``x`` of a problem with the same constraints, e.g. phase one's, to
        start from (see :meth:`_warm_point`); None starts cold.
    screen_above
        Stop early (``optimal_inaccurate``, ``info["screened"]``) once the objective minus the
        gap, an estimate of the dual bound, exceeds this value with the equations nearly
        satisfied. Not a proof: the caller must confirm "clearly positive" otherwise (the
        analysis does with the paper's QP, and repeats phase one in full when the QP's
        tension is small).
    """

    name = "reduced"
    second_order_cones = True
    honours = frozenset({"stop_above", "accept", "screen_above", "warm_start"})

    def __init__(
        self,
        tolerance: float = _TOLERANCE,
        max_iter: int = 80,
        verbose: bool = False,
        stop_above: float | None = None,
        factorization: str = "auto",
        accept=None,
        accept_below: float = _ACCEPT_BELOW,
        screen_above: float | None = None,
    ):
        self.tolerance = tolerance
        self.max_iter = max_iter
        self.verbose = verbose
        self.stop_above = stop_above
        from shapegen.statics.solvers.normal_equations import check_factorization

        check_factorization(factorization)
        self.factorization = factorization
        self.accept = accept
        self.accept_below = accept_below
        self.screen_above = screen_above
        self.warm_start = None

    def solve(self, problem) -> Solution:
        from shapegen.statics.solvers.reduced_kkt import KktSystem as _Kkt
        from shapegen.statics.solvers.reduced_kkt import complementarity as _complementarity
        from shapegen.statics.solvers.reduced_kkt import max_steps as _max_steps
        from shapegen.statics.solvers.reduced_kkt import objective_value as _objective

        start = time.perf_counter()
        trivial = trivial_solution(problem)
        if trivial is not None:
            return trivial
        if problem.second_order and problem.friction == 0:
            # without friction the cone closes to its axis (u = t = 0, no interior): every
            # pyramid with mu = 0 is that same set, as linear rows
            problem = dataclasses.replace(problem, pyramid="4", cone=_CLOSED_CONE)
        kkt = _Kkt(problem, self.factorization)
        point = self._initial_point(kkt)
        if self.warm_start is not None:
            point = self._warm_point(kkt, point, self.warm_start)
        cones = kkt.second_order
        # a second-order cone has degree 1, as one linear row
        n_ineq = point.slack_cut.size + point.slack_s.size + (kkt.m if cones else 0)
        tol = self.tolerance
        load_scale = 1.0 + float(np.abs(kkt.w).max())
        status, best, iterations, info_early = SolveStatus.MAX_ITERATIONS, None, 0, False
        accepted, screened = False, False
        # separate primal and dual step lengths (the usual choice for linear programs) are only
        # consistent when the Hessian is negligible: the phase-one problem
        separate_steps = bool(problem.quadratic.max() <= _NEGLIGIBLE_HESSIAN)
        for iterations in range(1, self.max_iter + 1):
            check_clock()  # one iteration is a factorisation: judging's clock between them
            res = kkt.residuals(point)
            gap = _complementarity(point)
            x = kkt.join(point.x_cut, point.x_s)
            objective = _objective(problem, x)
            primal = max(
                float(np.abs(res.primal).max()),
                float(np.abs(res.ineq_cut).max(initial=0.0)),
                float(np.abs(res.ineq_s).max()),
                float(np.abs(res.ineq_q).max()) if cones else 0.0,
            )
            dual = max(float(np.abs(res.dual_cut).max()), float(np.abs(res.dual_s).max()))
            if self.verbose:
                print(
                    f"{iterations:3d} primal {primal:.2e} dual {dual:.2e} gap {gap:.2e} "
                    f"objective {objective:.6e}"
                )
            # Stopping: see the constants at the top of the module.
            dual_scale = 1.0 + float(np.abs(kkt.q_s).max()) + float(np.abs(point.dual_s).max())
            if (
                primal <= tol * load_scale
                and dual <= _DUAL_FLOOR * tol * dual_scale
                and gap <= _GAP_TOLERANCES * tol + _GAP_REL * objective
            ):
                status = SolveStatus.OPTIMAL
                break
            acceptable = (
                primal <= _FAIR * tol
                and dual <= _FAIR_DUAL * tol * dual_scale
                and gap <= _FAIR * tol + _FAIR_GAP_REL * objective
            )
            if acceptable:
                best = point
            if gap <= _STALLED_GAP * tol and iterations > 1:
                break  # converged as far as the arithmetic allows: nothing left to gain
            if (
                self.accept is not None
                and objective <= self.accept_below
                and primal <= _FAIR * tol
                and self.accept(kkt.join(point.x_cut, point.x_s))
            ):
                status, accepted = SolveStatus.OPTIMAL, True
                break
            if (
                self.screen_above is not None
                and primal <= _SCREEN_PRIMAL_REL * load_scale
                and objective - gap > self.screen_above
            ):
                # the optimum is most likely far above the threshold (objective - gap estimates
                # the dual bound); the caller confirms it with the QP (see ``screen_above``)
                best, info_early, screened = point, True, True
                break
            if (
                self.stop_above is not None
                and primal <= _FAIR * tol
                and dual <= _DUAL_FLOOR * tol * dual_scale
                and objective - 2 * gap > self.stop_above
            ):
                # the optimum is certainly above the threshold: the caller only needed to know
                best, info_early = point, True
                break
            if self._farkas(kkt, point):
                status = SolveStatus.INFEASIBLE
                break
            try:
                # a cone's point on its boundary (det 0) is a breakdown, not a warning
                with np.errstate(divide="raise", invalid="raise"):
                    scaling = _soc.scaling(point.slack_q, point.dual_q) if cones else None
                hessian = kkt.factor(
                    point.dual_cut / point.slack_cut, point.dual_s / point.slack_s, scaling
                )
            except (np.linalg.LinAlgError, RuntimeError, ValueError, FloatingPointError):
                status = SolveStatus.NUMERICAL_ERROR
                break
            rc_q = _soc.jordan_product(scaling.lam, scaling.lam) if cones else None
            mu = gap / n_ineq
            # predictor (affine scaling), then corrector with Mehrotra's centring
            # the predictor only sets the centring and the second-order term: one solve, no
            # refinement (the corrector is refined)
            affine = kkt.direction(
                point,
                hessian,
                res,
                point.slack_cut * point.dual_cut,
                point.slack_s * point.dual_s,
                rc_q,
                passes=1,
            )
            alpha, alpha_dual = _max_steps(point, affine)
            if not separate_steps:
                alpha = alpha_dual = min(alpha, alpha_dual)
            mu_affine = _complementarity(point.moved(affine, alpha, alpha_dual)) / n_ineq
            sigma = min(1.0, (mu_affine / mu) ** 3) if mu > 0 else 0.0
            rc_cut = point.slack_cut * point.dual_cut + affine.slack_cut * affine.dual_cut
            rc_s = point.slack_s * point.dual_s + affine.slack_s * affine.dual_s
            if cones:
                rc_q = rc_q + _soc.jordan_product(
                    scaling.apply(-1, affine.slack_q), scaling.apply(1, affine.dual_q)
                )
                rc_q[:, 0] -= sigma * mu
            step = kkt.direction(point, hessian, res, rc_cut - sigma * mu, rc_s - sigma * mu, rc_q)
            alpha, alpha_dual = (min(1.0, _STEP_BACK * a) for a in _max_steps(point, step))
            if not separate_steps:
                alpha = alpha_dual = min(alpha, alpha_dual)
            if not np.isfinite(alpha + alpha_dual) or min(alpha, alpha_dual) < _MIN_STEP:
                status = SolveStatus.NUMERICAL_ERROR
                break
            point = point.moved(step, alpha, alpha_dual)
            if not (np.all(np.isfinite(point.x_cut)) and np.all(np.isfinite(point.y))):
                status = SolveStatus.NUMERICAL_ERROR
                break

        kkt.normal.release()
        info = {
            "factor_seconds": kkt.factor_seconds,
            "early_stop": info_early,
            "accepted": accepted,
            "screened": screened,
            "factorization": kkt.normal.method,
            "factorization_fallbacks": kkt.normal.fallbacks,
            "factorizations": kkt.normal.factorizations,
            "factor_cpu": kkt.normal.factor_cpu,
            "normal_assembly_cpu": kkt.normal.assembly_cpu,
        }
        seconds = time.perf_counter() - start
        if status is not SolveStatus.OPTIMAL:
            if status is SolveStatus.INFEASIBLE or best is None:
                return Solution(status, None, None, float("nan"), iterations, seconds, info)
            point, status = best, SolveStatus.OPTIMAL_INACCURATE
        x = kkt.join(point.x_cut, point.x_s)
        value = _objective(problem, x)
        return Solution(status, x, point.y.copy(), value, iterations, seconds, info)

    @staticmethod
    def _initial_point(kkt: _Kkt) -> _Point:
        """The plain start ``x = 0``, ``y = 0`` with slacks at the load scale and duals at the
        cost scale (the linear tension cost, or the load scale for the squared one).

        Measured against Mehrotra's least-squares start and CVXOPT's unit-weight Newton start,
        this took fewest iterations on walls (11 against 11-14 at 1 000 blocks, 12 against
        18-20 at 10 000): those starts put the forces far from the compressive region and the
        first iterations only took short steps.
        """
        from shapegen.statics.solvers.reduced_kkt import Point as _Point

        m, k = kkt.m, len(kkt.cone)
        primal = max(float(np.abs(kkt.w).max()), _SCALE_FLOOR)
        dual = max(float(np.abs(kkt.q_s).max()), primal)
        axis = np.zeros((m, 3))
        axis[:, 0] = 1.0  # the cone's identity e: its centre ray
        return _Point(
            np.zeros((m, 3)),
            np.zeros(m),
            np.zeros(kkt.a.shape[0]),
            np.full((m, k), primal),
            np.full(m, primal),
            np.full((m, k), dual),
            np.full(m, dual),
            primal * axis if kkt.second_order else None,
            dual * axis if kkt.second_order else None,
        )

    @staticmethod
    def _warm_point(kkt: _Kkt, cold: _Point, x: np.ndarray) -> _Point:
        """Start from the forces ``x`` (same constraints, another objective): the slacks are
        what ``x`` leaves, floored at 1% of the load scale so that no product starts at zero;
        multipliers and inequality duals start cold.

        Measured on the sliding running-bond walls, starting the QP from phase one's (possibly
        screened) forces saves a fifth to a third of its iterations (1 004 blocks: 17 -> 14):
        the cold start spends its first iterations finding forces that balance the load.
        """
        from shapegen.statics.solvers.reduced_kkt import Point as _Point
        from shapegen.statics.solvers.reduced_kkt import to_rows as _to_rows

        x_cut, x_s = kkt.split(np.asarray(x, dtype=float))
        floor = _WARM_SLACK_FLOOR * float(cold.slack_s[0])
        return _Point(
            x_cut.copy(),
            x_s.copy(),
            cold.y,
            np.maximum(-_to_rows(x_cut, kkt.cone), floor),
            np.maximum(x_s, floor),
            cold.dual_cut,
            cold.dual_s,
            _soc.interior(kkt.cone_diagonal * x_cut, floor) if kkt.second_order else None,
            cold.dual_q,
        )

    @staticmethod
    def _farkas(kkt: _Kkt, point: _Point) -> bool:
        """A certificate that ``A x + w = 0, G x <= 0`` has no solution: ``y`` and ``z >= 0``
        with ``A^T y + G^T z = 0`` and ``w . y > 0`` (then ``y . (A x + w) > 0`` for every
        admissible ``x``). Interior point duals grow along such a ray when the primal is
        infeasible; the test runs once they are large."""
        from shapegen.statics.solvers.reduced_kkt import from_rows as _from_rows

        size = max(
            float(np.abs(point.y).max()),
            float(point.dual_cut.max(initial=0.0)),
            float(point.dual_s.max()),
        )
        if kkt.second_order:
            size = max(size, float(point.dual_q[:, 0].max()))
        if size < _FARKAS_SIZE:
            return False
        aty_cut, aty_s = kkt.split(kkt.at @ point.y)
        if kkt.second_order:  # G_q^T z_q
            aty_cut = aty_cut - kkt.cone_diagonal * point.dual_q
        stationarity = max(
            float(np.abs(aty_cut + _from_rows(point.dual_cut, kkt.cone)).max()),
            float(np.abs(aty_s - point.dual_s).max()),
        )
        return stationarity <= _FARKAS_REL * size and float(
            np.einsum("i,i->", kkt.w, point.y)
        ) > _FARKAS_REL * size * float(np.abs(kkt.w).max())
