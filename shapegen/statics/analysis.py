"""``analyze(model)``: does a block assembly stand? The tension-penalty QP and its verdict.

The infeasibility ``y`` is the least sum of squared vertex tensions (N^2) that holds every free
block in equilibrium with the friction pyramid respected (Whiting, Ochsendorf, Durand 2009):
``y = 0`` means the assembly stands with compression and friction alone.

The verdict ``feasible`` is scale independent and robust to solver noise. It comes from a
certificate: a set of compressive, pyramid-respecting vertex forces whose equilibrium residual
(largest entry, forces / W and torques / (W L), see :func:`certify`) is at most
``tolerances.feasible_rel``. The forces are tried first from the least-norm equilibrium
(:mod:`~shapegen.statics.certificate`; solver ``auto`` or ``reduced``): a wall that stands
comfortably is certified without any interior point iteration. Otherwise they are
taken from the linear phase-one problem ``min sum s`` on the same constraints: an interior
point solution of it carries tensions of the order of the barrier parameter (~1e-12 W),
whereas one of ``min sum s^2`` keeps tensions of order sqrt(barrier) that would blur the
verdict near a limit state. Either way the same test decides (:attr:`Analysis.decided_by`
says whose forces it read).

0. least-norm forces certified: feasible, ``y = 0`` (the certified forces carry no tension),
   multipliers zero;
1. phase one infeasible (no equilibrium even with tension: e.g. a tangential load with no
   friction): not feasible, ``y = inf``;
2. phase one certified: feasible; ``y`` is the (negligible) sum of squared phase-one tensions and
   the multipliers are zero (``y`` vanishes around a feasible design);
3. otherwise not feasible, and the QP ``min sum s^2`` gives ``y``. (Should phase one fail to
   converge, the QP is solved alone and judged as in the seed paper: not feasible when
   ``y / W^2 > tolerances.screen_rel``, else by the certificate on its own solution.)

Sliding is not a solver failure: with tension allowed, a large compression paired with an equal
tension buys friction capacity, so an assembly that could only stand by sliding gets a finite
``y > 0`` and ``feasible = False`` with status ``optimal``.
"""

from __future__ import annotations

__all__ = ["DECIDERS", "Analysis", "analyze", "certify"]

import math
import time
from dataclasses import dataclass, field

import numpy as np

from shapegen.errors import OptionError
from shapegen.json_values import finite_or_none
from shapegen.statics.assembly import StaticsProblem, assemble, tilted
from shapegen.statics.bodies import contacts_and_bodies
from shapegen.statics.certificate import (
    certify,
    least_norm_certificate,
    nearby_forces,
    reserve_certificate,
)
from shapegen.statics.interface import Interface
from shapegen.statics.solvers import Solution, SolveRequest, SolveStatus, get_backend
from shapegen.statics.standins import design_blocks, design_figures, statics_model
from shapegen.statics.statics_options import StaticsOptions
from shapegen.statics.tension import PHASE_ONE_STOP, proves_tension
from shapegen.tolerances import DEFAULT as DEFAULT_TOLERANCES
from shapegen.tolerances import ROUNDOFF_REL

# estimated sum of tensions (of W) above which phase one may stop on its estimate; the QP then
# confirms "does not stand" (y / W^2 above screen_rel), else phase one is run in full
PHASE_ONE_SCREEN = 0.1

DECIDERS = ("least_norm", "phase_one", "qp", "reserve", "carried")
"""The values of :attr:`Analysis.decided_by`."""


