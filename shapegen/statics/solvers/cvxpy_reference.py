"""The reference formulation: the same problem written readably in cvxpy."""

from __future__ import annotations

__all__ = ["CvxpyBackend"]

import time

import numpy as np

from shapegen.limits import check_clock
from shapegen.statics.solvers.base import Backend, Solution, SolveStatus, trivial_solution

# Solver setting: the tolerance asked of cvxpy's back-end.
TOLERANCE = 1e-10

_STATUS = {
    "optimal": SolveStatus.OPTIMAL,
    "optimal_inaccurate": SolveStatus.OPTIMAL_INACCURATE,
    "infeasible": SolveStatus.INFEASIBLE,
    "infeasible_inaccurate": SolveStatus.INFEASIBLE,
    "unbounded": SolveStatus.NUMERICAL_ERROR,
    "unbounded_inaccurate": SolveStatus.NUMERICAL_ERROR,
    "user_limit": SolveStatus.MAX_ITERATIONS,
    "solver_error": SolveStatus.NUMERICAL_ERROR,
}


class CvxpyBackend(Backend):
    """``minimize sum(s^2)`` subject to equilibrium and the friction pyramid (or cone), in cvxpy.

    Slow to build (cvxpy canonicalises the expression tree) but easy to read and to vary; the
    tests check it against the other back-ends.
    """

    name = "cvxpy"
    library = "cvxpy"
    second_order_cones = True

    def __init__(self, solver: str | None = None, tolerance: float = TOLERANCE):
        self.solver = solver
        self.tolerance = tolerance

    def solve(self, problem) -> Solution:
        import cvxpy as cp

        trivial = trivial_solution(problem)
        if trivial is not None:
            return trivial
        check_clock()  # the reference's solve cannot look at the clock: it starts within it
        start = time.perf_counter()
        m = problem.n_vertices
        a = problem.equality
        a_normal, a_tangent1, a_tangent2 = a[:, :m], a[:, 2 * m : 3 * m], a[:, 3 * m :]
        compression = cp.Variable(m, nonneg=True)
        tension = cp.Variable(m, nonneg=True)
        friction1 = cp.Variable(m)
        friction2 = cp.Variable(m)
        equilibrium = (
            a_normal @ (compression - tension)
            + a_tangent1 @ friction1
            + a_tangent2 @ friction2
            + problem.load
            == 0
        )
        friction = friction_constraints(problem, compression, friction1, friction2)
        weight = problem.quadratic[m : 2 * m]
        regularization = problem.quadratic[0] / 2
        objective = (
            cp.sum(cp.multiply(weight / 2, cp.square(tension)))
            + problem.linear[m : 2 * m] @ tension
            + regularization
            * (cp.sum_squares(compression) + cp.sum_squares(friction1) + cp.sum_squares(friction2))
        )
        cvx_problem = cp.Problem(cp.Minimize(objective), [equilibrium, *friction])
        kwargs = {}
        solver = self.solver or ("CLARABEL" if "CLARABEL" in cp.installed_solvers() else None)
        if solver == "CLARABEL":
            kwargs = {
                "tol_gap_abs": self.tolerance,
                "tol_gap_rel": self.tolerance,
                "tol_feas": self.tolerance,
            }
        try:
            cvx_problem.solve(solver=solver, **kwargs)
        except cp.error.SolverError as error:
            return Solution(
                SolveStatus.NUMERICAL_ERROR,
                None,
                None,
                float("nan"),
                0,
                time.perf_counter() - start,
                {"native_status": str(error)},
            )
        status = _STATUS.get(cvx_problem.status, SolveStatus.NUMERICAL_ERROR)
        seconds = time.perf_counter() - start
        if not status.solved:
            return Solution(
                status, None, None, float("nan"), 0, seconds, {"native_status": cvx_problem.status}
            )
        x = np.concatenate([compression.value, tension.value, friction1.value, friction2.value])
        # cvxpy's dual of "expr == 0" is the multiplier of +expr in the Lagrangian
        multipliers = np.asarray(equilibrium.dual_value, float).reshape(-1)
        stats = cvx_problem.solver_stats
        return Solution(
            status,
            x,
            multipliers,
            float(cvx_problem.value),
            int(stats.num_iters or 0),
            seconds,
            {"native_status": cvx_problem.status},
        )


def friction_constraints(problem, compression, friction1, friction2) -> list:
    """The friction model of ``problem`` on cvxpy variables: the Coulomb cone itself,
    ``||(u, t)|| <= mu c`` at each vertex, or each side of the pyramid,
    ``a u + b t <= mu cos(pi/K) c`` (its last row, ``c >= 0``, is the variable's sign)."""
    import cvxpy as cp

    if problem.second_order:
        return [cp.SOC(problem.friction * compression, cp.vstack([friction1, friction2]), axis=0)]
    return [g[1] * friction1 + g[2] * friction2 <= -g[0] * compression for g in problem.cone[:-1]]
