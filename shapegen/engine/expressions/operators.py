"""Operators of CGA's expressions on values: the arithmetic and ordering of two numbers (or
strings, or two arrays), and the element-wise array operators of arrayTypes.html (``.+``, ``.-``,
``.*``, ``./``, ``.%``, ``.==``, ``.!=``, ``.<``, ``.<=``, ``.>``, ``.>=``, ``.&&``, ``.||`` and the
unary ``.!``, ``.-``, ``.+``).

An element-wise operator applies its operator to each element and gives an array of the
array operand's dimensions; two arrays must have equal dimensions, and one operand at least is an
array. ``.+`` adds numbers or, where a string is involved, concatenates (``["a", "b"] .+ 1`` is
``["a1", "b1"]``); ``.%`` is C's remainder (the sign of the dividend: ``[8; -5; 0] .% 3`` is
``[2; -2; 0]``). Two arrays are ordered row by row (arrayTypes.html, "Relational operators"): the
first differing element decides; a row that is the start of the other's is less (fewer columns),
and then the array with fewer rows is less. The operators raise ``ValueError`` with the user's
message.
"""

from __future__ import annotations

__all__ = [
    "ARITHMETIC",
    "ELEMENTWISE_OPERATORS",
    "ORDER",
    "elementwise",
    "ieee_arithmetic",
    "elementwise_unary",
    "ordered",
    "remainder",
]

import math
from collections.abc import Callable

from shapegen.engine.expressions.arrays import Array, format_value, type_name


def remainder(a: float, b: float) -> float:
    """C's ``fmod``: the remainder with the sign of ``a``."""
    if b == 0.0:
        raise ZeroDivisionError
    return math.fmod(a, b)


def ieee_arithmetic(op: str, a: float, b: float) -> float:
    """``a op b`` as IEEE 754 gives it where Python raises: ``x / 0`` is an infinity of the
    sign of ``x`` (nan for ``0 / 0``), a remainder by zero or of an infinity is nan. What
    CityEngine's runtime computes (its maths are C++ doubles)."""
    if op == "/" and b == 0.0:
        if a == 0.0 or math.isnan(a):
            return math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)
    return math.nan


ARITHMETIC: dict[str, Callable[[float, float], float]] = {
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "%": remainder,
}

ORDER: dict[str, Callable[[object, object], bool]] = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
}


def _rows(array: Array) -> list[tuple]:
    columns = array.columns
    return [array.values[r * columns : (r + 1) * columns] for r in range(array.rows)]


def ordered(op: str, a: object, b: object) -> bool:
    """``a op b`` for ``op`` in :data:`ORDER`: two numbers, two strings, or two arrays of numbers
    or of strings, ordered row by row."""
    if isinstance(a, Array) and isinstance(b, Array):
        kinds = {type(value) for value in a.values + b.values}
        if len(kinds) > 1 or kinds - {float, str}:
            raise ValueError(
                f"'{op}' compares two arrays of numbers or two of strings, got a {type_name(a)} "
                f"and a {type_name(b)}"
            )
        return ORDER[op](_rows(a), _rows(b))
    if type(a) is not type(b) or type(a) not in (float, str):
        raise ValueError(
            f"'{op}' compares two numbers, two strings or two arrays, got a {type_name(a)} and a "
            f"{type_name(b)}"
        )
    return ORDER[op](a, b)


def _plus(a: object, b: object) -> object:
    if type(a) is float and type(b) is float:
        return a + b
    if type(a) is str or type(b) is str:
        return format_value(a) + format_value(b)
    raise ValueError(
        f"'.+' adds numbers or joins strings, got a {type_name(a)} and a {type_name(b)}"
    )


def _numbers(op: str, function: Callable[[float, float], float], ieee: bool = False) -> Callable:
    def apply(a: object, b: object) -> float:
        if type(a) is not float or type(b) is not float:
            raise ValueError(f"'.{op}' needs numbers, got a {type_name(a)} and a {type_name(b)}")
        try:
            return function(a, b)
        except ZeroDivisionError:
            if ieee:
                return ieee_arithmetic(op, a, b)
            raise ValueError("division by zero") from None

    return apply


def _ordered(op: str) -> Callable:
    function = ORDER[op]

    def apply(a: object, b: object) -> bool:
        if type(a) is not type(b) or type(a) not in (float, str):
            raise ValueError(
                f"'.{op}' compares numbers or strings, got a {type_name(a)} and a {type_name(b)}"
            )
        return function(a, b)

    return apply


def _logical(op: str) -> Callable:
    def apply(a: object, b: object) -> bool:
        if type(a) is not bool or type(b) is not bool:
            raise ValueError(f"'.{op}' needs booleans, got a {type_name(a)} and a {type_name(b)}")
        return (a or b) if op == "||" else (a and b)

    return apply


_ELEMENTWISE: dict[str, Callable[[object, object], object]] = {
    ".+": _plus,
    **{"." + op: _numbers(op, function) for op, function in ARITHMETIC.items()},
    ".==": lambda a, b: type(a) is type(b) and a == b,
    ".!=": lambda a, b: not (type(a) is type(b) and a == b),
    **{"." + op: _ordered(op) for op in ORDER},
    ".&&": _logical("&&"),
    ".||": _logical("||"),
}


# .cga: a division by zero gives inf or nan element by element, as the scalar operators do
_ELEMENTWISE_IEEE = {
    **_ELEMENTWISE,
    **{"." + op: _numbers(op, function, ieee=True) for op, function in ARITHMETIC.items()},
}

ELEMENTWISE_OPERATORS = frozenset(_ELEMENTWISE)


def elementwise(op: str, a: object, b: object, ieee: bool = False) -> Array:
    """``a op b`` element by element (``op`` with its dot: ``".+"``); with ``ieee`` (``.cga``),
    a division or remainder by zero gives what :func:`ieee_arithmetic` gives, not an error."""
    function = (_ELEMENTWISE_IEEE if ieee else _ELEMENTWISE)[op]
    if isinstance(a, Array) and isinstance(b, Array):
        if (a.rows, a.columns) != (b.rows, b.columns):
            raise ValueError(
                f"'{op}' needs arrays of equal dimensions, got {a.rows}x{a.columns} and "
                f"{b.rows}x{b.columns}"
            )
        values, shape = [function(x, y) for x, y in zip(a.values, b.values, strict=True)], a
    elif isinstance(a, Array):
        values, shape = [function(x, b) for x in a.values], a
    elif isinstance(b, Array):
        values, shape = [function(a, y) for y in b.values], b
    else:
        raise ValueError(f"'{op}' works on arrays; for two values write '{op[1:]}'")
    element = type(values[0]) if values else shape.element_type()
    return Array(tuple(values), shape.rows, shape.columns, element)


def elementwise_unary(op: str, a: object) -> Array:
    """``.!a``, ``.-a`` or ``.+a`` element by element."""
    if not isinstance(a, Array):
        raise ValueError(f"'{op}' works on arrays; for a value write '{op[1:]}'")
    want = bool if op == ".!" else float
    for value in a.values:
        if type(value) is not want:
            raise ValueError(f"'{op}' needs {'booleans' if want is bool else 'numbers'}, got a "
                             f"{type_name(value)}")  # fmt: skip
    if op == ".!":
        values = tuple(not v for v in a.values)
    else:
        values = tuple(-v for v in a.values) if op == ".-" else a.values
    return Array(values, a.rows, a.columns, want)
