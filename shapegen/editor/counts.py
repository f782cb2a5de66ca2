"""Which attrs count things: the Inspector steps them by 1 and refuses a fraction.

The grammar has one kind of number, so an attr is a whole number by how the rules use it. An
attr is a **count** when its default and its ``@Range`` bounds are whole numbers and its value
reaches a place where the rules count with it:

- an ``int`` parameter of a primitive: ``i("barrel_vault", courses = vault_courses)`` (the
  primitive refuses a fraction);
- a recursion counter, a rule or function parameter that a call to itself steps by a whole
  number: ``Bays(part, n) --> ... Bays(part, n - 1)`` makes ``Bays(part, bays)`` count with
  ``bays`` (5.4 would lay out six bays);
- the other side of a comparison with such a counter: ``Towers(k) --> case k <= main_spans``
  with ``main_spans = case towers >= 2 : towers - 1 ...`` counts with ``towers``.

A value reaches such a place through names (attrs, consts, functions, rule and function
parameters at their call sites), ``+`` and ``-``, ``min``, ``max`` and the values of a ``case``;
``*``, ``/``, ``floor``, ``rint`` and the like make a count of any number, so a length in
``floor(length / span)`` is not one.

>>> from shapegen import pipeline                                    # doctest: +SKIP
>>> sorted(count_attrs(pipeline.load("cluny.grammar")))[:2]          # doctest: +SKIP
['aisle_vault_segments', 'arcade_segments']
"""

from __future__ import annotations

__all__ = ["count_attrs", "is_whole"]

import math
import weakref
from collections.abc import Iterator

from shapegen.errors import ShapegenError
from shapegen.grammar import ast

