"""Parameter search over a grammar's ``@Free`` attrs, for any structure.

>>> import shapegen
>>> from shapegen.search import optimize
>>> result = optimize(shapegen.load_grammar("arch_columns.grammar"))  # doctest: +SKIP
>>> result.feasible, result.values                                     # doctest: +SKIP

A search asks for a design that stands with a reserve: ``margin`` defaults to
:data:`DEFAULT_MARGIN` (0.1); ``margin=0`` stops on the feasibility boundary, as the papers do.
The names below load on first use, so reading :data:`DEFAULT_MARGIN` costs nothing.
"""

from shapegen.lazy_names import lazy_names
from shapegen.search.defaults import DEFAULT_MARGIN

__all__ = [
    "DEFAULT_MARGIN",
    "DesignSession",
    "Evaluation",
    "Evaluator",
    "FreeParameter",
    "GRADIENTS",
    "IterationRecord",
    "Landscape",
    "OBJECTIVES",
    "OptimizationResult",
    "RangeWarning",
    "SearchOptions",
    "energy_landscape",
    "optimize",
    "select_parameters",
]

_HOMES = {
    "DesignSession": "session",
    "Evaluation": "evaluator",
    "Evaluator": "evaluator",
    "FreeParameter": "parameters",
    "GRADIENTS": "search_options",
    "IterationRecord": "result",
    "Landscape": "landscape",
    "OBJECTIVES": "search_options",
    "OptimizationResult": "result",
    "RangeWarning": "parameters",
    "SearchOptions": "search_options",
    "energy_landscape": "landscape",
    "optimize": "optimizer",
    "select_parameters": "parameters",
}


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)