@dataclass
class Analysis:
    """The outcome of :func:`analyze`.

    Attributes
    ----------
    status
        Solver outcome (:class:`SolveStatus`).
    feasible
        True when the assembly stands (see the module docstring for the criterion).
    infeasibility
        ``y``, N^2: least sum of squared vertex tensions (inf when no equilibrium exists).
    infeasibility_normalized
        ``y / W^2``, dimensionless.
    max_tension
        Largest vertex tension, N.
    total_weight
        ``W``, weight of the free (structural, non-fixed) blocks, N.
    interfaces
        The interfaces analysed (scaled by the kern).
    resultant_forces
        ``(ni, 3)`` N: total force on ``second`` from ``first``.
    resultant_points
        ``(ni, 3)`` m: centre of the normal forces in the interface plane (nan when the normal
        resultant is ~0).
    interface_tension
        ``(ni,)`` N: sum of the vertex tensions of each interface.
    block_tension
        ``(nb,)`` N per block of ``model.blocks``: largest ``interface_tension`` touching it.
    forces
        ``(m, 4)`` per vertex: compression, tension, friction along tangent1 and tangent2, N.
    multipliers
        ``(6 nf,)`` equilibrium multipliers, six per free block (force rows, then torque rows),
        with ``dy/dw = multipliers`` for the external wrench ``w`` (units N for force rows and
        N / m for torque rows, so that their products with N and N m give N^2), or None.
    timings
        Seconds spent in "interfaces", "assembly", "solve", "certify" (and "directions", the
        search for the worst direction of a tilt without an azimuth).
    solver
        The back-end that produced the solution.
    problem
        The assembled problem (reusable: sparsity pattern, orderings, index arrays).
    model
        The model analysed (``analyze(model, stood=...)`` checks it is the same one).
    worst_direction
        True when a tilt without an azimuth was turned towards the worst direction found.
    bodies
        The :class:`~shapegen.statics.bodies.Bodies` judged (the blocks' own when each block is
        its own body and nothing rides as load).
    stand_ins
        The :class:`~shapegen.statics.standins.StandIns` judged in place of leaves the model
        keeps as drawn (None when there are none). ``model`` is then the
        :class:`~shapegen.statics.standins.StaticsModel` judged, and ``n_blocks`` and
        ``block_tension`` are those of the model's own blocks, which come first in it.
    decided_by
        Whose forces or bound decided the verdict (one of :data:`DECIDERS`): ``"least_norm"``
        (the least-norm forces passed the certificate: no interior point iteration ran),
        ``"phase_one"`` (phase one's forces passed it, or phase one found no equilibrium),
        ``"qp"`` (the QP's tension: does not stand), ``"reserve"`` (the forces of the same
        design judged with a reserve, ``stood``), ``"carried"`` (the last design's forces or
        multipliers, :func:`~shapegen.statics.incremental.reanalyze`).
    """

    status: SolveStatus
    feasible: bool
    infeasibility: float
    infeasibility_normalized: float
    max_tension: float
    total_weight: float
    interfaces: list[Interface]
    resultant_forces: np.ndarray
    resultant_points: np.ndarray
    interface_tension: np.ndarray
    block_tension: np.ndarray
    forces: np.ndarray
    multipliers: np.ndarray | None
    timings: dict[str, float]
    solver: str
    problem: StaticsProblem | None = field(default=None, repr=False)
    n_blocks: int = 0
    model: object = field(default=None, repr=False)
    worst_direction: bool = False
    bodies: object = field(default=None, repr=False)
    stand_ins: object = field(default=None, repr=False)
    decided_by: str = "phase_one"

    @property
    def tilt(self) -> dict | None:
        """The tilt the loads were turned by (``tilt_deg``, ``azimuth_deg``, its
        ``load_multiplier`` ``tan(tilt)``, and ``azimuth``: ``"worst"`` when the direction is
        the one of least lateral capacity, else ``"given"``), or None when upright."""
        problem = self.problem
        if problem is None or not problem.tilt:
            return None
        return {
            "tilt_deg": float(problem.tilt),
            "azimuth_deg": round(float(problem.azimuth), 6),
            "load_multiplier": math.tan(math.radians(problem.tilt)),
            "azimuth": "worst" if self.worst_direction else "given",
        }

    def to_report(self) -> dict:
        """A JSON-ready summary (plain Python numbers and strings)."""
        number = finite_or_none
        return {
            "blocks": int(self.n_blocks),
            "interfaces": len(self.interfaces),
            "feasible": bool(self.feasible),
            "infeasibility": number(self.infeasibility),
            "infeasibility_normalized": number(self.infeasibility_normalized),
            "max_tension": number(self.max_tension),
            "total_weight": number(self.total_weight),
            "seconds": float(sum(self.timings.values())),
            "status": self.status.value,
            "solver": self.solver,
            "decided_by": self.decided_by,
            "friction": number(self.problem.friction) if self.problem is not None else None,
            "pyramid": self.problem.pyramid if self.problem is not None else None,
            "timings": {k: float(v) for k, v in self.timings.items()},
            # 0: nothing to judge (a rule of faces models no solid; every block a support)
            "free_bodies": self.problem.n_free if self.problem is not None else 0,
            **({"tilt": self.tilt} if self.tilt is not None else {}),
            **(
                {"bodies": self.bodies.to_report()}
                if self.bodies is not None and not self.bodies.trivial
                else {}
            ),
            **({"stand_ins": self.stand_ins.to_report()} if self.stand_ins is not None else {}),
        }


