"""Parameter search: tune a grammar's free attrs until its model stands.

The seed paper (Whiting, Ochsendorf, Durand 2009): rebuild the model for parameters theta,
analyse it, and minimise the infeasibility y(theta) within the bounds of the free parameters with
SQP, stopping as soon as the model is feasible. We minimise the normalised infeasibility
``y / W^2`` (dimensionless, so the same settings work for a garden wall and a cathedral) over the
parameters rescaled to [0, 1] by their ``@Range``.

Gradients:

- ``"forward"``: forward finite differences, n + 1 analyses per gradient (the paper's choice).
- ``"adjoint"``: by the envelope theorem, ``dy/dtheta = lambda . (dA/dtheta f + dw/dtheta)`` with
  the optimal forces ``f`` and equilibrium multipliers ``lambda`` of the one QP already solved.
  ``A`` and ``w`` depend on theta only through the geometry, so their derivatives are taken by
  finite differences of the *assembly* (rebuild, find interfaces, assemble; no QP). One QP per
  gradient whatever the number of parameters. Where a step changes the contact topology, that
  component falls back to a forward difference.

``objective="closest"`` (ours) looks for the feasible design nearest to the designer's values:
minimise ``||theta - theta0||^2`` (scaled by the ranges) subject to ``sqrt(y / W^2) <= 0``.
"""

from __future__ import annotations

__all__ = [
    "FreeParameter",
    "Evaluation",
    "IterationRecord",
    "OptimizationResult",
    "select_parameters",
    "Evaluator",
    "optimize",
    "OBJECTIVES",
    "GRADIENTS",
]

import difflib
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize
from scipy.spatial import cKDTree

from shapegen.errors import GeometryError, GrammarError, ShapegenError, StaticsError
from shapegen.model.model import Model

OBJECTIVES = ("energy", "closest")
GRADIENTS = ("adjoint", "forward")

# Relative step (fraction of a parameter's range) of the finite differences on the geometry and,
# for the forward-difference gradient, on the whole analysis. The geometry is exact to round-off,
# so a small step is safe there; the QP solution is accurate to ~1e-9, so forward differences of y
# need a larger step.
ADJOINT_STEP = 1e-6
FORWARD_STEP = 1e-4
# Length of the SQP's first step, as a fraction of the parameter ranges.
FIRST_STEP = 0.1


@dataclass(frozen=True)
class FreeParameter:
    """A parameter the search may change: its attr name, starting value and bounds."""

    name: str
    initial: float
    lower: float
    upper: float

    @property
    def span(self) -> float:
        return self.upper - self.lower


@dataclass
class Evaluation:
    """One build and analysis at ``theta``."""

    theta: np.ndarray
    model: Model | None
    analysis: object | None
    infeasibility: float  # y / W^2, dimensionless; inf when the evaluation failed
    feasible: bool
    error: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None and math.isfinite(self.infeasibility)


@dataclass(frozen=True)
class IterationRecord:
    """What the progress display shows after each iteration."""

    iteration: int
    infeasibility: float
    feasible: bool
    parameters: dict[str, float]
    qp_solves: int
    seconds: float


@dataclass
class OptimizationResult:
    """The outcome of :func:`optimize`.

    ``converged`` is True when the search stopped for a reason other than the iteration limit or
    a failure (feasible found, or a local minimum reached). ``parameters`` maps each free
    parameter to ``{initial, final, min, max}``; ``path`` holds theta after each iteration.
    """

    converged: bool
    feasible: bool
    iterations: int
    qp_solves: int
    seconds: float
    initial_infeasibility: float
    final_infeasibility: float
    parameters: dict[str, dict[str, float]]
    message: str
    objective: str
    gradient: str
    path: list[dict[str, float]] = field(default_factory=list)
    model: Model | None = None
    analysis: object | None = None
    margin: float = 0.0

    @property
    def seconds_per_iteration(self) -> float:
        return self.seconds / self.iterations if self.iterations else 0.0

    @property
    def values(self) -> dict[str, float]:
        """Final parameter values, ``name -> value``."""
        return {name: p["final"] for name, p in self.parameters.items()}

    def to_report(self) -> dict:
        """The ``optimization`` object of a build report (plain JSON types)."""

        def number(value):
            return float(value) if math.isfinite(value) else None

        return {
            "converged": self.converged,
            "feasible": self.feasible,
            "iterations": self.iterations,
            "qp_solves": self.qp_solves,
            "seconds": self.seconds,
            "seconds_per_iteration": self.seconds_per_iteration,
            "initial_infeasibility": number(self.initial_infeasibility),
            "final_infeasibility": number(self.final_infeasibility),
            "objective": self.objective,
            "gradient": self.gradient,
            "message": self.message,
            "margin": self.margin,
            "parameters": self.parameters,
        }


