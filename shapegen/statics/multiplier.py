"""The horizontal load multiplier: how much sideways load an assembly takes before it falls.

For a direction ``d`` in the ground plane (an azimuth), the linear program

    maximise lambda  subject to  A f + w + lambda l(d) = 0,  f compression-only in the friction
                                 pyramid (or cone) at every joint vertex,

has the same equilibrium rows ``A``, the same friction constraints and the same dead load ``w``
(the weights and point loads) as the tension-penalty problem, with the tensions fixed at zero; the
lateral load ``l(d)`` is every vertical load turned horizontal towards ``d``
(:func:`shapegen.statics.tilt.lateral_map`). Its optimum ``lambda*`` is the largest horizontal
load, as a fraction of the vertical loads, that the blocks carry on compression and friction
alone: the collapse multiplier of the equivalent static lateral load. By the scaling argument
of :mod:`shapegen.statics.tilt` the assembly then stands on a table tilted by ``theta`` towards
``d`` exactly when ``tan(theta) <= lambda*``: the critical tilt is ``atan(lambda*)``.

``lambda`` is free in sign: ``lambda* < 0`` means the assembly does not stand upright (it would
need to be tilted the other way), and an infeasible program that no tilt towards ``d`` lets it
stand. The worst direction is the one of least ``lambda*``: the set of horizontal loads an
assembly carries is convex (a projection of the convex set of admissible forces), so the
least ``lambda*`` over directions is its distance to the origin, reached at a smooth minimum of
``lambda*(azimuth)``; a sweep finds its neighbourhood and a bounded scalar search refines it.

The program is solved by Clarabel on the sparse matrices (an LP for the pyramids, an SOCP for the
exact cone), or by cvxpy for the readable reference formulation used in the tests.
"""

from __future__ import annotations

__all__ = [
    "DirectionCapacity",
    "STATUSES",
    "SWEEP_DIRECTIONS",
    "load_multiplier",
    "worst_direction",
]

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from shapegen.errors import OptionError, StaticsError
from shapegen.limits import clock_ran_out
from shapegen.statics.assembly import REGULARIZATION, StaticsProblem, load_vector
from shapegen.statics.solvers.base import limit_time
from shapegen.statics.tilt import lateral_map, load_direction_problem, normalized_azimuth
from shapegen.tolerances import TIE_REL

SWEEP_DIRECTIONS = 16
"""Directions of the sweep for the worst one: every 22.5 degrees. The least multiplier lies at
a smooth minimum; a sample within 11.25 degrees of it is within 2 % of it, and the refinement
(:data:`REFINE_AZIMUTH_DEG`) takes it the rest of the way."""

REFINE_AZIMUTH_DEG = 0.25
"""Azimuth resolution of the refined worst direction, degrees. Near the minimum the multiplier
varies as ``1 / cos(error)``: 0.25 degrees off changes it by one part in 100 000."""

UNBOUNDED_MULTIPLIER = 1e6
"""A multiplier above this (a tilt within 6e-5 degrees of 90) is unbounded: the assembly stands
at any tilt (blocks wedged between supports)."""

STATUSES = ("limit", "unbounded", "not_upright", "never", "failed")
"""``limit``: the assembly stands up to ``atan(lambda*)``; ``unbounded``: at every tilt below 90
degrees; ``not_upright``: it does not stand upright (``lambda* < 0``); ``never``: no tilt towards
this direction lets it stand; ``failed``: the solver did not converge."""


@dataclass(frozen=True)
class DirectionCapacity:
    """The capacity towards one azimuth.

    Attributes
    ----------
    azimuth
        Degrees in the ground plane from +x towards +z, in [0, 360).
    multiplier
        ``lambda*``: the largest horizontal load, as a fraction of the vertical loads (inf when
        unbounded, -inf when no tilt towards this direction stands, nan when the solver failed).
    status
        One of :data:`STATUSES`.
    method
        How it was found: ``"lp"`` (the load-multiplier program), ``"bisection"`` (on the
        verdict, when the program and the verdict disagreed).
    checked
        True when the verdict of the tension-penalty analysis confirmed it (stands half the
        resolution below, does not stand half the resolution above).
    seconds
        Time spent, s.
    """

    azimuth: float
    multiplier: float
    status: str
    method: str = "lp"
    checked: bool = False
    seconds: float = 0.0

    @property
    def tilt(self) -> float | None:
        """The critical tilt, degrees: ``atan(lambda*)``, 90 when unbounded, None when the
        assembly does not stand upright (or the solver failed)."""
        if self.status == "unbounded":
            return 90.0
        if self.status != "limit":
            return None
        return math.degrees(math.atan(max(self.multiplier, 0.0)))

    @property
    def rank(self) -> float:
        """Orders directions from the worst: the multiplier (-inf when none stands, +inf for a
        failed solve, which cannot be the worst)."""
        return self.multiplier if not math.isnan(self.multiplier) else math.inf

    def to_report(self) -> dict:
        """Plain JSON values (non-finite multipliers as None)."""
        multiplier = self.multiplier if math.isfinite(self.multiplier) else None
        if self.status == "limit":
            multiplier = max(float(multiplier), 0.0)
        elif self.status != "unbounded":
            multiplier = None
        return {
            "azimuth_deg": round(float(self.azimuth), 6),
            "tilt_deg": self.tilt,
            "load_multiplier": multiplier,
            "status": self.status,
            "method": self.method,
            "checked": bool(self.checked),
        }


