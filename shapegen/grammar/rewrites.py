"""Forms CGA defines as other forms, written as them when the tree is built: the generic
``start`` rule of a rule marked ``start`` (start.html) and the deprecated boolean operation
before a rule (changelog 2025.0)."""

from __future__ import annotations

from shapegen.grammar import ast

__all__ = ["BOOLEAN_OPERATIONS", "generic_start_rules", "two_operands"]

BOOLEAN_OPERATIONS = frozenset({"union", "subtract", "intersect"})


def two_operands(operation: ast.Operation, item) -> ast.Operation:
    """``subtract Rule`` as CGA 2025.0 rewrites it: ``subtract { OperandA. | Rule }`` (the
    current shape first), and ``subtract(swap) Rule`` as ``subtract { Rule | OperandB. }``."""
    where = item.location
    swap = any(
        isinstance(a.value, ast.Name) and a.value.name == "swap" for a in operation.arguments
    )
    current = ast.Successor("OperandB" if swap else "OperandA", leaf=True, location=where)
    operands = [ast.Sequence((current,), location=where), ast.Sequence((item,), location=where)]
    if swap:
        operands.reverse()
    branches = tuple(
        ast.OperationBranch(None, "absolute", body, location=where) for body in operands
    )
    return ast.Operation(operation.name, (), branches, location=operation.location)


def generic_start_rules(definitions: list, marked: set) -> list[ast.Rule]:
    """``start(p...) --> Init(p...)`` for each rule ``Init`` written ``start Init`` (its location
    in ``marked``): start.html, ``start(20)`` is the same as ``Init(20)`` and an importing file's
    ``lib.start(10)`` as ``lib.Init(10)``; unless the file has a rule ``start`` of that arity."""
    rules = [d for d in definitions if isinstance(d, ast.Rule)]
    taken = {(rule.name, len(rule.params)) for rule in rules}
    generic = []
    for rule in rules:
        key = ("start", len(rule.params))
        if rule.location in marked and key not in taken:
            taken.add(key)
            where = rule.location
            args = tuple(ast.Name(p.name, location=where) for p in rule.params)
            call = ast.Successor(rule.name, args, called=bool(args), location=where)
            body = ast.Sequence((call,), location=where)
            generic.append(ast.Rule("start", rule.params, body, location=where))
    return generic
