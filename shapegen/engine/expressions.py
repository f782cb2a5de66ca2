"""Compiling grammar expressions into Python closures.

Each expression node becomes a closure ``value(args, state)``: ``args`` holds the values of the
enclosing rule's or function's parameters (a tuple, positions resolved at compile time) and
``state`` is the shape being derived (its attributes, scope, split and comp indices, random
generator). Compiling once and calling closures keeps per-shape work small: the optimizer
rebuilds whole models many times.

Values are ``float`` (every number), ``bool`` or ``str``. A type mismatch, a division by zero or
a math domain error raises :class:`~shapegen.errors.GrammarError` at the offending node, and so
does work past a :class:`~shapegen.limits.WorkLimits` bound: user-function calls (how many, how
deeply nested) and string sizes are counted on the derivation (``state.run``).
"""

from __future__ import annotations

__all__ = ["ExpressionCompiler", "format_value", "type_name"]

import math
from collections.abc import Callable

from shapegen.errors import GrammarError
from shapegen.grammar import ast
from shapegen.limits import limit_hint

Value = float | bool | str
Compiled = Callable[[tuple, object], Value]


def type_name(value: object) -> str:
    """The grammar's name for a value's type (for error messages)."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, float):
        return "number"
    if isinstance(value, str):
        return "string"
    return type(value).__name__


def format_value(value: object) -> str:
    """A value as CGA prints it: ``3`` for 3.0, ``true`` for True."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
            return str(int(value))
        return repr(value)
    return str(value)


def _degrees(function: Callable[[float], float]) -> Callable[[float], float]:
    return lambda x: function(math.radians(x))


def _inverse_degrees(function: Callable[..., float]) -> Callable[..., float]:
    return lambda *x: math.degrees(function(*x))


_MATH: dict[str, Callable[..., float]] = {
    "sin": _degrees(math.sin),
    "cos": _degrees(math.cos),
    "tan": _degrees(math.tan),
    "asin": _inverse_degrees(math.asin),
    "acos": _inverse_degrees(math.acos),
    "atan": _inverse_degrees(math.atan),
    "atan2": _inverse_degrees(math.atan2),
    "sqrt": math.sqrt,
    "abs": abs,
    "min": min,
    "max": max,
    "floor": lambda x: float(math.floor(x)),
    "ceil": lambda x: float(math.ceil(x)),
    "rint": lambda x: float(round(x)),
    "pow": math.pow,
    "exp": math.exp,
    "ln": math.log,
    "log10": math.log10,
}


