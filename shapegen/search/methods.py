"""The search methods, in coordinates ``u = (theta - lower) / span`` in the unit box.

- With a gradient (the seed paper, Whiting et al. 2009): SLSQP on ``sqrt(measure)``. The measure
  vanishes quadratically at the boundary of the standing region (y is a sum of squared
  tensions), where SQP would creep towards the boundary without crossing it; its square root
  keeps a slope there and steps across.
- Without one (Patow 2012): Powell's method on ``sqrt(measure)``. For the cable structure that
  is affine in the cable diameter above the limit, so the search follows the paper's search on
  the diameter itself.

Both stop at the first design that stands (the papers' rule). ``closest`` (ours) then looks for
the standing design nearest to the start: the segment from the start to the nearest standing
design is bisected, and a short constrained polish (SLSQP with a gradient, COBYLA without) slides
along the boundary.
"""

from __future__ import annotations

__all__ = [
    "Search",
    "FIRST_STEP",
    "MAX_FIRST_STEP",
    "POWELL_XTOL",
    "POWELL_FTOL",
    "SLSQP_FTOL",
    "UNJUDGED_WALL",
]

import math
import time

import numpy as np
from scipy.optimize import minimize

from shapegen.search.evaluator import Evaluation, Evaluator
from shapegen.search.result import IterationRecord

FIRST_STEP = 0.1
"""Shortest first step of the SQP, as a fraction of the parameter ranges (its largest move)."""

MAX_FIRST_STEP = 0.5
"""Longest first step of the SQP, as a fraction of the parameter ranges (its largest move)."""

POWELL_XTOL = 1e-4
"""Powell's tolerance on the parameters, as a fraction of their ranges."""

POWELL_FTOL = 1e-6
"""Powell's tolerance on the relative change of ``sqrt(measure)``."""

SLSQP_FTOL = 1e-12
"""SLSQP's tolerance on the change of the scaled ``sqrt(measure)``: tight, because the descent
is meant to stop at the first design that stands, not at a small measure."""

UNJUDGED_WALL = 10.0
"""A design that cannot be judged reads ``UNJUDGED_WALL`` times the worst scaled
``sqrt(measure)`` seen, times ``1 + its distance`` (in the unit box) from the last judged design;
its slope is that of ``UNJUDGED_WALL * worst * |u - last|^2``, pointing back."""

POLISH_ITERATIONS = 10
"""Iterations of the closest-design polish (SLSQP; COBYLA, which takes no gradient, gets ten
times as many function calls), at most ``max_iter``."""

POLISH_FTOL = 1e-8
"""SLSQP's tolerance on the squared distance (unit box) in the closest-design polish."""

POLISH_RHOBEG = 0.05
"""COBYLA's first step in the closest-design polish, as a fraction of the parameter ranges:
the polish starts on the boundary and only slides along it."""


class _Stop(Exception):
    """Raised from inside a method to stop at the first design that stands."""


