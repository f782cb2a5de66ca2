"""The infeasibility over a grid of two free parameters (the seed paper's Figures 3 and 8)."""

from __future__ import annotations

__all__ = ["Landscape", "energy_landscape"]

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from shapegen.engine.search import Evaluator, select_parameters
from shapegen.errors import StaticsError


@dataclass
class Landscape:
    """``infeasibility[i, j]`` (y / W^2) at ``(first[j], second[i])``; nan where a build failed."""

    first_name: str
    second_name: str
    first: np.ndarray
    second: np.ndarray
    infeasibility: np.ndarray
    feasible: np.ndarray
    qp_solves: int


def energy_landscape(
    grammar,
    first: str,
    second: str,
    *,
    grid: int = 15,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: tuple[float, float] | None = None,
    analysis_options: Mapping[str, object] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Landscape:
    """Evaluate ``y / W^2`` on a ``grid x grid`` lattice over the ranges of two attrs.

    The other attrs keep their values (``attrs`` overrides). ``progress(done, total)`` is
    called after each evaluation.
    """
    if first == second:
        raise StaticsError("the landscape needs two different parameters")
    if not 2 <= int(grid) <= 200:
        raise StaticsError(f"grid must be between 2 and 200 points per axis; got {grid}")
    parameters, build_attrs = select_parameters(grammar, free=[first, second], attrs=attrs)
    evaluator = Evaluator(
        grammar, parameters, build_attrs, seed=seed, lot=lot, analysis_options=analysis_options
    )
    xs = np.linspace(parameters[0].lower, parameters[0].upper, int(grid))
    ys = np.linspace(parameters[1].lower, parameters[1].upper, int(grid))
    values = np.full((len(ys), len(xs)), np.nan)
    feasible = np.zeros((len(ys), len(xs)), bool)
    total = values.size
    for i, y in enumerate(ys):
        for j, x in enumerate(xs):
            evaluation = evaluator.evaluate(np.array([x, y]))
            if evaluation.ok:
                values[i, j] = evaluation.infeasibility
                feasible[i, j] = evaluation.feasible
            if progress is not None:
                progress(i * len(xs) + j + 1, total)
    return Landscape(first, second, xs, ys, values, feasible, evaluator.qp_solves)