class ExpressionCompiler:
    """Compiles expressions of one grammar.

    Parameters
    ----------
    grammar
        The parsed file (for the source text in error messages and the function table).
    global_names
        Names of attributes and constants, read from ``state.attrs`` at run time.
    """

    def __init__(self, grammar: ast.Grammar, global_names: set[str]):
        self.grammar = grammar
        self.global_names = global_names
        self.functions: dict[str, tuple[int, Compiled]] = {}
        self.function_nodes = {f.name: f for f in grammar.functions}

    # ------------------------------------------------------------------ errors
    def error(self, node: object, message: str) -> GrammarError:
        location = getattr(node, "location", None)
        if location is not None and location.line == 0:
            location = None
        return GrammarError(message, location, self.grammar.source)

    # ------------------------------------------------------------------ functions
    def compile_functions(self) -> None:
        """Compile every user function (they may call each other, recursively)."""
        for function in self.grammar.functions:
            params = {p.name: k for k, p in enumerate(function.params)}
            self.functions[function.name] = (len(params), None)
        for function in self.grammar.functions:
            params = {p.name: k for k, p in enumerate(function.params)}
            self.functions[function.name] = (len(params), self.compile(function.body, params))

    # ------------------------------------------------------------------ expressions
    def compile(self, node: ast.Expression, params: dict[str, int]) -> Compiled:
        """A closure ``value(args, state)`` for ``node``; ``params`` maps names to arg positions."""
        method = getattr(self, "_" + type(node).__name__, None)
        if method is None:
            raise self.error(node, f"unsupported expression {type(node).__name__}")
        return method(node, params)

    def _Number(self, node: ast.Number, params) -> Compiled:
        value = float(node.value)
        return lambda args, state: value

    def _String(self, node: ast.String, params) -> Compiled:
        value = node.value
        return lambda args, state: value

    def _Boolean(self, node: ast.Boolean, params) -> Compiled:
        value = bool(node.value)
        return lambda args, state: value

    def _Name(self, node: ast.Name, params) -> Compiled:
        name = node.name
        if name in params:
            index = params[name]
            return lambda args, state: args[index]
        if name in self.global_names:
            return lambda args, state: state.attrs[name]
        if name in self.function_nodes:
            return self._call_user(node, name, ())
        raise self.error(node, f"unknown name {name!r}")

    def _ShapeAttribute(self, node: ast.ShapeAttribute, params) -> Compiled:
        key = f"{node.obj}.{node.field}"
        reader = _SHAPE_READERS.get(key)
        if reader is None:
            raise self.error(node, f"unknown shape attribute {key!r}")
        return lambda args, state: reader(state)

    def _Unary(self, node: ast.Unary, params) -> Compiled:
        operand = self.compile(node.operand, params)
        error = self.error
        if node.op == "!":

            def negate(args, state):
                value = operand(args, state)
                if type(value) is not bool:
                    raise error(node, f"'!' needs a boolean, got a {type_name(value)}")
                return not value

            return negate

        sign = -1.0 if node.op == "-" else 1.0

        def minus(args, state):
            value = operand(args, state)
            if type(value) is not float:
                raise error(node, f"'{node.op}' needs a number, got a {type_name(value)}")
            return sign * value

        return minus

    def _Binary(self, node: ast.Binary, params) -> Compiled:
        left = self.compile(node.left, params)
        right = self.compile(node.right, params)
        op = node.op
        error = self.error
        if op in ("&&", "||"):
            want = op == "||"

            def logical(args, state):
                a = left(args, state)
                if type(a) is not bool:
                    raise error(node, f"'{op}' needs booleans, got a {type_name(a)}")
                if a is want:
                    return a
                b = right(args, state)
                if type(b) is not bool:
                    raise error(node, f"'{op}' needs booleans, got a {type_name(b)}")
                return b

            return logical
        if op == "+":

            def add(args, state):
                a = left(args, state)
                b = right(args, state)
                if type(a) is float and type(b) is float:
                    return a + b
                if type(a) is str or type(b) is str:
                    text = format_value(a) + format_value(b)
                    state.run.count_string(node, len(text))
                    return text
                raise error(node, f"cannot add a {type_name(a)} and a {type_name(b)}")

            return add
        if op in _ARITHMETIC:
            function = _ARITHMETIC[op]

            def arithmetic(args, state):
                a = left(args, state)
                b = right(args, state)
                if type(a) is not float or type(b) is not float:
                    raise error(
                        node, f"'{op}' needs numbers, got a {type_name(a)} and a {type_name(b)}"
                    )
                try:
                    return function(a, b)
                except ZeroDivisionError:
                    raise error(node, "division by zero") from None
                except (ValueError, OverflowError):  # fmod of an infinity
                    raise error(
                        node, f"{format_value(a)} {op} {format_value(b)} is not defined"
                    ) from None

            return arithmetic
        if op in ("==", "!="):
            equal = op == "=="

            def compare_equal(args, state):
                a = left(args, state)
                b = right(args, state)
                return (type(a) is type(b) and a == b) is equal

            return compare_equal
        if op in _ORDER:
            function = _ORDER[op]

            def compare(args, state):
                a = left(args, state)
                b = right(args, state)
                if type(a) is not type(b) or type(a) is bool:
                    raise error(
                        node,
                        f"'{op}' compares two numbers or two strings, "
                        f"got a {type_name(a)} and a {type_name(b)}",
                    )
                return function(a, b)

            return compare
        raise self.error(node, f"unknown operator {op!r}")

    def _Call(self, node: ast.Call, params) -> Compiled:
        arguments = tuple(self.compile(arg, params) for arg in node.args)
        name = node.name
        if name in self.function_nodes:
            return self._call_user(node, name, arguments)
        if name in _MATH:
            return self._call_math(node, _MATH[name], arguments)
        if name == "rand":
            return self._call_rand(node, arguments)
        if name in ("str", "float", "bool") and len(arguments) == 1:
            return self._call_conversion(node, name, arguments[0])
        raise self.error(node, f"unknown function {name!r}")

    def _call_user(self, node, name: str, arguments: tuple) -> Compiled:
        functions = self.functions
        expected = len(self.function_nodes[name].params)
        if len(arguments) != expected:
            raise self.error(
                node, f"function {name!r} takes {expected} arguments, got {len(arguments)}"
            )

        error = self.error

        def call(args, state):
            body = functions[name][1]
            values = tuple(a(args, state) for a in arguments)
            run = state.run
            run.enter_call(node, name)
            try:
                return body(values, state)
            except RecursionError:
                raise error(
                    node,
                    f"function {name!r} calls itself too deeply for Python's stack (endless "
                    f"recursion?) {limit_hint('max_call_depth', run.limits)}",
                ) from None
            finally:
                run.call_depth -= 1

        return call

    def _call_math(self, node, function, arguments: tuple) -> Compiled:
        error = self.error
        name = node.name

        def call(args, state):
            values = [a(args, state) for a in arguments]
            for value in values:
                if type(value) is not float:
                    raise error(node, f"{name}() needs numbers, got a {type_name(value)}")
            try:
                result = function(*values)
            except (ValueError, OverflowError):
                shown = ", ".join(format_value(v) for v in values)
                raise error(node, f"{name}({shown}) is not defined") from None
            return float(result)

        return call

    def _call_rand(self, node, arguments: tuple) -> Compiled:
        error = self.error
        if len(arguments) > 2:
            raise error(node, f"rand() takes at most 2 arguments, got {len(arguments)}")

        def call(args, state):
            values = [a(args, state) for a in arguments]
            for value in values:
                if type(value) is not float:
                    raise error(node, f"rand() needs numbers, got a {type_name(value)}")
            low, high = (
                (0.0, 1.0)
                if not values
                else ((0.0, values[0]) if len(values) == 1 else (values[0], values[1]))
            )
            return low + (high - low) * state.random()

        return call

    def _call_conversion(self, node, name: str, argument: Compiled) -> Compiled:
        error = self.error

        def call(args, state):
            value = argument(args, state)
            if name == "str":
                return format_value(value)
            if name == "bool":
                if type(value) is str:
                    return value.strip().lower() in ("true", "1")
                return bool(value)
            if type(value) is str:
                try:
                    return float(value)
                except ValueError:
                    raise error(node, f"float({value!r}): not a number") from None
            return float(value)

        return call

    def _CaseExpression(self, node: ast.CaseExpression, params) -> Compiled:
        branches = [
            (self.compile(b.condition, params), self.compile(b.value, params), b)
            for b in node.branches
        ]
        otherwise = self.compile(node.otherwise, params)
        error = self.error

        def case(args, state):
            for condition, value, branch in branches:
                test = condition(args, state)
                if type(test) is not bool:
                    raise error(
                        branch, f"a case condition must be a boolean, got a {type_name(test)}"
                    )
                if test:
                    return value(args, state)
            return otherwise(args, state)

        return case

    def _StochasticExpression(self, node: ast.StochasticExpression, params) -> Compiled:
        branches = [(float(b.percent), self.compile(b.value, params)) for b in node.branches]
        otherwise = self.compile(node.otherwise, params)

        def stochastic(args, state):
            draw = 100.0 * state.random()
            for percent, value in branches:
                if draw < percent:
                    return value(args, state)
                draw -= percent
            return otherwise(args, state)

        return stochastic