def select_parameters(
    grammar,
    free: Sequence[str] | None = None,
    fix: Mapping[str, object] | None = None,
    attrs: Mapping[str, object] | None = None,
) -> tuple[list[FreeParameter], dict[str, object]]:
    """The parameters to search and the attrs held fixed.

    ``free`` names attrs to search (each needs a ``@Range``); by default the ``@Free`` attrs.
    ``fix`` pins attrs (also removing them from the free set). Returns the free parameters and
    the attr overrides to build with.
    """
    attrs = dict(attrs or {})
    fix = dict(fix or {})
    known = grammar.attrs
    for name in [*(free or []), *fix]:
        if name not in known:
            close = difflib.get_close_matches(name, list(known), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise GrammarError(f"{grammar.name}: no attr named {name!r}{hint}")
    attrs.update(fix)
    ranges = grammar.parameter_ranges(attrs)
    names = list(free) if free else list(grammar.free_parameters)
    names = [n for n in names if n not in fix]
    if not names:
        raise GrammarError(
            f"{grammar.name}: nothing to optimize: no attr is marked @Free (or all are fixed); "
            "name some with --free"
        )
    parameters = []
    for name in names:
        if name not in ranges:
            raise GrammarError(
                f"{grammar.name}: attr {name!r} has no @Range, so it cannot be a free parameter"
            )
        spec = ranges[name]
        lower, upper, initial = spec["min"], spec["max"], spec["value"]
        if type(initial) is not float:
            raise GrammarError(f"{grammar.name}: attr {name!r} is not a number")
        if not (lower < upper):
            raise GrammarError(f"{grammar.name}: attr {name!r} has an empty @Range")
        parameters.append(FreeParameter(name, min(max(initial, lower), upper), lower, upper))
    return parameters, attrs


class Evaluator:
    """Builds and analyses the model at parameter values theta; counts QP solves; caches."""

    def __init__(
        self,
        grammar,
        parameters: Sequence[FreeParameter],
        attrs: Mapping[str, object] | None = None,
        *,
        seed: int = 0,
        lot: tuple[float, float] | None = None,
        analysis_options: Mapping[str, object] | None = None,
    ):
        self.grammar = grammar
        self.parameters = list(parameters)
        self.attrs = dict(attrs or {})
        self.seed = seed
        self.lot = lot
        self.analysis_options = dict(analysis_options or {})
        self.qp_solves = 0
        self._cache: dict[tuple, Evaluation] = {}

    @property
    def lower(self) -> np.ndarray:
        return np.array([p.lower for p in self.parameters])

    @property
    def upper(self) -> np.ndarray:
        return np.array([p.upper for p in self.parameters])

    def named(self, theta: np.ndarray) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.parameters, theta, strict=True)}

    def build(self, theta: np.ndarray) -> Model:
        attrs = {**self.attrs, **self.named(theta)}
        return self.grammar.build(attrs=attrs, seed=self.seed, lot=self.lot)

    def evaluate(self, theta: np.ndarray) -> Evaluation:
        """Build and analyse at ``theta`` (cached: SQP asks twice for the same point)."""
        from shapegen.statics import analyze

        theta = np.clip(np.asarray(theta, float), self.lower, self.upper)
        key = tuple(np.round(theta, 15))
        if key in self._cache:
            return self._cache[key]
        try:
            model = self.build(theta)
            analysis = analyze(model, **self.analysis_options)
            self.qp_solves += 1
            y = float(analysis.infeasibility_normalized)
            evaluation = Evaluation(theta, model, analysis, y, bool(analysis.feasible))
            if not math.isfinite(y):
                evaluation.error = f"the analysis returned status {analysis.status.value}"
        except (GrammarError, GeometryError, StaticsError) as exc:
            message = str(exc).splitlines()[0]
            evaluation = Evaluation(theta, None, None, math.inf, False, message)
        self._cache[key] = evaluation
        return evaluation

    # ------------------------------------------------------------------ gradients
    def gradient(self, theta: np.ndarray, method: str = "adjoint") -> np.ndarray:
        """``d(y / W^2) / d theta`` (per unit of each parameter)."""
        base = self.evaluate(theta)
        if not base.ok:
            return np.zeros(len(self.parameters))
        if method == "forward":
            return np.array([self._forward(base, j) for j in range(len(self.parameters))])
        return self._adjoint(base)

    def _step(self, theta: np.ndarray, j: int, relative: float) -> float:
        h = relative * self.parameters[j].span
        # step inwards at the upper bound so the probe stays within the range
        return -h if theta[j] + h > self.parameters[j].upper else h

    def _forward(self, base: Evaluation, j: int) -> float:
        h = self._step(base.theta, j, FORWARD_STEP)
        probe = base.theta.copy()
        probe[j] += h
        other = self.evaluate(probe)
        if not other.ok:
            return 0.0
        return (other.infeasibility - base.infeasibility) / h

    def _adjoint(self, base: Evaluation) -> np.ndarray:
        from shapegen.statics import assemble, find_interfaces

        analysis = base.analysis
        problem = analysis.problem
        if problem is None or analysis.multipliers is None:
            return np.array([self._forward(base, j) for j in range(len(self.parameters))])
        weight, length = problem.weight, problem.length
        x = (analysis.forces / weight).T.ravel()
        lam = analysis.multipliers.reshape(-1, 6).copy() / weight
        lam[:, 3:] *= length
        lam = lam.ravel()
        base_residual = problem.residual(x)
        options = {k: v for k, v in self.analysis_options.items() if k in ("friction", "pyramid")}
        kern = float(self.analysis_options.get("kern", 1.0))
        grad = np.zeros(len(self.parameters))
        for j in range(len(self.parameters)):
            h = self._step(base.theta, j, ADJOINT_STEP)
            probe = base.theta.copy()
            probe[j] += h
            try:
                model = self.build(probe)
                moved = assemble(model, find_interfaces(model), kern=kern, **options)
            except ShapegenError:
                grad[j] = self._forward(base, j)
                continue
            order = _match_vertices(problem, moved)
            if order is None or moved.equality.shape != problem.equality.shape:
                grad[j] = self._forward(base, j)  # the contacts changed: no adjoint here
                continue
            m = problem.n_vertices
            x_moved = x.reshape(4, m)[:, order].ravel()
            change = moved.residual(x_moved)[...] - base_residual
            grad[j] = float(lam @ change) / h
        return grad


