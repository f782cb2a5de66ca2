"""Constant folding: the value of an expression when it is known at load time.

The load-time checks fold ``@Range`` bounds, ``@Lot`` sizes and attr defaults to judge them before
any shape exists; an expression that needs a shape, a random draw or a function call folds to
:data:`UNKNOWN`.
"""

from __future__ import annotations

import math

from shapegen.grammar import ast

__all__ = ["UNKNOWN", "constant_value", "is_number"]


class _Unknown:
    """A value that cannot be known at load time (it needs a shape, a random draw...)."""

    def __repr__(self) -> str:
        return "<unknown>"


#: The folded value of an expression that is not known at load time.
UNKNOWN = _Unknown()


def is_number(value: object) -> bool:
    """True for a finite number (the language's numbers are floats)."""
    return isinstance(value, float) and math.isfinite(value)


def constant_value(expression: ast.Expression, values: dict | None = None, _seen=None):
    """The value of ``expression`` if it is known at load time, else an unknown marker.

    Numbers, strings, booleans, ``+ - * /`` and unary minus are folded; a name is folded through
    the attr or const it refers to (with its default value). Anything else is unknown.
    """
    values = values or {}
    seen = _seen if _seen is not None else set()
    if isinstance(expression, ast.Number):
        return expression.value
    if isinstance(expression, ast.String | ast.Boolean):
        return expression.value
    if isinstance(expression, ast.Name):
        target = values.get(expression.name)
        if isinstance(target, ast.Attribute | ast.Constant) and expression.name not in seen:
            return constant_value(target.value, values, seen | {expression.name})
        return UNKNOWN
    if isinstance(expression, ast.Unary) and expression.op in ("-", "+"):
        operand = constant_value(expression.operand, values, seen)
        if not is_number(operand):
            return UNKNOWN
        return -operand if expression.op == "-" else operand
    if isinstance(expression, ast.Binary) and expression.op in ("+", "-", "*", "/"):
        left = constant_value(expression.left, values, seen)
        right = constant_value(expression.right, values, seen)
        if not (is_number(left) and is_number(right)):
            return UNKNOWN
        if expression.op == "+":
            return left + right
        if expression.op == "-":
            return left - right
        if expression.op == "*":
            return left * right
        return left / right if right != 0 else UNKNOWN
    return UNKNOWN
