"""What every statics back-end shares: the status values, the solution record, the base class."""

from __future__ import annotations

__all__ = ["SolveStatus", "Solution", "SolveRequest", "Backend", "trivial_solution"]

import enum
import importlib.util
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from shapegen.errors import StaticsError
from shapegen.limits import remaining_seconds


class SolveStatus(enum.Enum):
    """Outcome of a solve. A value on the result, never an exception."""

    OPTIMAL = "optimal"
    OPTIMAL_INACCURATE = "optimal_inaccurate"
    INFEASIBLE = "infeasible"  # no equilibrium even with tension
    MAX_ITERATIONS = "max_iterations"
    NUMERICAL_ERROR = "numerical_error"

    @property
    def solved(self) -> bool:
        """True when the solution can be read (optimal or nearly so)."""
        return self in (SolveStatus.OPTIMAL, SolveStatus.OPTIMAL_INACCURATE)


@dataclass
class Solution:
    """A back-end's answer to a :class:`~shapegen.statics.assembly.StaticsProblem`.

    Attributes
    ----------
    status
        The outcome.
    x
        ``(4 m,)`` scaled variables ``[c, s, u, t]`` (N / W), or None when not solved.
    multipliers
        ``(6 nf,)`` scaled equilibrium multipliers ``lam`` with the Lagrangian
        ``objective + lam . (A x + w)``, so ``d objective / d w = lam``; None when not available.
    objective
        Optimal value of the scaled objective (``y / W^2`` for the paper's objective).
    iterations
        Iterations of the solver.
    seconds
        Wall time of the solve, s.
    info
        Back-end specific figures (factorisation time, native status...).
    """

    status: SolveStatus
    x: np.ndarray | None
    multipliers: np.ndarray | None
    objective: float
    iterations: int = 0
    seconds: float = 0.0
    info: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SolveRequest:
    """What a caller asks of a solve beyond its answer: shortcuts a back-end takes only when it
    declares them in :attr:`Backend.honours` (the others solve to the end, cold; the answer
    means the same). See :class:`~shapegen.statics.solvers.reduced.ReducedBackend`.

    Attributes
    ----------
    stop_above
        Stop once the optimal value is certainly above this scaled value (phase one).
    accept
        A test of the primal ``x`` (the feasibility certificate) that ends the solve once true.
    screen_above
        Stop once an estimate of the dual bound exceeds this scaled value (not a proof).
    warm_start
        Forces ``x`` of a problem with the same constraints to start from.
    """

    stop_above: float | None = None
    accept: Callable[[np.ndarray], bool] | None = None
    screen_above: float | None = None
    warm_start: np.ndarray | None = None


class Backend:
    """A solver back-end: a name, a lazy import, a status map, what it declares it can do
    (:attr:`second_order_cones`, :attr:`honours`) and one :meth:`solve`."""

    name: str = ""
    library: str | None = None  # the module the back-end imports lazily, if any
    second_order_cones: bool = False  # solves the exact Coulomb cone (pyramid "cone")
    honours: ClassVar[frozenset[str]] = frozenset()
    """The :class:`SolveRequest` fields this back-end acts on (attributes of the same names)."""

    def take(self, request: SolveRequest) -> Backend:
        """This back-end, set to act on what ``request`` asks and it declares it honours."""
        for name in self.honours:
            value = getattr(request, name)
            if value is not None:
                setattr(self, name, value)
        return self

    def refuse_unsupported(self, problem) -> None:
        """Raise :class:`StaticsError` for a problem this back-end cannot solve exactly: the
        exact friction cone on a back-end of linear inequalities only (solving it without the
        cone would drop friction's limit, a silent wrong answer)."""
        if problem.second_order and not self.second_order_cones:
            from shapegen.statics.solvers import cone_refusal

            raise StaticsError(cone_refusal(self.name))

    def available(self) -> bool:
        """True when the back-end's library can be imported."""
        return self.library is None or importlib.util.find_spec(self.library) is not None

    def solve(self, problem) -> Solution:  # pragma: no cover
        """Solve a :class:`~shapegen.statics.assembly.StaticsProblem`, with what
        :meth:`take` set (from scratch unless the back-end honours ``warm_start``)."""
        raise NotImplementedError


def trivial_solution(problem) -> Solution | None:
    """The answer for a problem without vertices (or without free blocks), else None: only an
    unloaded assembly is then in equilibrium."""
    if problem.n_vertices and problem.n_free:
        return None
    x = np.zeros(problem.n_variables)
    if problem.load.size and float(np.abs(problem.load).max()) > 0 and not problem.n_vertices:
        return Solution(SolveStatus.INFEASIBLE, None, None, float("nan"))
    return Solution(SolveStatus.OPTIMAL, x, np.zeros(problem.load.size), 0.0)


def limit_time(settings) -> None:
    """Give a Clarabel solve the time left on the work clock (judging's, see
    :func:`shapegen.limits.work_clock`) as its ``time_limit``: its iterations cannot look at
    the clock themselves. A solve that runs out ends with status ``MaxTime``, which the caller
    turns into the clock's one-line error (:func:`shapegen.limits.clock_ran_out`)."""
    left = remaining_seconds()
    if left is not None:
        settings.time_limit = max(left, 1e-3)