def _match_vertices(problem, moved) -> np.ndarray | None:
    """For each vertex of ``moved``, the vertex of ``problem`` it continues (same interface,
    nearest position), or None when the contact topology differs."""
    if moved.n_vertices != problem.n_vertices or moved.n_free != problem.n_free:
        return None
    if not np.array_equal(moved.vertex_interface, problem.vertex_interface):
        return None
    pairs_old = [(i.first, i.second) for i in problem.interfaces]
    pairs_new = [(i.first, i.second) for i in moved.interfaces]
    if pairs_old != pairs_new:
        return None
    if problem.n_vertices == 0:
        return np.zeros(0, int)
    # Neighbouring joints share corners (four course joints meet at a block's corner), so match
    # each vertex among its own interface's vertices only: a fourth coordinate, the interface
    # number times a length far beyond the model, keeps interfaces apart in the search.
    points_old, points_new = problem.vertex_points, moved.vertex_points
    apart = 1e3 * (1.0 + float(np.ptp(points_old)) + float(np.abs(points_old).max()))
    _, nearest = cKDTree(np.column_stack([points_old, problem.vertex_interface * apart])).query(
        np.column_stack([points_new, moved.vertex_interface * apart])
    )
    if not np.array_equal(problem.vertex_interface[nearest], moved.vertex_interface):
        return None
    if len(np.unique(nearest)) != len(nearest):
        return None
    return nearest