def _program(problem: StaticsProblem):
    """The matrices of the load-multiplier program with variables ``[c, u, t, lambda]``:
    the equality block (without the lambda column), the linear inequalities and the
    second-order cone rows (None for the pyramids)."""
    m = problem.n_vertices
    keep = np.r_[0:m, 2 * m : 4 * m]  # the tension columns go: the tensions are zero
    equality = problem.equality[:, keep]
    inequality = problem.inequality_matrix()
    per_vertex = len(problem.cone) + 1
    rows = np.ones(inequality.shape[0], bool)
    rows[per_vertex - 1 :: per_vertex] = False  # the rows -s <= 0
    inequality = inequality[rows][:, keep]
    cones = problem.second_order_matrix()[:, keep] if problem.second_order else None
    return equality, inequality, cones


def load_multiplier(
    model, problem: StaticsProblem, azimuth: float, *, solver: str = "clarabel"
) -> DirectionCapacity:
    """The largest horizontal load multiplier towards ``azimuth`` (degrees).

    Parameters
    ----------
    model
        The model ``problem`` was assembled from (its loads must all be vertical:
        :func:`shapegen.statics.tilt.load_direction_problem`).
    problem
        The assembled problem (its own tilt, if any, is ignored: the multiplier is measured
        from upright).
    azimuth
        Direction of the horizontal load, degrees from +x towards +z.
    solver
        ``"clarabel"`` (direct, sparse) or ``"cvxpy"`` (the reference formulation).
    """
    reason = load_direction_problem(model)
    if reason is not None:
        raise StaticsError(
            f"the lateral capacity needs vertical loads (a tilt is then a horizontal load"
            f" proportional to them): {reason}"
        )
    if solver not in ("clarabel", "cvxpy"):
        raise OptionError(f"the load multiplier is solved by clarabel or cvxpy; got {solver!r}")
    start = time.perf_counter()
    azimuth = normalized_azimuth(azimuth)
    dead = load_vector(model, problem)
    lateral = load_vector(model, problem, lateral_map(azimuth))
    if problem.n_free == 0:
        return DirectionCapacity(azimuth, math.inf, "unbounded", seconds=0.0)
    if problem.n_vertices == 0:
        return DirectionCapacity(azimuth, -math.inf, "never", seconds=0.0)
    solve = _solve_clarabel if solver == "clarabel" else _solve_cvxpy
    outcome, value = solve(problem, dead, lateral)
    seconds = time.perf_counter() - start
    if outcome == "infeasible":
        return DirectionCapacity(azimuth, -math.inf, "never", seconds=seconds)
    if outcome == "unbounded" or (outcome == "optimal" and value >= UNBOUNDED_MULTIPLIER):
        return DirectionCapacity(azimuth, math.inf, "unbounded", seconds=seconds)
    if outcome != "optimal":
        return DirectionCapacity(azimuth, math.nan, "failed", seconds=seconds)
    status = "limit" if value >= 0 else "not_upright"
    return DirectionCapacity(azimuth, float(value), status, seconds=seconds)


