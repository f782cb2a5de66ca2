"""``optimize(grammar)``: tune a grammar's free attrs until the design stands, for any structure.

The structure (block statics by default, the cable model for ``@Structure("cable")``, a
plug-in...) judges each design; the search moves the free parameters within their ``@Range``
to bring its measure to zero: with a gradient when the structure gives one, derivative-free
otherwise (:mod:`shapegen.search.methods`). Every option is honoured for every structure or
refused with one line.
"""

from __future__ import annotations

__all__ = ["optimize"]

import time
from collections.abc import Callable, Mapping

import numpy as np

from shapegen.errors import GeometryError, OptionError
from shapegen.model.lot import Lot
from shapegen.search.evaluator import Evaluator
from shapegen.search.methods import Search
from shapegen.search.parameters import FreeParameter, select_parameters
from shapegen.search.result import IterationRecord, OptimizationResult
from shapegen.search.search_options import SearchOptions
from shapegen.structures import Structure, make_structure


def optimize(
    grammar,
    options: SearchOptions | None = None,
    *,
    structure: Structure | None = None,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: Lot | None = None,
    start: Mapping[str, float] | None = None,
    progress: Callable[[IterationRecord], None] | None = None,
    build: bool = True,
    **choices: object,
) -> OptimizationResult:
    """Search the free parameters of ``grammar`` for a design that stands.

    Parameters
    ----------
    grammar
        A loaded :class:`~shapegen.engine.grammar_api.Grammar`.
    options
        How to search (:class:`~shapegen.search.search_options.SearchOptions`: free and fixed attrs,
        objective, gradient, iterations, margin, multistart); ``choices`` are its fields given
        as keywords (``optimize(grammar, max_iter=20)``), over ``options`` when both are given.
        The designs are judged with the structure's margin (block statics: every joint shrunk
        about its centroid to ``1 - margin`` of its size; cables: the diameter limit lowered to
        ``1 - margin`` of itself), so the design found stands with that reserve; the returned
        assessment is without margin, and the result records the margin used. Multistart's
        extra starts are tried when a start ends without a design that stands (energy), or all
        compared (closest). ``gradient`` None takes the structure's best: adjoint when it has
        one, else none (Powell's method).
    structure
        What judges the designs; by default the grammar's own (``@Structure``, else block
        statics with default options), from :func:`~shapegen.structures.make_structure`.
    attrs
        Other attr overrides. Every design, the final one included, is built with ``attrs``
        and the options' ``fix``; the result's ``attrs`` holds them all.
    start
        Starting values overriding the attrs' (a warm start).
    progress
        Called after each iteration with an :class:`IterationRecord`.
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
    options = options or SearchOptions()
    if choices:
        options = options.replace(**choices)
    if structure is None:
        structure = make_structure(grammar.structure)
    gradient = _gradient(structure, options.gradient)
    objective, margin, fix = options.objective, options.margin, options.fix
    started = time.perf_counter()
    parameters, build_attrs = select_parameters(grammar, options.free, fix, attrs)
    if start:
        parameters = [
            FreeParameter(p.name, min(max(float(start.get(p.name, p.initial)), p.lower), p.upper),
                          p.lower, p.upper)
            for p in parameters
        ]  # fmt: skip
    evaluator = Evaluator(
        grammar, structure, parameters, build_attrs, seed=seed, lot=lot, margin=margin
    )
    search = Search(evaluator, gradient, options.max_iter, progress, started)
    theta0 = np.array([p.initial for p in parameters])
    first = evaluator.evaluate(theta0)
    if first.error and first.assessment is None:
        raise GeometryError(f"the starting design cannot be judged: {first.error}")
    starts = [theta0]
    rng = np.random.default_rng(seed)
    starts += [rng.uniform(evaluator.lower, evaluator.upper) for _ in range(options.multistart)]

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


def _gradient(structure: Structure, gradient: str | None) -> str:
    """The gradient method to use: None takes the structure's best; 'adjoint' for a structure
    without a gradient is an OptionError."""
    if gradient is None:
        return "adjoint" if structure.has_gradient else "none"
    if gradient == "adjoint" and not structure.has_gradient:
        raise OptionError(
            f"gradient 'adjoint': the {structure.name} structure gives no gradient; use "
            "'forward' (finite differences) or 'none' (derivative-free)"
        )
    return gradient