class _Stop(Exception):
    """Raised from inside the SQP to stop at the first feasible evaluation (the paper's rule)."""


def optimize(
    grammar,
    *,
    free: Sequence[str] | None = None,
    fix: Mapping[str, object] | None = None,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: tuple[float, float] | None = None,
    objective: str = "energy",
    gradient: str = "adjoint",
    max_iter: int = 50,
    multistart: int = 0,
    start: Mapping[str, float] | None = None,
    analysis_options: Mapping[str, object] | None = None,
    progress: Callable[[IterationRecord], None] | None = None,
    margin: float = 0.0,
) -> OptimizationResult:
    """Search the free parameters of ``grammar`` for a model that stands.

    Parameters
    ----------
    grammar
        A loaded :class:`~shapegen.engine.grammar_api.Grammar`.
    free, fix, attrs
        Which attrs to search (default: the ``@Free`` ones), attrs pinned to values, and other
        attr overrides.
    objective
        ``"energy"`` (the paper: minimise y, stop at the first feasible model) or ``"closest"``
        (the feasible design nearest to the starting values, distances scaled by the ranges).
    gradient
        ``"adjoint"`` (one QP per gradient, the default) or ``"forward"`` (n + 1 QPs).
    max_iter
        SQP iterations per start.
    multistart
        Extra random starts within the bounds (seeded by ``seed``) tried when a start ends
        without a feasible model (energy), or all compared (closest).
    start
        Starting values overriding the attrs' (a warm start).
    analysis_options
        Passed to :func:`~shapegen.statics.analyze` (friction, pyramid, kern, solver).
    progress
        Called after each iteration with an :class:`IterationRecord`.
    margin
        Geometric safety margin in [0, 1): the search judges designs with every joint shrunk
        about its centroid to ``1 - margin`` of its size (the kern), so the design found stands
        with that reserve; 0 (the default) stops on the feasibility boundary, as the paper does.
        A design that stands on shrunk joints stands on the full ones (they contain them); the
        returned analysis is at the caller's own ``kern``.
    """
    from shapegen.engine import bridge_rules  # a @Structure("cable") grammar: the cable model

    if bridge_rules.is_cable_structure(grammar):
        return bridge_rules.optimize_bridge(
            grammar, free=free, fix=fix, attrs=attrs, seed=seed, lot=lot
        )
    if objective not in OBJECTIVES:
        raise StaticsError(f"objective must be one of {', '.join(OBJECTIVES)}; got {objective!r}")
    if gradient not in GRADIENTS:
        raise StaticsError(f"gradient must be one of {', '.join(GRADIENTS)}; got {gradient!r}")
    if int(max_iter) < 1:
        raise StaticsError(f"max_iter must be at least 1; got {max_iter}")
    if int(multistart) < 0:
        raise StaticsError(f"multistart must be >= 0; got {multistart}")
    if not (isinstance(margin, (int, float)) and 0.0 <= margin < 1.0):
        raise StaticsError(f"margin must be a number in [0, 1); got {margin!r}")
    started = time.perf_counter()
    parameters, build_attrs = select_parameters(grammar, free, fix, attrs)
    user_options = dict(analysis_options or {})
    search_options = dict(user_options)
    if margin > 0:
        search_options["kern"] = float(user_options.get("kern", 1.0)) * (1.0 - margin)
    if start:
        parameters = [
            FreeParameter(p.name, min(max(float(start.get(p.name, p.initial)), p.lower), p.upper),
                          p.lower, p.upper)
            for p in parameters
        ]  # fmt: skip
    evaluator = Evaluator(
        grammar, parameters, build_attrs, seed=seed, lot=lot, analysis_options=search_options
    )
    search = _Search(evaluator, objective, gradient, int(max_iter), progress, started)
    theta0 = np.array([p.initial for p in parameters])
    first = evaluator.evaluate(theta0)
    if first.error and first.model is None:
        raise GeometryError(f"the starting design cannot be built: {first.error}")
    starts = [theta0]
    rng = np.random.default_rng(seed)
    starts += [rng.uniform(evaluator.lower, evaluator.upper) for _ in range(int(multistart))]

    if first.feasible:
        outcome = (first, True, "the starting design already stands")
    elif objective == "energy":
        outcome = search.energy(starts)
    else:
        outcome = search.closest(theta0, starts)
    best, converged, message = outcome
    final_analysis = best.analysis
    if margin > 0 and best.model is not None:
        from shapegen.statics import analyze

        final_analysis = analyze(best.model, **user_options)
        message += f" (with a {margin:.0%} geometric margin)"
    return OptimizationResult(
        converged=converged,
        feasible=best.feasible,
        iterations=search.iterations,
        qp_solves=evaluator.qp_solves,
        seconds=time.perf_counter() - started,
        initial_infeasibility=first.infeasibility,
        final_infeasibility=best.infeasibility,
        parameters={
            p.name: {"initial": p.initial, "final": float(v), "min": p.lower, "max": p.upper}
            for p, v in zip(parameters, best.theta, strict=True)
        },
        message=message,
        objective=objective,
        gradient=gradient,
        path=[evaluator.named(theta0), *search.path],
        model=best.model,
        analysis=final_analysis,
        margin=float(margin),
    )


