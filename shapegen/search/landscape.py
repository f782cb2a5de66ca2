"""A structure's measure over a grid of two free parameters (the seed paper's Figures 3 and 8)."""

from __future__ import annotations

__all__ = ["Landscape", "energy_landscape"]

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from shapegen.errors import OptionError
from shapegen.model.lot import Lot
from shapegen.search.evaluator import Evaluator
from shapegen.search.parameters import select_parameters
from shapegen.structures import Structure, make_structure


@dataclass
class Landscape:
    """``infeasibility[i, j]``, the structure's measure (``measure``: y/W² for block statics) at
    ``(first[j], second[i])``; nan where a design could not be judged."""

    first_name: str
    second_name: str
    first: np.ndarray
    second: np.ndarray
    infeasibility: np.ndarray
    feasible: np.ndarray
    evaluations: int
    measure: str = "y/W²"


def energy_landscape(
    grammar,
    first: str,
    second: str,
    *,
    grid: int = 15,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: Lot | None = None,
    structure: Structure | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Landscape:
    """Evaluate the structure's measure on a ``grid x grid`` lattice over the ranges of two attrs.

    The other attrs keep their values (``attrs`` overrides). ``structure`` judges the designs
    (default: the grammar's own). ``progress(done, total)`` is called after each evaluation.
    """
    if first == second:
        raise OptionError("the landscape needs two different parameters")
    if not 2 <= int(grid) <= 200:
        raise OptionError(f"grid must be between 2 and 200 points per axis; got {grid}")
    if structure is None:
        structure = make_structure(grammar.structure)
    parameters, build_attrs = select_parameters(grammar, free=[first, second], attrs=attrs)
    evaluator = Evaluator(grammar, structure, parameters, build_attrs, seed=seed, lot=lot)
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
    return Landscape(
        first, second, xs, ys, values, feasible, evaluator.evaluations, structure.measure_name
    )