class Search:
    """The runs of one :func:`~shapegen.search.optimize` call.

    Parameters
    ----------
    evaluator
        Judges designs.
    gradient
        ``"adjoint"``, ``"forward"`` (SLSQP) or ``"none"`` (Powell, COBYLA).
    max_iter
        Iterations per start.
    progress
        Called with an :class:`IterationRecord` after each iteration.
    """

    def __init__(self, evaluator: Evaluator, gradient: str, max_iter: int, progress, started):
        self.evaluator = evaluator
        self.gradient_method = gradient
        self.max_iter = max_iter
        self.progress = progress
        self.started = started
        self.iterations = 0
        self.path: list[dict[str, float]] = []
        self.lower = evaluator.lower
        self.span = evaluator.upper - evaluator.lower

    @property
    def method(self) -> str:
        return "Powell" if self.gradient_method == "none" else "SLSQP"

    def theta(self, u: np.ndarray) -> np.ndarray:
        return self.lower + np.clip(u, 0.0, 1.0) * self.span

    def u(self, theta: np.ndarray) -> np.ndarray:
        return (theta - self.lower) / self.span

    def _record(self, u: np.ndarray) -> None:
        self.iterations += 1
        evaluation = self.evaluator.evaluate(self.theta(np.asarray(u, float)))
        named = self.evaluator.named(evaluation.theta)
        self.path.append(named)
        if self.progress is not None:
            self.progress(
                IterationRecord(
                    self.iterations,
                    evaluation.infeasibility,
                    evaluation.feasible,
                    named,
                    self.evaluator.evaluations,
                    time.perf_counter() - self.started,
                )
            )

    # ------------------------------------------------------------------ energy (the papers)
    def energy(self, starts: list[np.ndarray]) -> tuple[Evaluation, bool, str]:
        """From each start in turn until one finds a design that stands: the best design seen."""
        best = None
        converged = False
        message = ""
        for theta in starts:
            evaluation, converged, message = self._descend(theta)
            if best is None or evaluation.infeasibility < best.infeasibility or evaluation.feasible:
                best = evaluation
            if evaluation.feasible:
                break
        return best, converged, message

    def _descend(self, theta0: np.ndarray) -> tuple[Evaluation, bool, str]:
        first = self.evaluator.evaluate(theta0)
        state = {"best": first, "worst": 1.0, "last_good": self.u(theta0)}
        scale = self._scale(first)

        def value(u):
            evaluation = self.evaluator.evaluate(self.theta(u))
            if evaluation.feasible:
                state["best"] = evaluation
                raise _Stop
            if not evaluation.ok:
                # A design that cannot be judged: a wall the method backs away from, rising with
                # the distance from the last judged design, so a line search that meets a whole
                # region of such designs still slopes back out of it (a flat wall would read as a
                # minimum to Powell's method).
                away = float(np.linalg.norm(np.asarray(u, float) - state["last_good"]))
                return UNJUDGED_WALL * state["worst"] * (1.0 + away)
            scaled = math.sqrt(max(evaluation.infeasibility, 0.0)) / scale
            state["worst"] = max(state["worst"], scaled)
            state["last_good"] = np.array(u, float)
            if evaluation.infeasibility < state["best"].infeasibility:
                state["best"] = evaluation
            return scaled

        def slope(u):
            evaluation = self.evaluator.evaluate(self.theta(u))
            if not evaluation.ok:
                return 2.0 * UNJUDGED_WALL * state["worst"] * (np.asarray(u) - state["last_good"])
            return self._root_slope(evaluation) * self.span / scale

        bounds = [(0.0, 1.0)] * len(theta0)
        try:
            if self.gradient_method == "none":
                result = minimize(
                    value,
                    self.u(theta0),
                    method="Powell",
                    bounds=bounds,
                    callback=self._record,
                    options={"maxiter": self.max_iter, "xtol": POWELL_XTOL, "ftol": POWELL_FTOL},
                )
            else:
                result = minimize(
                    value,
                    self.u(theta0),
                    jac=slope,
                    method="SLSQP",
                    bounds=bounds,
                    callback=self._record,
                    options={"maxiter": self.max_iter, "ftol": SLSQP_FTOL},
                )
        except _Stop:
            self._record(self.u(state["best"].theta))
            return state["best"], True, "a design that stands was found"
        converged = bool(result.success)
        if converged:
            message = "a local minimum was reached without a design that stands"
        else:
            message = f"stopped: {result.message}"
        return state["best"], converged, message

    def _scale(self, first: Evaluation) -> float:
        """Divides sqrt(measure) so that SLSQP's first step (the plain gradient: SLSQP starts
        with the identity Hessian) goes to where the linearised sqrt(measure) vanishes, moving
        no parameter less than FIRST_STEP nor more than MAX_FIRST_STEP of its range (not
        straight into a corner). sqrt(measure) bends upwards towards the standing region, so
        this step still falls short; a fixed FIRST_STEP took one or two more iterations, each
        an analysis and a gradient."""
        if not (first.ok and first.infeasibility > 0):
            return 1.0
        root = math.sqrt(first.infeasibility)
        scale = root
        if self.gradient_method != "none":
            slope0 = self._root_slope(first) * self.span
            largest = float(np.abs(slope0).max())
            if largest > 0:
                to_zero = root * largest / float(slope0 @ slope0)  # largest move of that step
                step = min(max(to_zero, FIRST_STEP), MAX_FIRST_STEP)
                scale = max(largest / step, scale)
        return scale

    def _root_slope(self, evaluation: Evaluation) -> np.ndarray:
        """``d sqrt(measure) / d theta`` (zero where the measure is zero)."""
        y = evaluation.infeasibility
        if not evaluation.ok or y <= 0:
            return np.zeros(len(self.span))
        return self.evaluator.gradient(evaluation.theta, self.gradient_method) / (2 * math.sqrt(y))

    # ------------------------------------------------------------------ closest (ours)
    def closest(self, theta0: np.ndarray, starts: list[np.ndarray]) -> tuple[Evaluation, bool, str]:
        """The standing design nearest to ``theta0`` (distances scaled by the ranges)."""
        evaluator = self.evaluator
        u0 = self.u(theta0)
        standing_points: list[Evaluation] = []
        # 1. any design that stands, from each start
        for theta in starts:
            evaluation, _, _ = self._descend(theta)
            if evaluation.feasible:
                standing_points.append(evaluation)
        if not standing_points:
            best = min((evaluator.evaluate(t) for t in starts), key=lambda e: e.infeasibility)
            return best, False, "no design that stands was found"
        first = evaluator.evaluate(theta0)
        scale = math.sqrt(first.infeasibility) if first.ok and first.infeasibility > 0 else 1.0

        def distance(u):
            return float(np.sum((np.asarray(u) - u0) ** 2))

        def standing(u):  # >= 0 when the design stands
            evaluation = evaluator.evaluate(self.theta(u))
            if evaluation.feasible:
                standing_points.append(evaluation)
            if not evaluation.ok:
                return -1.0
            return -math.sqrt(max(evaluation.infeasibility, 0.0)) / scale

        # 2. the boundary on the segment from the start to the nearest standing design
        nearest = min(standing_points, key=lambda e: distance(self.u(e.theta)))
        nearest = self._bisect_segment(theta0, nearest)
        standing_points.append(nearest)
        # 3. a short polish off that segment. The constraint is flat (zero) inside the standing
        # region, so the polish only slides along the boundary; it is not trusted for the end
        # point, which is the best standing design seen, refined on its own segment.
        bounds = [(0.0, 1.0)] * len(u0)
        if self.gradient_method == "none":
            result = minimize(
                distance,
                self.u(nearest.theta),
                method="COBYLA",
                bounds=bounds,
                constraints=[{"type": "ineq", "fun": standing}],
                callback=self._record,
                options={
                    "maxiter": 10 * min(self.max_iter, POLISH_ITERATIONS),
                    "rhobeg": POLISH_RHOBEG,
                },
            )
        else:

            def standing_slope(u):
                evaluation = evaluator.evaluate(self.theta(u))
                return -self._root_slope(evaluation) * self.span / scale

            result = minimize(
                distance,
                self.u(nearest.theta),
                jac=lambda u: 2.0 * (np.asarray(u) - u0),
                method="SLSQP",
                bounds=bounds,
                constraints=[{"type": "ineq", "fun": standing, "jac": standing_slope}],
                callback=self._record,
                options={"maxiter": min(self.max_iter, POLISH_ITERATIONS), "ftol": POLISH_FTOL},
            )
        standing(result.x)
        best = min(standing_points, key=lambda e: distance(self.u(e.theta)))
        best = self._bisect_segment(theta0, best)
        return best, True, "the nearest design that stands was found"

    def _bisect_segment(self, theta0: np.ndarray, standing: Evaluation, steps: int = 12):
        low, high = 0.0, 1.0  # fraction of the way from theta0 to the standing design
        best = standing
        for _ in range(steps):
            middle = 0.5 * (low + high)
            evaluation = self.evaluator.evaluate(theta0 + middle * (standing.theta - theta0))
            if evaluation.feasible:
                high, best = middle, evaluation
            else:
                low = middle
        return best