def _solve(
    problem: StaticsProblem,
    names: tuple[str, ...],
    phase_one: bool = False,
    accept=None,
    screen: bool = False,
    warm_start: np.ndarray | None = None,
) -> tuple[Solution, str]:
    """Solve with the first of ``names`` that succeeds (an inaccurate solution is enough when
    only its primal forces are read, as for the certificate; a back-end that can may stop at
    the first solution that ``accept`` certifies)."""
    accepted = {SolveStatus.OPTIMAL, SolveStatus.INFEASIBLE}
    if phase_one:
        accepted.add(SolveStatus.OPTIMAL_INACCURATE)
    fallback = None
    request = SolveRequest(
        # phase one only has to tell "zero" from "clearly positive" (1e4 times the
        # certificate's resolution)
        stop_above=PHASE_ONE_STOP if phase_one else None,
        accept=accept,
        screen_above=PHASE_ONE_SCREEN if screen else None,
        warm_start=warm_start,
    )
    for name in names:
        solution = get_backend(name).take(request).solve(problem)
        if solution.status in accepted:
            return solution, name
        if fallback is None or (solution.status.solved and not fallback[0].status.solved):
            fallback = (solution, name)
    return fallback


def analyze(
    model,
    options: StaticsOptions | None = None,
    *,
    interfaces: list[Interface] | None = None,
    check: bool = True,
    stood: Analysis | None = None,
    bodies=None,
    expect_tension: bool = False,
    warm_start: Analysis | None = None,
    **settings: object,
) -> Analysis:
    """Check whether ``model`` stands under self-weight and its point loads.

    Parameters
    ----------
    model
        The :class:`~shapegen.model.model.Model`.
    options
        A :class:`~shapegen.statics.statics_options.StaticsOptions` (friction, pyramid, kern,
        solver, and a tilt of the loads towards an azimuth, or towards the worst direction).
    interfaces
        Precomputed contact interfaces (unscaled); found with ``find_interfaces`` when None.
    check
        Run ``check_model`` (unsupported bodies, blocks below the ground) first.
    stood
        An analysis of this same model with every joint shrunk as much or more (a larger
        margin) that stands: its interfaces and checks are reused, and its forces, moved to
        these joints (:mod:`shapegen.statics.reserve`), are the certificate without a solve
        (a search that judged its design with a reserve reports it without one this way).
    bodies
        The model's :class:`~shapegen.statics.bodies.Bodies` for these ``interfaces`` (found
        with :func:`~shapegen.statics.bodies.find_bodies` when None).
    expect_tension
        Solve the QP first (a search whose last design needed tension): phase one is only run
        when the QP does not prove the tension (:func:`~shapegen.statics.tension.proves_tension`).
    warm_start
        The analysis of a nearby design (the last one of a search): when its joints are this
        model's (the same pairs of blocks, the same vertex count each), its forces start the
        interior point solves instead of the cold start (the verdict and ``y`` are the same;
        fewer iterations).
    settings
        Instead of ``options``, its fields by name: ``analyze(model, friction=0.5)``.

    Returns
    -------
    Analysis
    """
    if options is None:
        options = StaticsOptions.from_mapping(settings)
    elif settings:
        raise OptionError(
            f"give either a StaticsOptions or its fields, not both ({', '.join(settings)})"
        )
    friction, pyramid, kern = options.friction, options.pyramid, options.kern
    order = options.backends()
    model = statics_model(model)  # leaves the model keeps as drawn, judged as stand-ins
    timings = {"interfaces": 0.0, "assembly": 0.0, "solve": 0.0, "certify": 0.0}
    size = float(model.size)  # one pass over the blocks for the tolerances and the length
    tol = DEFAULT_TOLERANCES.for_size(size)

    start = time.perf_counter()
    reuse = stood is not None and stood.model is model and stood.feasible and stood.problem
    if reuse and interfaces is None:
        interfaces, check = stood.problem.cache.get("interfaces"), False
        bodies = stood.bodies if bodies is None else bodies
    interfaces, bodies = contacts_and_bodies(
        model, options, tol, interfaces=interfaces, bodies=bodies, check=check
    )
    timings["interfaces"] = time.perf_counter() - start

    start = time.perf_counter()
    problem = assemble(
        model, interfaces, friction=friction, pyramid=pyramid, kern=float(kern), length=size,
        bodies=None if bodies.trivial else bodies,
    )  # fmt: skip
    problem.cache["interfaces"] = interfaces
    problem.cache["bodies"] = bodies
    timings["assembly"] = time.perf_counter() - start
    worst = options.tilted and options.azimuth is None
    if options.tilted:
        azimuth = options.azimuth
        if worst:
            from shapegen.statics.multiplier import worst_direction

            start = time.perf_counter()
            azimuth = worst_direction(model, problem)[0].azimuth
            timings["directions"] = time.perf_counter() - start
        problem = tilted(problem, model, options.tilt, azimuth)
    if reuse:
        known = reserve_certificate(stood, problem, tol)
        if known is not None:
            timings["certify"] = known.info["certify"]
            return _build_analysis(model, problem, known, stood.solver, True, known.objective,
                                   timings, worst, "reserve")  # fmt: skip
    if not expect_tension and order and order[0] == "reduced":
        least = least_norm_certificate(problem, tol, timings)
        if least is not None:
            return _build_analysis(model, problem, least, order[0], True, 0.0, timings, worst,
                                   "least_norm")  # fmt: skip

    start = time.perf_counter()
    near = nearby_forces(warm_start, problem)

    def solve_phase_one(screen: bool) -> tuple[Solution, str]:
        return _solve(
            problem.with_objective("tension_sum"),
            order,
            phase_one=True,
            accept=lambda x: certify(problem, x) <= tol.feasible_rel,
            screen=screen,
            warm_start=near,
        )

    # the QP first
    qp, qp_used = _solve(problem, order, warm_start=near) if expect_tension else (None, None)
    if qp is not None and proves_tension(qp):  # then the only solve
        timings["solve"] = time.perf_counter() - start
        y_norm = float(np.sum(qp.x[problem.n_vertices : 2 * problem.n_vertices] ** 2))
        return _build_analysis(model, problem, qp, qp_used, False, y_norm, timings, worst, "qp")
    qp = qp if qp is not None and qp.status.solved else None  # else judged from scratch below
    phase_one, used = solve_phase_one(screen=qp is None)
    timings["solve"] = time.perf_counter() - start
    start = time.perf_counter()
    feasible = phase_one.status.solved and certify(problem, phase_one.x) <= tol.feasible_rel
    if (
        not feasible
        and len(order) > 1
        and phase_one.status is SolveStatus.OPTIMAL_INACCURATE
        and used != order[-1]
        and _tension_sum(problem, phase_one.x) <= PHASE_ONE_STOP
    ):
        # Near the feasibility boundary the fast back-end may stop short; an inaccurate
        # phase one must not decide "does not stand" when the exact back-end can certify it.
        # (Far from it, phase one stops early on purpose: the tension is clearly positive.)
        phase_one, used = _solve(problem.with_objective("tension_sum"), order[-1:], True)
        feasible = phase_one.status.solved and certify(problem, phase_one.x) <= tol.feasible_rel
    timings["certify"] = time.perf_counter() - start

    decided_by = "phase_one"
    if phase_one.status is SolveStatus.INFEASIBLE:
        solution, y_norm = phase_one, float("inf")
    elif feasible:
        solution = phase_one
        m = problem.n_vertices
        y_norm = float(np.sum(phase_one.x[m : 2 * m] ** 2))
        solution.multipliers = np.zeros_like(phase_one.multipliers)
    else:
        start = time.perf_counter()
        if qp is None:  # the QP starts from phase one's forces (same constraints) where it can
            qp, qp_used = _solve(problem, order, warm_start=phase_one.x)
        solution, used = qp, qp_used
        decided_by = "qp"
        timings["solve"] += time.perf_counter() - start
        if solution.status.solved:
            m = problem.n_vertices
            y_norm = float(np.sum(solution.x[m : 2 * m] ** 2))
            if phase_one.info.get("screened") and not proves_tension(solution, tol.screen_rel):
                # phase one stopped on an estimate and the QP's tension is small: decide exactly
                start = time.perf_counter()
                phase_one, _ = solve_phase_one(screen=False)
                timings["solve"] += time.perf_counter() - start
                if phase_one.status.solved and certify(problem, phase_one.x) <= tol.feasible_rel:
                    feasible, solution, decided_by = True, phase_one, "phase_one"
                    y_norm = float(np.sum(phase_one.x[m : 2 * m] ** 2))
                    solution.multipliers = np.zeros_like(phase_one.multipliers)
            if not phase_one.status.solved and y_norm <= tol.screen_rel:
                start = time.perf_counter()
                feasible = certify(problem, solution.x) <= tol.feasible_rel
                timings["certify"] += time.perf_counter() - start
        elif solution.status is SolveStatus.INFEASIBLE:
            y_norm = float("inf")
        else:
            y_norm = float("nan")
    return _build_analysis(
        model, problem, solution, used, feasible, y_norm, timings, worst, decided_by
    )


