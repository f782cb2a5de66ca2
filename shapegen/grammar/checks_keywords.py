"""Load-time checks of the names CityEngine reads as keywords where they are written: an
operation's selector and mode words (``alignScopeToAxes(y)``, ``comp(f) { world.up : A }``), a
builtin's (``inside(inter)``), comp's kinds and selectors: :class:`KeywordNames`.

The checker of :mod:`shapegen.grammar.checks` asks :meth:`KeywordNames.words_at` before it
reports a name that nothing defines.
"""

from __future__ import annotations

from shapegen.errors import did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.checks_definitions import DefinitionTable
from shapegen.grammar.names import (
    COMP_KINDS,
    COMP_SELECTORS,
    FUNCTION_KEYWORDS,
    GEOMETRY_KEYWORDS,
    OPERATION_KEYWORDS,
)
from shapegen.grammar.problems import Findings

__all__ = ["KeywordNames"]


class KeywordNames:
    """The names of ``grammar`` that are CityEngine keywords where they stand (an operation's
    arguments and branch keys, a builtin's); building it reports unknown comp words."""

    def __init__(self, grammar: ast.RuleFile, definitions: DefinitionTable, findings: Findings):
        self._definitions = definitions
        self._findings = findings
        # ids of the names that may be keywords, and the words each may be
        self._words: dict[int, frozenset[str]] = {}
        # a parameter or local variable may stand as a comp selector (op_comp: a bool
        # selector), R(q) --> comp(f) { q : A }
        self._local_names = {
            name
            for definition in grammar.definitions
            for name in (
                *(p.name for p in getattr(definition, "params", ())),
                *(v.name for v in definition.local_variables),
            )
        }
        for node in ast.walk(grammar):
            if isinstance(node, ast.Operation):
                for argument in node.arguments:
                    self._mark(argument.value, OPERATION_KEYWORDS)
                for branch in node.branches:
                    self._mark(branch.key, OPERATION_KEYWORDS)
                if node.name == "comp":
                    self._comp_words(node)
            elif isinstance(node, ast.Insert):
                for option in node.options:  # i(asset, yUp, keepSizeAlignPosition)
                    self._mark(option, OPERATION_KEYWORDS)
            elif isinstance(node, ast.ComponentValues):
                for argument in node.arguments:
                    self._mark(argument, OPERATION_KEYWORDS)
                for branch in node.branches:
                    self._mark(branch.selector, OPERATION_KEYWORDS)
            elif isinstance(node, ast.Call) and node.name in FUNCTION_KEYWORDS:
                for argument in node.args:
                    self._mark(argument, FUNCTION_KEYWORDS[node.name])
            elif isinstance(node, ast.ShapeAttribute) and node.obj == "geometry":
                for argument in node.args:
                    self._mark(argument, GEOMETRY_KEYWORDS)

    def words_at(self, node) -> frozenset[str]:
        """The keywords ``node`` (a name or shape attribute) may be where it stands; empty for
        a name that can only be a name."""
        return self._words.get(id(node), frozenset())

    def _comp_words(self, node: ast.Operation) -> None:
        """comp's kind and selectors: an unknown one is named as such (not as an undefined
        name), with the valid ones."""
        kind = node.arguments[0].value if node.arguments else None
        if isinstance(kind, ast.Name) and kind.name not in COMP_KINDS:
            self._findings.report(
                kind.location,
                f"unknown component type '{kind.name}' in comp(); valid: {', '.join(COMP_KINDS)}",
            )
            self._words[id(kind)] = frozenset({kind.name})
        for branch in node.branches:
            key = branch.key
            if (
                isinstance(key, ast.Name)
                and key.name not in COMP_SELECTORS
                and key.name not in self._definitions.values
                and key.name not in self._local_names
            ):
                self._findings.report(
                    key.location,
                    f"unknown comp selector '{key.name}'; valid: {', '.join(COMP_SELECTORS[:6])}"
                    + "..."
                    + did_you_mean(key.name, COMP_SELECTORS),
                )
                self._words[id(key)] = frozenset({key.name})

    def _mark(self, expression, words: frozenset[str]) -> None:
        for node in ast.walk(expression):
            if isinstance(node, ast.Name | ast.ShapeAttribute):
                self._words[id(node)] = words