# The calls a count passes through unchanged (any of their arguments may be the count).
_PASSING_CALLS = frozenset({"min", "max"})
_COMPARISONS = frozenset({"<", "<=", ">", ">=", "==", "!="})
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def is_whole(value: object) -> bool:
    """True for a finite number without a fractional part (``5`` or ``5.0``, not ``True``)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    return math.isfinite(value) and float(value).is_integer()


def count_attrs(grammar) -> frozenset[str]:
    """The names of the attrs of ``grammar`` (a loaded :class:`~shapegen.engine.grammar_api.
    Grammar`) that are counts, as the module says; computed once per grammar."""
    known = _CACHE.get(grammar)
    if known is None:
        known = _CACHE[grammar] = _count_attrs(grammar)
    return known


def _count_attrs(grammar) -> frozenset[str]:
    counted = _Counts(grammar.ast).names()
    catalogue = grammar.catalogue
    try:
        ranges = catalogue.ranges()
    except ShapegenError:
        ranges = {}
    whole = set()
    for name in counted & set(catalogue):
        bounds = ranges.get(name)
        if is_whole(catalogue[name].default) and (
            bounds is None or (is_whole(bounds["min"]) and is_whole(bounds["max"]))
        ):
            whole.add(name)
    return frozenset(whole)


class _Counts:
    """Follows counts back from the places the rules count with to the names they come from."""

    def __init__(self, tree: ast.RuleFile):
        self.globals: dict[str, ast.Expression] = {}
        self.callables: dict[tuple[str, int], ast.Rule | ast.Function] = {}
        for definition in tree.definitions:
            if isinstance(definition, ast.Attribute | ast.Constant):
                self.globals[definition.name] = definition.value
            elif isinstance(definition, ast.Function) and not definition.params:
                self.globals[definition.name] = definition.body
            if isinstance(definition, ast.Function | ast.Rule):
                self.callables[(definition.name, len(definition.params))] = definition
        # every call (a successor or a function call) with the definition it is written in
        self.calls: dict[tuple[str, int], list[tuple[tuple, object]]] = {}
        for owner in tree.definitions:
            body = _body_of(owner)
            if body is None:
                continue
            for item in ast.walk(body):
                if isinstance(item, ast.Successor | ast.Call):
                    key = (item.name, len(item.args))
                    self.calls.setdefault(key, []).append((item.args, owner))
        self.counted: set[str] = set()
        self.counted_parameters: set[tuple[tuple[str, int], int]] = set()
        self.pending: list[tuple[ast.Expression, object]] = []

    def names(self) -> set[str]:
        for owner, body in self._bodies():
            if isinstance(owner, ast.Rule):
                self._primitive_counts(owner, body)
        for key, definition in self.callables.items():
            for index in self._counters(key, definition):
                self._count_parameter(key, index)
                name = definition.params[index].name
                for item in ast.walk(_body_of(definition)):
                    if isinstance(item, ast.Binary) and item.op in _COMPARISONS:
                        for side, other in ((item.left, item.right), (item.right, item.left)):
                            if isinstance(side, ast.Name) and side.name == name:
                                self.pending.append((other, definition))
        while self.pending:
            self._follow(*self.pending.pop())
        return self.counted

    def _bodies(self) -> Iterator[tuple[object, object]]:
        for definition in self.callables.values():
            yield definition, _body_of(definition)

    def _primitive_counts(self, rule: ast.Rule, body) -> None:
        from shapegen.primitives.library import get

        for item in ast.walk(body):
            if not isinstance(item, ast.Insert) or not isinstance(item.primitive, ast.String):
                continue
            try:
                parameters = get(item.primitive.value).parameters
            except (ShapegenError, LookupError):  # an asset file, or no such primitive
                continue
            for keyword in item.parameters:
                parameter = parameters.get(keyword.name)
                if parameter is not None and parameter.kind is int:
                    self.pending.append((keyword.value, rule))

    def _counters(self, key: tuple[str, int], definition) -> Iterator[int]:
        """The parameters a call of ``definition`` to itself steps by a whole number."""
        names = [p.name for p in definition.params]
        for args, owner in self.calls.get(key, ()):
            if owner is not definition:
                continue
            for index, arg in enumerate(args):
                if _stepped(arg, names[index]):
                    yield index

    def _count_parameter(self, key: tuple[str, int], index: int) -> None:
        if (key, index) in self.counted_parameters:
            return
        self.counted_parameters.add((key, index))
        for args, owner in self.calls.get(key, ()):
            self.pending.append((args[index], owner))

    def _follow(self, expression, owner) -> None:
        """Mark the names whose value ``expression`` (written in ``owner``) passes on."""
        if isinstance(expression, ast.Name):
            params = [p.name for p in getattr(owner, "params", ())]
            if expression.name in params:
                key = (owner.name, len(params))
                self._count_parameter(key, params.index(expression.name))
            elif expression.name in self.globals and expression.name not in self.counted:
                self.counted.add(expression.name)
                definition = self.callables.get((expression.name, 0))
                self.pending.append((self.globals[expression.name], definition))
        elif isinstance(expression, ast.Binary) and expression.op in ("+", "-"):
            self.pending.extend(((expression.left, owner), (expression.right, owner)))
        elif isinstance(expression, ast.Unary) and expression.op in ("+", "-"):
            self.pending.append((expression.operand, owner))
        elif isinstance(expression, ast.CaseExpression | ast.StochasticExpression):
            values = [branch.value for branch in expression.branches]
            self.pending.extend((value, owner) for value in (*values, expression.otherwise))
        elif isinstance(expression, ast.Call):
            if expression.name in _PASSING_CALLS:
                self.pending.extend((arg, owner) for arg in expression.args)
            else:
                function = self.callables.get((expression.name, len(expression.args)))
                if isinstance(function, ast.Function) and function.params:
                    self.pending.append((function.body, function))


def _stepped(arg, name: str) -> bool:
    """``name + k``, ``k + name`` or ``name - k`` with ``k`` a whole number other than 0."""
    if not isinstance(arg, ast.Binary) or arg.op not in ("+", "-"):
        return False
    pairs = [(arg.left, arg.right)] + ([(arg.right, arg.left)] if arg.op == "+" else [])
    for side, step in pairs:
        if isinstance(side, ast.Name) and side.name == name:
            return isinstance(step, ast.Number) and is_whole(step.value) and step.value != 0
    return False


def _body_of(definition):
    if isinstance(definition, ast.Rule | ast.Function):
        return definition.body
    if isinstance(definition, ast.Attribute | ast.Constant):
        return definition.value
    return None