def _tension_sum(problem: StaticsProblem, x: np.ndarray | None) -> float:
    """Scaled sum of the vertex tensions of a solution (inf without one)."""
    if x is None:
        return float("inf")
    m = problem.n_vertices
    return float(np.sum(x[m : 2 * m]))


def _build_analysis(
    model, problem, solution, used, feasible, y_norm, timings, worst=False, decided_by="phase_one"
) -> Analysis:
    m = problem.n_vertices
    ni = len(problem.interfaces)
    nb = len(model.blocks)
    weight = problem.weight
    if solution.x is not None:
        forces = solution.x.reshape(4, m).T * weight
    else:
        forces = np.full((m, 4), np.nan)
    frames = (
        np.array([(i.normal, i.tangent1, i.tangent2) for i in problem.interfaces], float)
        if ni
        else np.zeros((0, 3, 3))
    )
    owner = problem.vertex_interface
    normal_force = forces[:, 0] - forces[:, 1]
    local = np.stack([normal_force, forces[:, 2], forces[:, 3]], axis=1)  # (m, 3)
    world = np.einsum("vi,vij->vj", local, frames[owner]) if m else np.zeros((0, 3))
    resultant = np.stack([np.bincount(owner, world[:, k], minlength=ni) for k in range(3)], axis=1)
    normal_total = np.bincount(owner, normal_force, minlength=ni)
    moment = np.stack(
        [
            np.bincount(owner, normal_force * problem.vertex_points[:, k], minlength=ni)
            for k in range(3)
        ],
        axis=1,
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        points = moment / normal_total[:, None]
    points[np.abs(normal_total) <= ROUNDOFF_REL * weight] = np.nan
    tension = np.bincount(owner, forces[:, 1], minlength=ni)
    block_tension = np.zeros(nb)
    if ni:
        first = np.array([i.first for i in problem.interfaces])
        second = np.array([i.second for i in problem.interfaces])
        safe = np.nan_to_num(tension)
        np.maximum.at(block_tension, first, safe)
        on_block = second >= 0
        np.maximum.at(block_tension, second[on_block], safe[on_block])
        structural_free = problem.free_index >= 0
        block_tension[~structural_free] = 0.0
    # the figures per block are the model's own blocks' (its stand-ins, if any, follow them)
    block_tension = design_figures(block_tension, model)
    multipliers = None
    if solution.multipliers is not None:
        # d(y/W^2)/d(w/W) = lam  ->  dy/dw = W lam (force rows), W lam / L (torque rows)
        lam = solution.multipliers.reshape(-1, 6) * weight
        lam[:, 3:] /= problem.length
        multipliers = lam.reshape(-1)
    total_weight = problem.weight if problem.n_free else 0.0
    y = y_norm * weight**2 if np.isfinite(y_norm) else y_norm
    # round-off can leave tiny negative tensions: a tension is never below zero
    max_tension = max(float(np.max(forces[:, 1])), 0.0) if m and solution.x is not None else 0.0
    if solution.x is None and solution.status is SolveStatus.INFEASIBLE:
        max_tension = float("inf")
    return Analysis(
        status=solution.status,
        feasible=bool(feasible),
        infeasibility=float(y),
        infeasibility_normalized=float(y_norm),
        max_tension=max_tension,
        total_weight=float(total_weight),
        interfaces=problem.interfaces,
        resultant_forces=resultant,
        resultant_points=points,
        interface_tension=tension,
        block_tension=block_tension,
        forces=forces,
        multipliers=multipliers,
        timings=timings,
        solver=used,
        problem=problem,
        n_blocks=design_blocks(model),
        model=model,
        worst_direction=bool(worst),
        bodies=problem.cache.get("bodies"),
        stand_ins=getattr(model, "stand_ins", None),
        decided_by=decided_by,
    )
