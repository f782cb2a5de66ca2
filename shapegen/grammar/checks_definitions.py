"""The definitions of a rule file as the load-time checks look names up: :class:`DefinitionTable`.

Built once per check by :class:`~shapegen.grammar.checks.Checker`, which hands it to the
annotation checks and the keyword names; building it reports duplicate definitions, a function
named like a builtin and a rule named like an operation.
"""

from __future__ import annotations

from shapegen.grammar import ast
from shapegen.grammar.names import (
    BUILTIN_FUNCTIONS,
    CGA_OPERATIONS,
    LIBRARY_FUNCTIONS,
    OPERATIONS,
)
from shapegen.grammar.problems import Findings

__all__ = ["DefinitionTable"]


class DefinitionTable:
    """attrs, consts and functions by name (``values``, the first of each name), rules by name
    and number of parameters (``rules``: as in CGA, one name may be overloaded by arity), the
    arities of each rule name and of each function name."""

    def __init__(self, grammar: ast.RuleFile, findings: Findings):
        self.values: dict[str, ast.Attribute | ast.Constant | ast.Function] = {}
        self.rules: dict[tuple[str, int], ast.Rule] = {}
        self.arities: dict[str, list[int]] = {}
        self.function_arities: dict[str, set[int]] = {}
        self._findings = findings
        for definition in grammar.definitions:
            if isinstance(definition, ast.Rule):
                self._add_rule(definition)
            else:
                self._add_value(definition)

    def _add_rule(self, rule: ast.Rule) -> None:
        name = rule.name
        if (
            name in OPERATIONS or name in CGA_OPERATIONS or name == "NIL"
        ) and not self.operation_overload(rule):
            self._findings.report(
                rule.location, f"'{name}' is an operation; a rule cannot use its name"
            )
        key = (name, len(rule.params))
        previous = self.rules.get(key)
        if previous is not None:
            self._findings.report(
                rule.location, f"duplicate rule '{name}' (first defined at {previous.location})"
            )
        else:
            self.rules[key] = rule
            self.arities.setdefault(name, []).append(key[1])

    def _add_value(self, definition: ast.Attribute | ast.Constant | ast.Function) -> None:
        name = definition.name
        if (
            isinstance(definition, ast.Function)
            and name in BUILTIN_FUNCTIONS
            and name not in LIBRARY_FUNCTIONS
            and _overlaps(BUILTIN_FUNCTIONS[name], len(definition.params))
        ):  # CGA resolves a call by its signature: another arity is an overload
            self._findings.report(
                definition.location, f"'{name}' is a builtin function; choose another name"
            )
        previous = self.values.get(name)
        if isinstance(definition, ast.Function):
            arities = self.function_arities.setdefault(name, set())
            if isinstance(previous, ast.Function) and len(definition.params) not in arities:
                arities.add(len(definition.params))
                return  # an overload: CGA tells functions apart by their arity
            arities.add(len(definition.params))
        if previous is not None:
            self._findings.report(
                definition.location,
                f"duplicate definition of '{name}' (first defined at {previous.location})",
            )
        else:
            self.values[name] = definition

    def operation_overload(self, rule: ast.Rule) -> bool:
        """A .cga rule with an operation's name and a number of parameters none of the
        operation's signatures has: CityEngine calls it where a call has that many arguments
        (changelog 2019.1: operations are told from rules of the same name by signature)."""
        if not self._findings.cga or rule.name not in CGA_OPERATIONS or rule.name == "NIL":
            return False
        low, high = CGA_OPERATIONS[rule.name]
        return not low <= len(rule.params) <= high


def _overlaps(arity: tuple[int, int], count: int) -> bool:
    return arity[0] <= count <= arity[1]