def _divide(a: float, b: float) -> float:
    return a / b


def _remainder(a: float, b: float) -> float:
    if b == 0.0:
        raise ZeroDivisionError
    return math.fmod(a, b)


_ARITHMETIC = {
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": _divide,
    "%": _remainder,
}

_ORDER = {
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
}


def _euler(state, k: int) -> float:
    r = state.shape.scope.rotation
    # Angles of rotation_matrix(): R = Rz @ Ry @ Rx, in degrees.
    if k == 0:
        return math.degrees(math.atan2(r[2, 1], r[2, 2]))
    if k == 1:
        return math.degrees(-math.asin(max(-1.0, min(1.0, float(r[2, 0])))))
    return math.degrees(math.atan2(r[1, 0], r[0, 0]))


_SHAPE_READERS: dict[str, Callable[[object], Value]] = {
    "scope.sx": lambda state: float(state.shape.scope.size[0]),
    "scope.sy": lambda state: float(state.shape.scope.size[1]),
    "scope.sz": lambda state: float(state.shape.scope.size[2]),
    "scope.tx": lambda state: float(state.shape.scope.origin[0]),
    "scope.ty": lambda state: float(state.shape.scope.origin[1]),
    "scope.tz": lambda state: float(state.shape.scope.origin[2]),
    "scope.rx": lambda state: _euler(state, 0),
    "scope.ry": lambda state: _euler(state, 1),
    "scope.rz": lambda state: _euler(state, 2),
    "split.index": lambda state: float(state.split_index),
    "split.total": lambda state: float(state.split_total),
    "comp.index": lambda state: float(state.comp_index),
    "comp.total": lambda state: float(state.comp_total),
}