def _solve_clarabel(problem, dead, lateral) -> tuple[str, float]:
    import clarabel

    equality, inequality, cones = _program(problem)
    n = equality.shape[1]
    column = sp.csc_matrix(lateral.reshape(-1, 1))
    blocks = [sp.hstack([equality, column], format="csc")]
    blocks.append(sp.hstack([inequality, sp.csc_matrix((inequality.shape[0], 1))], format="csc"))
    kinds = [clarabel.ZeroConeT(equality.shape[0]), clarabel.NonnegativeConeT(inequality.shape[0])]
    if cones is not None:
        blocks.append(sp.hstack([cones, sp.csc_matrix((cones.shape[0], 1))], format="csc"))
        kinds += [clarabel.SecondOrderConeT(3)] * problem.n_vertices
    constraints = sp.vstack(blocks, format="csc")
    rhs = np.zeros(constraints.shape[0])
    rhs[: equality.shape[0]] = -dead
    # The minute Tikhonov term of the penalty problem keeps the optimal forces bounded when a
    # self-stress exists; its effect on lambda is of order 1e-10.
    objective = sp.diags(np.r_[np.full(n, REGULARIZATION), 0.0], format="csc")
    linear = np.zeros(n + 1)
    linear[-1] = -1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_iter = 200
    # Clarabel's own LDL: "auto" picks the multithreaded faer, three times the process time
    # here (a 1 000-block wall: 3.9 s against 12.6 s of CPU, the same 29 iterations)
    settings.direct_solve_method = "qdldl"
    limit_time(settings)
    result = clarabel.DefaultSolver(objective, linear, constraints, rhs, kinds, settings).solve()
    native = str(result.status).split(".")[-1]
    if native == "MaxTime":
        clock_ran_out()
    if native in ("Solved", "AlmostSolved"):
        return "optimal", float(result.x[-1])
    if native in ("PrimalInfeasible", "AlmostPrimalInfeasible"):
        return "infeasible", math.nan
    if native in ("DualInfeasible", "AlmostDualInfeasible"):
        return "unbounded", math.inf
    return "failed", math.nan


def _solve_cvxpy(problem, dead, lateral) -> tuple[str, float]:
    import cvxpy as cp

    from shapegen.statics.solvers.cvxpy_reference import friction_constraints

    m = problem.n_vertices
    a = problem.equality
    compression = cp.Variable(m, nonneg=True)
    friction1, friction2 = cp.Variable(m), cp.Variable(m)
    multiplier = cp.Variable()
    equilibrium = (
        a[:, :m] @ compression
        + a[:, 2 * m : 3 * m] @ friction1
        + a[:, 3 * m :] @ friction2
        + dead
        + multiplier * lateral
        == 0
    )
    friction = friction_constraints(problem, compression, friction1, friction2)
    squares = cp.sum_squares(compression) + cp.sum_squares(friction1) + cp.sum_squares(friction2)
    regularization = REGULARIZATION / 2 * squares
    program = cp.Problem(cp.Maximize(multiplier - regularization), [equilibrium, *friction])
    try:
        program.solve(solver="CLARABEL" if "CLARABEL" in cp.installed_solvers() else None)
    except cp.error.SolverError:
        return "failed", math.nan
    if program.status in ("optimal", "optimal_inaccurate"):
        return "optimal", float(multiplier.value)
    if program.status in ("infeasible", "infeasible_inaccurate"):
        return "infeasible", math.nan
    if program.status in ("unbounded", "unbounded_inaccurate"):
        return "unbounded", math.inf
    return "failed", math.nan


def worst_direction(
    model,
    problem: StaticsProblem,
    *,
    directions: int = SWEEP_DIRECTIONS,
    solver: str = "clarabel",
) -> tuple[DirectionCapacity, list[DirectionCapacity]]:
    """The direction of least multiplier, and the sweep that led to it.

    A sweep of ``directions`` azimuths evenly spaced from 0, then a bounded scalar search
    (Brent) within one step either side of the least, to :data:`REFINE_AZIMUTH_DEG`.
    Directions whose multipliers agree to one part in 10^9 are the same: the least azimuth of
    them is the worst (a symmetric design gives 0 rather than 180 degrees).
    Returns ``(worst, sweep)``, the sweep in order of azimuth.
    """
    from scipy.optimize import minimize_scalar

    if directions < 1:
        raise OptionError(f"the sweep needs at least one direction; got {directions}")
    step = 360.0 / directions
    computed: dict[float, DirectionCapacity] = {}

    def at(azimuth: float) -> DirectionCapacity:
        key = round(normalized_azimuth(azimuth), 4) % 360.0
        if key not in computed:
            computed[key] = load_multiplier(model, problem, key, solver=solver)
        return computed[key]

    sweep = [at(k * step) for k in range(directions)]
    start = _least(sweep)
    if directions > 1 and start.status in ("limit", "not_upright"):

        def multiplier_at(azimuth: float) -> float:
            rank = at(azimuth).rank
            return rank if math.isfinite(rank) else 1e300

        minimize_scalar(
            multiplier_at,
            bounds=(start.azimuth - step, start.azimuth + step),
            method="bounded",
            options={"xatol": REFINE_AZIMUTH_DEG},
        )
    return _least(list(computed.values())), sweep


def _least(candidates: list[DirectionCapacity]) -> DirectionCapacity:
    """The direction of least multiplier; near-ties go to the least azimuth."""
    least = min(c.rank for c in candidates)
    slack = TIE_REL * max(1.0, abs(least)) if math.isfinite(least) else 0.0
    return min((c for c in candidates if c.rank <= least + slack), key=lambda c: c.azimuth)
