"""What a search reports: one record per iteration, and the outcome."""

from __future__ import annotations

__all__ = ["IterationRecord", "OptimizationResult"]

from dataclasses import dataclass, field

from shapegen.json_values import finite_or_none
from shapegen.model import Model
from shapegen.structures import Assessment


@dataclass(frozen=True)
class IterationRecord:
    """What the progress display shows after each iteration."""

    iteration: int
    infeasibility: float  # the structure's measure, 0 when the design stands
    feasible: bool
    parameters: dict[str, float]
    evaluations: int
    seconds: float


@dataclass
class OptimizationResult:
    """The outcome of :func:`~shapegen.search.optimize`.

    Attributes
    ----------
    converged
        True when the search stopped for a reason other than the iteration limit or a failure
        (a design that stands was found, or a local minimum was reached).
    feasible
        True when the design found stands (with the margin, if any).
    iterations, evaluations
        Iterations of the method; designs judged by the structure (for block statics, QP
        analyses).
    initial_infeasibility, final_infeasibility
        The structure's measure (zero exactly when it stands) at the start and at the end.
    parameters
        ``name -> {initial, final, min, max}`` for each free parameter.
    attrs
        Every attr override the final design is made of: the caller's attrs, the fixed ones and
        the final free values. Building with these gives ``model``.
    fixed
        The attrs held with ``fix``.
    structure, measure
        The structure's name and what its measure is (``"y/W²"``...).
    method, gradient, objective
        ``"SLSQP"`` or ``"Powell"``; ``"adjoint"``, ``"forward"`` or ``"none"``; ``"energy"`` or
        ``"closest"``.
    path
        The free values after each iteration (the first entry is the start).
    model, assessment
        The final design's model and its assessment without margin.
    margin
        The reserve the search demanded (0: stop on the boundary, as the paper does).
    """

    converged: bool
    feasible: bool
    iterations: int
    evaluations: int
    seconds: float
    initial_infeasibility: float
    final_infeasibility: float
    parameters: dict[str, dict[str, float]]
    attrs: dict[str, object]
    message: str
    objective: str
    gradient: str
    method: str
    structure: str
    measure: str
    fixed: dict[str, object] = field(default_factory=dict)
    path: list[dict[str, float]] = field(default_factory=list)
    model: Model | None = None
    assessment: Assessment | None = None
    margin: float = 0.0

    @property
    def seconds_per_iteration(self) -> float:
        return self.seconds / self.iterations if self.iterations else 0.0

    @property
    def values(self) -> dict[str, float]:
        """Final free parameter values, ``name -> value``."""
        return {name: p["final"] for name, p in self.parameters.items()}

    @property
    def analysis(self):
        """The block :class:`~shapegen.statics.analysis.Analysis` of the final design (None for
        another structure)."""
        return self.assessment.block_analysis if self.assessment else None

    def to_report(self) -> dict:
        """The ``optimization`` object of a report (plain JSON types)."""
        return {
            "structure": self.structure,
            "measure": self.measure,
            "converged": self.converged,
            "feasible": self.feasible,
            "iterations": self.iterations,
            "evaluations": self.evaluations,
            "seconds": self.seconds,
            "seconds_per_iteration": self.seconds_per_iteration,
            "initial_infeasibility": finite_or_none(self.initial_infeasibility),
            "final_infeasibility": finite_or_none(self.final_infeasibility),
            "objective": self.objective,
            "method": self.method,
            "gradient": self.gradient,
            "message": self.message,
            "margin": self.margin,
            "parameters": self.parameters,
            "fixed": dict(self.fixed),
        }
