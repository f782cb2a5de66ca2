"""Clarabel called directly on the scipy.sparse matrices of the assembled problem."""

from __future__ import annotations

__all__ = ["ClarabelBackend"]

import time

import numpy as np

from shapegen.limits import clock_ran_out
from shapegen.statics.solvers.base import (
    Backend,
    Solution,
    SolveStatus,
    limit_time,
    trivial_solution,
)

# Solver settings: clarabel's gap and feasibility tolerances, and its KKT ratio.
TOLERANCE = 1e-10
KKT_RATIO = 1e-8

_STATUS = {
    "Solved": SolveStatus.OPTIMAL,
    "AlmostSolved": SolveStatus.OPTIMAL_INACCURATE,
    "PrimalInfeasible": SolveStatus.INFEASIBLE,
    "AlmostPrimalInfeasible": SolveStatus.INFEASIBLE,
    # the objective is bounded below by 0, so dual infeasibility means numerical trouble
    "DualInfeasible": SolveStatus.NUMERICAL_ERROR,
    "AlmostDualInfeasible": SolveStatus.NUMERICAL_ERROR,
    "MaxIterations": SolveStatus.MAX_ITERATIONS,
    "MaxTime": SolveStatus.MAX_ITERATIONS,
    "NumericalError": SolveStatus.NUMERICAL_ERROR,
    "InsufficientProgress": SolveStatus.OPTIMAL_INACCURATE,
}


class ClarabelBackend(Backend):
    """Interior point solver Clarabel on ``min x P x / 2 + q x`` s.t. ``A x = -w``, ``G x <= 0``.

    Equalities go into a ``ZeroConeT``, inequalities into a ``NonnegativeConeT`` (Clarabel's
    form is ``A x + s = b``, ``s`` in the cone). With the exact friction cone, each vertex adds a
    ``SecondOrderConeT(3)`` on ``(mu c, u, t)``.
    """

    name = "clarabel"
    library = "clarabel"
    second_order_cones = True

    def __init__(self, tolerance: float = TOLERANCE, max_iter: int = 200):
        self.tolerance = tolerance
        self.max_iter = max_iter

    def solve(self, problem) -> Solution:
        import clarabel
        import scipy.sparse as sp  # with the solve: checking options loads no solver

        trivial = trivial_solution(problem)
        if trivial is not None:
            return trivial
        start = time.perf_counter()
        p = problem.equality.shape[0]
        blocks = [problem.equality, problem.inequality_matrix()]
        cones = [clarabel.ZeroConeT(p), clarabel.NonnegativeConeT(blocks[1].shape[0])]
        if problem.second_order:
            blocks.append(problem.second_order_matrix())
            cones += [clarabel.SecondOrderConeT(3)] * problem.n_vertices
        constraints = sp.vstack(blocks, format="csc")
        rhs = np.concatenate([-problem.load, np.zeros(constraints.shape[0] - p)])
        objective = sp.diags(problem.quadratic, format="csc")
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.max_iter = self.max_iter
        settings.tol_gap_abs = self.tolerance
        settings.tol_gap_rel = self.tolerance
        settings.tol_feas = self.tolerance
        settings.tol_ktratio = KKT_RATIO
        limit_time(settings)
        solver = clarabel.DefaultSolver(
            objective, problem.linear, constraints, rhs, cones, settings
        )
        result = solver.solve()
        native = str(result.status).split(".")[-1]
        if native == "MaxTime":
            clock_ran_out()
        status = _STATUS.get(native, SolveStatus.NUMERICAL_ERROR)
        seconds = time.perf_counter() - start
        if not status.solved:
            return Solution(
                status,
                None,
                None,
                float("nan"),
                result.iterations,
                seconds,
                {"native_status": native},
            )
        x = np.asarray(result.x)
        # Clarabel's Lagrangian is f + z . (A x - b) with z = [y_eq, z_ineq]; A x - b = A x + w
        multipliers = np.asarray(result.z)[:p].copy()
        value = float(0.5 * problem.quadratic @ x**2 + problem.linear @ x)
        return Solution(
            status, x, multipliers, value, result.iterations, seconds, {"native_status": native}
        )
