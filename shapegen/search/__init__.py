"""Parameter search over a grammar's ``@Free`` attrs, for any structure.

>>> import shapegen
>>> from shapegen.search import optimize
>>> result = optimize(shapegen.load_grammar("arch_columns.grammar"))  # doctest: +SKIP
>>> result.feasible, result.values                                     # doctest: +SKIP
"""

from shapegen.search.evaluator import Evaluation, Evaluator
from shapegen.search.landscape import Landscape, energy_landscape
from shapegen.search.optimize import GRADIENTS, OBJECTIVES, optimize
from shapegen.search.parameters import FreeParameter, select_parameters
from shapegen.search.result import IterationRecord, OptimizationResult
from shapegen.search.session import DesignSession

__all__ = [
    "DesignSession",
    "Evaluation",
    "Evaluator",
    "FreeParameter",
    "GRADIENTS",
    "IterationRecord",
    "Landscape",
    "OBJECTIVES",
    "OptimizationResult",
    "energy_landscape",
    "optimize",
    "select_parameters",
]