class _Search:
    """The SQP runs of one :func:`optimize` call, in coordinates u = (theta - lower) / span."""

    def __init__(self, evaluator, objective, gradient, max_iter, progress, started):
        self.evaluator = evaluator
        self.objective = objective
        self.gradient_method = gradient
        self.max_iter = max_iter
        self.progress = progress
        self.started = started
        self.iterations = 0
        self.path: list[dict[str, float]] = []
        self.lower = evaluator.lower
        self.span = evaluator.upper - evaluator.lower
        self.best: Evaluation | None = None  # best evaluation seen, by the search's own measure

    def theta(self, u: np.ndarray) -> np.ndarray:
        return self.lower + np.clip(u, 0.0, 1.0) * self.span

    def u(self, theta: np.ndarray) -> np.ndarray:
        return (theta - self.lower) / self.span

    def _record(self, u: np.ndarray) -> None:
        self.iterations += 1
        evaluation = self.evaluator.evaluate(self.theta(u))
        named = self.evaluator.named(evaluation.theta)
        self.path.append(named)
        if self.progress is not None:
            self.progress(
                IterationRecord(
                    self.iterations,
                    evaluation.infeasibility,
                    evaluation.feasible,
                    named,
                    self.evaluator.qp_solves,
                    time.perf_counter() - self.started,
                )
            )

    # ------------------------------------------------------------------ energy (the paper)
    def energy(self, starts: list[np.ndarray]) -> tuple[Evaluation, bool, str]:
        best = None
        converged = False
        message = ""
        for theta in starts:
            evaluation, converged, message = self._energy_from(theta)
            if best is None or evaluation.infeasibility < best.infeasibility or evaluation.feasible:
                best = evaluation
            if evaluation.feasible:
                break
        return best, converged, message

    def _energy_from(self, theta0: np.ndarray) -> tuple[Evaluation, bool, str]:
        evaluator = self.evaluator
        # The SQP minimises sqrt(y / W^2): the same minimisers as y, but y vanishes
        # quadratically at the feasible boundary, where SQP would creep towards the boundary
        # without ever crossing it; its square root keeps a slope there and steps across.
        first = evaluator.evaluate(theta0)
        scale = math.sqrt(first.infeasibility) if first.ok and first.infeasibility > 0 else 1.0
        if first.ok and first.infeasibility > 0:
            # SLSQP's first step is the plain gradient (identity Hessian): scale the objective
            # so that step moves FIRST_STEP of the ranges, not straight into a corner.
            slope0 = self._root_slope(first) * self.span
            scale = max(float(np.abs(slope0).max()) / FIRST_STEP, scale)
        state = {"last_good": self.u(theta0), "worst": 1.0, "best": first}

        def value(u):
            evaluation = evaluator.evaluate(self.theta(u))
            if evaluation.feasible:
                state["best"] = evaluation
                raise _Stop
            if not evaluation.ok:
                return 10.0 * state["worst"]  # a failed build: a wall the SQP backs away from
            scaled = math.sqrt(max(evaluation.infeasibility, 0.0)) / scale
            state["worst"] = max(state["worst"], scaled)
            state["last_good"] = np.array(u, float)
            if evaluation.infeasibility < state["best"].infeasibility:
                state["best"] = evaluation
            return scaled

        def slope(u):
            evaluation = evaluator.evaluate(self.theta(u))
            if not evaluation.ok:
                return 20.0 * state["worst"] * (np.asarray(u) - state["last_good"])
            return self._root_slope(evaluation) * self.span / scale

        try:
            result = minimize(
                value,
                self.u(theta0),
                jac=slope,
                method="SLSQP",
                bounds=[(0.0, 1.0)] * len(theta0),
                callback=self._record,
                options={"maxiter": self.max_iter, "ftol": 1e-12},
            )
        except _Stop:
            self._record(self.u(state["best"].theta))
            return state["best"], True, "a feasible design was found"
        converged = bool(result.success)
        if converged:
            message = "a local minimum of the infeasibility was reached without a feasible design"
        else:
            message = f"stopped: {result.message}"
        return state["best"], converged, message

    def _root_slope(self, evaluation: Evaluation) -> np.ndarray:
        """``d sqrt(y / W^2) / d theta`` (zero where y is zero)."""
        y = evaluation.infeasibility
        if not evaluation.ok or y <= 0:
            return np.zeros(len(self.span))
        return self.evaluator.gradient(evaluation.theta, self.gradient_method) / (2 * math.sqrt(y))

    # ------------------------------------------------------------------ closest (ours)
    def closest(self, theta0: np.ndarray, starts: list[np.ndarray]) -> tuple[Evaluation, bool, str]:
        evaluator = self.evaluator
        u0 = self.u(theta0)
        feasible_points: list[Evaluation] = []
        # 1. find any feasible design (the energy search), from each start
        for theta in starts:
            evaluation, _, _ = self._energy_from(theta)
            if evaluation.feasible:
                feasible_points.append(evaluation)
        if not feasible_points:
            best = min((evaluator.evaluate(t) for t in starts), key=lambda e: e.infeasibility)
            return best, False, "no feasible design was found"
        # 2. from the nearest feasible design, minimise the distance subject to feasibility
        first = evaluator.evaluate(theta0)
        scale = math.sqrt(first.infeasibility) if first.ok and first.infeasibility > 0 else 1.0

        def distance(u):
            return float(np.sum((np.asarray(u) - u0) ** 2))

        def distance_slope(u):
            return 2.0 * (np.asarray(u) - u0)

        def standing(u):  # >= 0 when feasible
            evaluation = evaluator.evaluate(self.theta(u))
            if evaluation.feasible:
                feasible_points.append(evaluation)
            if not evaluation.ok:
                return -1.0
            return -math.sqrt(max(evaluation.infeasibility, 0.0)) / scale

        def standing_slope(u):
            evaluation = evaluator.evaluate(self.theta(u))
            return -self._root_slope(evaluation) * self.span / scale

        # 2. the boundary on the segment from the start to the nearest feasible design
        nearest = min(feasible_points, key=lambda e: distance(self.u(e.theta)))
        nearest = self._bisect_segment(theta0, nearest)
        feasible_points.append(nearest)
        # 3. a short SQP polish off that segment. The constraint is flat (zero) inside the
        # feasible region, so SQP only slides along the boundary; it is not trusted for the end
        # point, which is the best feasible design seen, refined on its own segment.
        result = minimize(
            distance,
            self.u(nearest.theta),
            jac=distance_slope,
            method="SLSQP",
            bounds=[(0.0, 1.0)] * len(u0),
            constraints=[{"type": "ineq", "fun": standing, "jac": standing_slope}],
            callback=self._record,
            options={"maxiter": min(self.max_iter, 10), "ftol": 1e-8},
        )
        standing(result.x)
        best = min(feasible_points, key=lambda e: distance(self.u(e.theta)))
        best = self._bisect_segment(theta0, best)
        return best, True, "the nearest feasible design was found"

    def _bisect_segment(self, theta0: np.ndarray, feasible: Evaluation, steps: int = 12):
        low, high = 0.0, 1.0  # fraction of the way from theta0 to the feasible design
        best = feasible
        for _ in range(steps):
            middle = 0.5 * (low + high)
            evaluation = self.evaluator.evaluate(theta0 + middle * (feasible.theta - theta0))
            if evaluation.feasible:
                high, best = middle, evaluation
            else:
                low = middle
        return best
