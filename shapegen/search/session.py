"""Interactive editing (the seed paper's Figure 13): change an attr, re-optimize, warm-started.

>>> session = DesignSession("barrel_vault.grammar")          # doctest: +SKIP
>>> session.set(span=7.5)                                    # doctest: +SKIP
>>> result = session.optimize()   # starts from the last solution  # doctest: +SKIP
"""

from __future__ import annotations

__all__ = ["DesignSession"]

from collections.abc import Callable

from shapegen.engine.grammar_api import Grammar, load_grammar
from shapegen.search.optimizer import optimize
from shapegen.search.result import IterationRecord, OptimizationResult
from shapegen.search.search_options import SearchOptions
from shapegen.structures import Structure, make_structure


class DesignSession:
    """A grammar with the designer's current attr values and the last optimized parameters.

    ``set(...)`` changes attrs the designer controls; ``optimize()`` re-runs the search of the
    free parameters starting from the previous solution, so small edits need few iterations.
    Any structure works: the grammar's own by default, or the ``structure`` given. The search
    runs with ``options`` (:class:`~shapegen.search.search_options.SearchOptions`), or with its
    fields given as keywords (``DesignSession(grammar, free=["span"], margin=0)``).
    """

    def __init__(
        self,
        grammar: Grammar | str,
        options: SearchOptions | None = None,
        *,
        seed: int = 0,
        structure: Structure | None = None,
        **choices: object,
    ):
        self.grammar = grammar if isinstance(grammar, Grammar) else load_grammar(grammar)
        self.options = (options or SearchOptions()).replace(**choices)
        self.seed = seed
        self.structure = structure or make_structure(self.grammar.structure)
        self.attrs: dict[str, object] = {}
        self.solution: dict[str, float] | None = None
        self.last: OptimizationResult | None = None

    def set(self, **attrs: object) -> None:
        """Change attrs (not the free parameters, which the search owns)."""
        self.attrs.update(attrs)

    def optimize(
        self,
        max_iter: int | None = None,
        progress: Callable[[IterationRecord], None] | None = None,
    ) -> OptimizationResult:
        """Re-optimize the free parameters, warm-started from the last solution (``max_iter``:
        this time's iterations, None: the options')."""
        options = self.options if max_iter is None else self.options.replace(max_iter=max_iter)
        result = optimize(
            self.grammar,
            options,
            attrs=self.attrs,
            seed=self.seed,
            start=self.solution,
            structure=self.structure,
            progress=progress,
        )
        self.solution = result.values
        self.last = result
        return result
