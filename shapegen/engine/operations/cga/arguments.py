"""The arguments of CGA operations, checked one way for all of them: how many there are and
that they are plain (not ``'x``, ``~x`` or ``key=x``), whether a ``{ ... }`` block may follow,
selector words (``world.up``, ``yUp``, ``front``), and values of a type (a finite number, a
boolean, a string) checked when the operation runs.

Every message names the operation: ``offset() takes 1 or 2 arguments, got 3``, ``color(): green
must be a finite number, got a string``, ``extrude(): the type is one of face.normal, ...``.
"""

from __future__ import annotations

__all__ = [
    "argument_word",
    "choice",
    "number",
    "plain_arguments",
    "selector_name",
    "typed",
]

from collections.abc import Collection
from math import isfinite

from shapegen.engine.derivation.finite import finite_parameter
from shapegen.engine.expressions.arrays import type_name
from shapegen.grammar import ast

_KIND_NAMES = {float: "finite number", bool: "boolean", str: "string"}


def plain_arguments(program, node, counts: Collection[int], block: bool = False) -> list:
    """The argument expressions of ``node``, after checking that there are as many as one of
    ``counts`` (a tuple, or a range), that each is plain, and that no ``{ ... }`` block follows
    unless the operation takes one (``block``)."""
    for argument in node.arguments:
        if argument.kind != "plain":
            raise program.error(
                argument if getattr(argument, "location", None) else node,
                f"{node.name}() takes plain arguments, not a {argument.kind} one",
            )
    if node.branches and not block:
        raise program.error(node, f"{node.name}() takes no {{ ... }} block")
    n = len(node.arguments)
    if n not in counts:
        raise program.error(node, f"{node.name}() takes {_expected(counts)} arguments, got {n}")
    return [argument.value for argument in node.arguments]


def _expected(counts: Collection[int]) -> str:
    if isinstance(counts, range):
        low, high = counts[0], counts[-1]
        return f"{low}" if low == high else f"{low} to {high}"
    return " or ".join(str(c) for c in counts)


def argument_word(expression) -> str | None:
    """A selector argument as written (``world.up``, ``yUp``, a string), or None."""
    if isinstance(expression, ast.String):
        return expression.value
    return selector_name(expression)


def selector_name(expression) -> str | None:
    """A selector written as a name (``front``, ``world.up``), or None (a string or a value)."""
    if isinstance(expression, ast.Name):
        return expression.name
    if isinstance(expression, ast.ShapeAttribute):
        return f"{expression.obj}.{expression.field}"
    return None


def choice(program, node, expression, choices: tuple[str, ...], what: str) -> str:
    """The selector word of ``expression``, which must be one of ``choices``."""
    word = argument_word(expression)
    if word not in choices:
        raise program.error(
            node, f"{node.name}(): {what} is one of {', '.join(choices)}; got {word or 'a value'}"
        )
    return word


def typed(program, node, expression, params, kind: type, what: str, at=None):
    """``f(args, state)``: the value of ``expression``, which must be of ``kind`` (float, bool or
    str) when the operation runs; a number must be finite (in a ``.cga`` rule nan and inf are
    0 with a warning, as CityEngine's runtime has them). Errors point at ``at`` (a part of the
    operation, such as a branch) or the operation."""
    compiled = program.expressions.compile(expression, params)
    error = program.error
    place = node if at is None else at

    def value(args, state):
        result = compiled(args, state)
        if type(result) is kind and (kind is not float or isfinite(result)):
            return result  # the common case: what the operation asks for
        if kind is float and type(result) is int:
            result = float(result)
        if type(result) is not kind:
            raise error(
                place,
                f"{node.name}(): {what} must be a {_KIND_NAMES[kind]}, got a {type_name(result)}",
            )
        if kind is float:
            return finite_parameter(program, place, state, result, f"{node.name}(): {what}")
        return result

    return value


def number(program, node, expression, params, what: str, at=None):
    """``f(args, state)``: a finite number (see :func:`typed`)."""
    return typed(program, node, expression, params, float, what, at)
