"""Expressions on a batch of shapes: a value is one Python value shared by every shape of the
batch (a number, a string, a boolean) or a numpy column with one entry per shape.

A part of an expression that reads nothing that differs between the shapes (literals, attrs
with one value, builtins, arrays, indices and ``case`` values of those) is evaluated once by
the engine's own compiled expression, so it means exactly what it means one shape at a time
(CGA's string concatenation and number formatting included). What differs between shapes is
computed on columns: ``geometry.area()`` and ``geometry.volume()``, ``rand`` drawn from each
shape's own stream, attrs ``set`` from those, and ``+ - * /``, comparisons, ``! - && ||`` on
them. Anything else raises
:class:`~shapegen.engine.operations.registry.Unsupported`: those shapes are derived one at
a time.
"""

from __future__ import annotations

__all__ = ["ColumnExpressions"]

import numpy as np

from shapegen.engine.operations.registry import Unsupported, is_column
from shapegen.grammar import ast

_ARITHMETIC = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide}
_ORDER = {"<": np.less, "<=": np.less_equal, ">": np.greater, ">=": np.greater_equal}
_EQUAL = {"==": np.equal, "!=": np.not_equal}
_RANDOM_CALLS = frozenset({"rand", "p", "listRandom", "fileRandom"})


class ColumnExpressions:
    """Evaluates expressions of ``program`` (a compiled :class:`~shapegen.engine.interpreter.
    Program`) on a batch (:class:`~shapegen.engine.batch.lots.ShapeBatch`)."""

    def __init__(self, program, probe):
        self.program = program
        self.probe = probe  # a ShapeState whose attrs are set to a batch's shared values
        self._compiled: dict[int, object] = {}

    def value(self, node, batch):
        """The value of ``node`` on ``batch``: one Python value or a column."""
        if self._shared(node, batch):
            return self._shared_value(node, batch)
        if isinstance(node, ast.Name):
            return batch.attrs[node.name]  # a column (shared names took the branch above)
        if isinstance(node, ast.ShapeAttribute):
            return batch.geometry_value(node)
        if isinstance(node, ast.Call) and node.name == "rand":
            return self._rand(node, batch)
        if isinstance(node, ast.Unary):
            return self._unary(node, self.value(node.operand, batch))
        if isinstance(node, ast.Binary):
            return self._binary(node, batch)
        raise Unsupported(f"{type(node).__name__} on values that differ between shapes")

    # ------------------------------------------------------------------ shared values
    def _shared(self, node, batch) -> bool:
        """True when ``node`` reads nothing that differs between the shapes of ``batch``."""
        if isinstance(node, ast.Number | ast.String | ast.Boolean):
            return True
        if isinstance(node, ast.Name):
            value = batch.attrs.get(node.name, _MISSING)
            if value is _MISSING:
                if node.name in self.program.const_nodes:
                    return True
                raise Unsupported(f"the name {node.name!r}")
            return not is_column(value)
        if isinstance(node, ast.ShapeAttribute):
            return False
        if isinstance(node, ast.Call):
            if node.name in _RANDOM_CALLS or node.name in self.program.expressions.function_nodes:
                return False
            return all(self._shared(a, batch) for a in node.args)
        if isinstance(node, ast.Unary):
            return self._shared(node.operand, batch)
        if isinstance(node, ast.Binary):
            return self._shared(node.left, batch) and self._shared(node.right, batch)
        if isinstance(node, ast.ArrayLiteral):
            return all(self._shared(item, batch) for row in node.rows for item in row)
        if isinstance(node, ast.Colon):
            parts = (node.start, node.step, node.stop)
            return all(part is None or self._shared(part, batch) for part in parts)
        if isinstance(node, ast.Index):
            return self._shared(node.target, batch) and all(
                self._shared(index, batch) for index in node.indices
            )
        if isinstance(node, ast.CaseExpression):
            return self._shared(node.otherwise, batch) and all(
                self._shared(b.condition, batch) and self._shared(b.value, batch)
                for b in node.branches
            )
        return False  # a stochastic value draws from each shape's stream, and the others

    def _shared_value(self, node, batch):
        if isinstance(node, ast.Number):
            return float(node.value)
        if isinstance(node, ast.String | ast.Boolean):
            return node.value
        compiled = self._compiled.get(id(node))
        if compiled is None:
            compiled = self._compiled[id(node)] = (self.program.expressions.compile(node, {}), node)
        probe = self.probe
        probe.attrs = batch.shared_attrs()
        run = probe.run
        warnings, errors = len(run.warnings), run.cga_errors
        value = compiled[0]((), probe)
        if len(run.warnings) != warnings or run.cga_errors != errors:
            raise Unsupported("an expression that warns")
        if type(value) not in (float, str, bool):
            raise Unsupported(f"a value of type {type(value).__name__}")
        return value

    # ------------------------------------------------------------------ columns
    def _rand(self, node, batch):
        if len(node.args) > 2:
            raise Unsupported("rand() of more than two arguments")
        values = [self.value(a, batch) for a in node.args]
        for value in values:
            if not _numbers(value):
                raise Unsupported("rand() of a value that is not a number")
        low, high = (
            (0.0, 1.0)
            if not values
            else ((0.0, values[0]) if len(values) == 1 else (values[0], values[1]))
        )
        draws = batch.draws()
        return low + (high - low) * draws  # the engine's order of operations, per shape

    @staticmethod
    def _unary(node, operand):
        if node.op == "-" and _numbers(operand):
            return -operand
        if node.op == "+" and _numbers(operand):
            return operand
        if node.op == "!" and _booleans(operand):
            return ~operand
        raise Unsupported(f"the operator {node.op!r} on a column")

    def _binary(self, node, batch):
        op = node.op
        if op in ("&&", "||"):
            if _draws(node.right, self.program):
                raise Unsupported("a random draw on the right of && or ||")
        left = self.value(node.left, batch)
        right = self.value(node.right, batch)
        if op in _ARITHMETIC:
            if not (_numbers(left) and _numbers(right)):
                raise Unsupported(f"{op!r} of a column and a value that is not a number")
            if op == "/":
                zero = np.asarray(right) == 0.0
                if np.any(zero):
                    batch.give_up(np.broadcast_to(zero, (batch.size,)), "a division by zero")
                    right = np.where(zero, 1.0, right)
            return _ARITHMETIC[op](left, right)
        if op in _ORDER:
            if not (_numbers(left) and _numbers(right)):
                raise Unsupported(f"{op!r} of a column and a value that is not a number")
            return _ORDER[op](left, right)
        if op in _EQUAL:
            if (_numbers(left) and _numbers(right)) or (_booleans(left) and _booleans(right)):
                return _EQUAL[op](left, right)
            raise Unsupported(f"{op!r} of values of different kinds")
        if op in ("&&", "||"):
            if not (_booleans(left) and _booleans(right)):
                raise Unsupported(f"{op!r} of values that are not booleans")
            return np.logical_and(left, right) if op == "&&" else np.logical_or(left, right)
        raise Unsupported(f"the operator {op!r} on a column")


_MISSING = object()


def _numbers(value) -> bool:
    if is_column(value):
        return value.dtype == np.float64
    return type(value) is float


def _booleans(value) -> bool:
    if is_column(value):
        return value.dtype == np.bool_
    return type(value) is bool


def _draws(node, program) -> bool:
    """True when evaluating ``node`` may draw a random number."""
    return any(
        isinstance(n, ast.Call)
        and (n.name in _RANDOM_CALLS or n.name in program.expressions.function_nodes)
        for n in ast.walk(node)
    )
