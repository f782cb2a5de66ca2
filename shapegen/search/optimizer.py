"""``optimize(grammar)``: tune a grammar's free attrs until the design stands, for any structure.

The structure (block statics by default, the cable model for ``@Structure("cable")``, a
plug-in...) judges each design; the search moves the free parameters within their ``@Range``
to bring its measure to zero: with a gradient when the structure gives one, derivative-free
otherwise (:mod:`shapegen.search.methods`). Every option is honoured for every structure or
refused with one line.
"""

from __future__ import annotations

__all__ = ["optimize", "OBJECTIVES", "GRADIENTS"]

import time
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from shapegen.errors import GeometryError, OptionError
from shapegen.search.defaults import DEFAULT_MARGIN
from shapegen.search.evaluator import Evaluator
from shapegen.search.methods import Search
from shapegen.search.parameters import FreeParameter, select_parameters
from shapegen.search.result import IterationRecord, OptimizationResult
from shapegen.structures import Structure, make_structure

OBJECTIVES = ("energy", "closest")
GRADIENTS = ("adjoint", "forward", "none")


def optimize(
    grammar,
    *,
    structure: Structure | None = None,
    free: Sequence[str] | None = None,
    fix: Mapping[str, object] | None = None,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: tuple[float, float] | None = None,
    objective: str = "energy",
    gradient: str | None = None,
    max_iter: int = 50,
    multistart: int = 0,
    start: Mapping[str, float] | None = None,
    progress: Callable[[IterationRecord], None] | None = None,
    margin: float = DEFAULT_MARGIN,
    build: bool = True,
) -> OptimizationResult:
    """Search the free parameters of ``grammar`` for a design that stands.

    Parameters
    ----------
    grammar
        A loaded :class:`~shapegen.engine.grammar_api.Grammar`.
    structure
        What judges the designs; by default the grammar's own (``@Structure``, else block
        statics with default options), from :func:`~shapegen.structures.make_structure`.
    free, fix, attrs
        Which attrs to search (default: the ``@Free`` ones), attrs pinned to values, and other
        attr overrides. Every design, the final one included, is built with ``attrs`` and
        ``fix``; the result's ``attrs`` holds them all.
    objective
        ``"energy"`` (the papers: bring the measure to zero, stop at the first design that
        stands) or ``"closest"`` (the standing design nearest to the starting values, distances
        scaled by the ranges).
    gradient
        ``"adjoint"`` (the structure's own gradient: one QP per gradient for block statics),
        ``"forward"`` (finite differences, n + 1 evaluations), ``"none"`` (derivative-free:
        Powell's method), or None for the structure's best: adjoint when it has one, else none.
    max_iter
        Iterations per start.
    multistart
        Extra random starts within the bounds (seeded by ``seed``) tried when a start ends
        without a design that stands (energy), or all compared (closest).
    start
        Starting values overriding the attrs' (a warm start).
    progress
        Called after each iteration with an :class:`IterationRecord`.
    margin
        Reserve in [0, 1): the search judges designs with the structure's margin (block statics:
        every joint shrunk about its centroid to ``1 - margin`` of its size; cables: the
        diameter limit lowered to ``1 - margin`` of itself), so the design found stands with
        that reserve. Default :data:`~shapegen.search.DEFAULT_MARGIN` (0.1): a design that
        stands with a reserve; 0 stops on the feasibility boundary, as the papers do. The
        returned assessment is without margin; the result records the margin used.
    build
        When the structure judged without a model (the cable model), build the final design
        once at the end (False: ``model`` stays None).

    Raises
    ------
    OptionError
        For an option that means nothing here (``gradient="adjoint"`` for a structure without a
        gradient), or an invalid value.
    GrammarError, GeometryError
        For free or fixed attrs the grammar does not have, and a starting design that cannot be
        judged.
    """
    if structure is None:
        structure = make_structure(grammar.structure)
    gradient = _checked_options(structure, objective, gradient, max_iter, multistart, margin)
    started = time.perf_counter()
    parameters, build_attrs = select_parameters(grammar, free, fix, attrs)
    if start:
        parameters = [
            FreeParameter(p.name, min(max(float(start.get(p.name, p.initial)), p.lower), p.upper),
                          p.lower, p.upper)
            for p in parameters
        ]  # fmt: skip
    evaluator = Evaluator(
        grammar, structure, parameters, build_attrs, seed=seed, lot=lot, margin=float(margin)
    )
    search = Search(evaluator, gradient, int(max_iter), progress, started)
    theta0 = np.array([p.initial for p in parameters])
    first = evaluator.evaluate(theta0)
    if first.error and first.assessment is None:
        raise GeometryError(f"the starting design cannot be judged: {first.error}")
    starts = [theta0]
    rng = np.random.default_rng(seed)
    starts += [rng.uniform(evaluator.lower, evaluator.upper) for _ in range(int(multistart))]

    if first.feasible:
        best, converged, message = first, True, "the starting design already stands"
    elif objective == "energy":
        best, converged, message = search.energy(starts)
    else:
        best, converged, message = search.closest(theta0, starts)
    design = best.design
    assessment = best.assessment
    if margin > 0 and design is not None:
        assessment = structure.assess(design, margin=0.0)
        message += f" (with a {margin:.0%} margin)"
    elif design is not None:
        message += " (margin 0: no reserve)"
    model = design.model if design is not None and (build or design.built) else None
    return OptimizationResult(
        converged=converged,
        feasible=best.feasible,
        iterations=search.iterations,
        evaluations=evaluator.evaluations,
        seconds=time.perf_counter() - started,
        initial_infeasibility=first.infeasibility,
        final_infeasibility=best.infeasibility,
        parameters={
            p.name: {"initial": p.initial, "final": float(v), "min": p.lower, "max": p.upper}
            for p, v in zip(parameters, best.theta, strict=True)
        },
        attrs=evaluator.attrs_at(best.theta),
        message=message,
        objective=objective,
        gradient=gradient,
        method=search.method,
        structure=structure.name,
        measure=structure.measure_name,
        fixed=dict(fix or {}),
        path=[evaluator.named(theta0), *search.path],
        model=model,
        assessment=assessment,
        margin=float(margin),
    )


def _checked_options(structure, objective, gradient, max_iter, multistart, margin) -> str:
    """The gradient method to use; an invalid or meaningless option is an OptionError."""
    if objective not in OBJECTIVES:
        raise OptionError(f"objective must be one of {', '.join(OBJECTIVES)}; got {objective!r}")
    if gradient is None:
        gradient = "adjoint" if structure.has_gradient else "none"
    if gradient not in GRADIENTS:
        raise OptionError(f"gradient must be one of {', '.join(GRADIENTS)}; got {gradient!r}")
    if gradient == "adjoint" and not structure.has_gradient:
        raise OptionError(
            f"gradient 'adjoint': the {structure.name} structure gives no gradient; use "
            "'forward' (finite differences) or 'none' (derivative-free)"
        )
    if isinstance(max_iter, bool) or int(max_iter) < 1:
        raise OptionError(f"max_iter must be at least 1; got {max_iter}")
    if isinstance(multistart, bool) or int(multistart) < 0:
        raise OptionError(f"multistart must be 0 or more; got {multistart}")
    if isinstance(margin, bool) or not (isinstance(margin, int | float) and 0.0 <= margin < 1.0):
        raise OptionError(f"margin must be a number in [0, 1); got {margin!r}")
    return gradient
