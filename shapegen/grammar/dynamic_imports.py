"""Dynamic imports (import.html, CGA 2023.0): ``prefix(attr = value, ...).Rule(args)`` runs an
imported rule with the import's attrs initialised again for that invocation.

:func:`reinitialised` makes the push that does so; :mod:`shapegen.grammar.imports` puts it in
place of each :class:`~shapegen.grammar.ast.DynamicImport` when it merges the imports.
"""

from __future__ import annotations

from shapegen.grammar import ast
from shapegen.grammar.problems import Problem
from shapegen.grammar.tree import rebuilt

__all__ = ["reinitialised"]


def reinitialised(
    call: ast.DynamicImport, attrs: list[ast.Attribute], problems: list[Problem]
) -> ast.Push:
    """The push that re-initialises an import's attrs for one dynamic invocation."""
    prefix = call.prefix + "."
    overrides = {}
    by_name = {a.name: a for a in attrs}
    for keyword in call.overrides:
        if prefix + keyword.name not in by_name:
            problems.append(
                (
                    keyword.location if keyword.location.line else call.location,
                    f"'{keyword.name}' is not an attr of the import '{call.prefix}'",
                )
            )
        overrides[prefix + keyword.name] = keyword.value
    order: list[str] = []
    state: dict[str, int] = {}

    def visit(name: str) -> None:  # dependencies first; cycles are the checks' to report
        if state.get(name):
            return
        state[name] = 1
        for node in ast.walk(by_name[name].value):
            if isinstance(node, ast.Name) and node.name in by_name:
                visit(node.name)
        order.append(name)

    for attr in attrs:
        visit(attr.name)
    items = [
        ast.Set(
            name, overrides.get(name, _value_with_locals(by_name[name])), location=call.location
        )
        for name in order
    ]
    items.append(
        ast.Successor(prefix + call.rule, call.args, called=bool(call.args), location=call.location)
    )
    return ast.Push(ast.Sequence(tuple(items), location=call.location), location=call.location)


def _value_with_locals(attr: ast.Attribute):
    """``attr``'s value with the local variables of its ``with (...)`` written in, each in
    place of its name (with.html: a local may read those before it), so that the value stands
    alone in a ``set``. A local that draws at random draws once per place it is read."""
    bound: dict = {}

    def change(tree, params):
        if isinstance(tree, ast.Name) and tree.name in bound:
            return bound[tree.name]
        return None

    for variable in attr.local_variables:
        bound[variable.name] = rebuilt(variable.value, change)
    return rebuilt(attr.value, change) if bound else attr.value
