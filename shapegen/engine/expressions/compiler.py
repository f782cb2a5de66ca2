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

import operator
from collections.abc import Callable

from shapegen.engine.derivation.random_streams import choice
from shapegen.engine.expressions.arrays import (
    Array,
    colon_range,
    concatenated,
    format_value,
    type_name,
)
from shapegen.engine.expressions.arrays import index_array as _index_array
from shapegen.engine.expressions.calls import CONTEXT_QUERIES, OCCLUSION, BuiltinCalls
from shapegen.engine.expressions.file_reading import reading_functions
from shapegen.engine.expressions.file_search import file_functions
from shapegen.engine.expressions.local_variables import local_scope, with_locals
from shapegen.engine.expressions.operators import (
    ARITHMETIC,
    ELEMENTWISE_OPERATORS,
    ORDER,
    elementwise,
    elementwise_unary,
    ieee_arithmetic,
    ordered,
)
from shapegen.engine.expressions.pure_functions import PURE_FUNCTIONS
from shapegen.engine.expressions.shape_attributes import convert_value, shape_reader
from shapegen.engine.shapes.tags import is_tagged
from shapegen.errors import GrammarError
from shapegen.grammar import ast
from shapegen.grammar.names import (
    BUILTIN_FUNCTIONS,
    FUNCTION_KEYWORDS,
    FUNCTION_SELECTOR_POSITIONS,
    GEOMETRY_KEYWORDS,
)
from shapegen.limits import limit_hint

Value = float | bool | str
Compiled = Callable[[tuple, object], Value]


class TailCall:
    """A user function's call in tail position, not made yet: what its function returns to
    the calling site, which makes it (:meth:`ExpressionCompiler.compile_tail`)."""

    __slots__ = ("key", "values", "node")

    def __init__(self, key: tuple[str, int], values: tuple, node):
        self.key = key  # (name, number of arguments)
        self.values = values
        self.node = node


class ExpressionCompiler:
    """Compiles expressions of one grammar.

    Parameters
    ----------
    grammar
        The parsed file (for the source text in error messages and the function table).
    global_names
        Names of attributes and constants, read from ``state.attrs`` at run time.
    component_values
        The compiler of the comp *function* (``comp(f) { all : scope.sx }``),
        ``component_values(compiler, node, params)``: it takes the shape apart as the comp
        operation does, so it lives with the operations
        (:func:`~shapegen.engine.operations.cga.comp_values.compile_component_values`).
    """

    def __init__(
        self,
        grammar: ast.RuleFile,
        global_names: set[str],
        component_values: Callable[..., Compiled],
    ):
        self.grammar = grammar
        self.global_names = global_names
        self.component_values = component_values
        # User functions by (name, number of parameters): CGA overloads a name by its arity.
        self.functions: dict[tuple[str, int], Compiled | None] = {}
        self.overloads = {(f.name, len(f.params)): f for f in grammar.functions}
        self.function_nodes = {f.name: f for f in reversed(grammar.functions)}
        self.files = file_functions(grammar.filename)
        self.readers = reading_functions(grammar.filename, self.files["fileRandom"])
        self.calls = BuiltinCalls(self.compile, self.error, self.files)

    # ------------------------------------------------------------------ errors
    def error(self, node: object, message: str) -> GrammarError:
        location = getattr(node, "location", None)
        if location is not None and location.line == 0:
            location = None
        file = location.file if location is not None else None
        return GrammarError(message, location, self.grammar.source_of(file))

    # ------------------------------------------------------------------ functions
    def compile_functions(self) -> None:
        """Compile every user function (they may call each other, recursively)."""
        for key in self.overloads:
            self.functions[key] = None
        for key, function in self.overloads.items():
            params = {p.name: k for k, p in enumerate(function.params)}
            scope, extend = local_scope(self, function, params)
            body = self.compile_tail(function.body, scope)
            self.functions[key] = body if extend is None else with_locals(body, extend)
        pure: dict[tuple[str, int], bool] = {}
        for key in self.overloads:
            if self._pure_function(key, pure):
                self.functions[key] = _remembered(self.functions[key])

    # ------------------------------------------------------------------ pure functions
    def _pure_function(self, key: tuple[str, int], known: dict) -> bool:
        """Whether the user function ``key`` gives the same value for the same arguments
        wherever it is called: its body reads only its parameters and ``with`` variables,
        literals, the builtins that read neither the shape nor a random stream, and other
        such functions (no attr or const, which ``set`` may change; no shape attribute, no
        random choice, no print). A function met again while it is being decided counts as
        pure (a recursion decides nothing by itself)."""
        if key in known:
            return known[key]
        known[key] = True
        function = self.overloads[key]
        names = {p.name for p in function.params}
        names |= {v.name for v in function.local_variables}
        nodes = [v.value for v in function.local_variables] + [function.body]
        known[key] = all(self._pure_node(node, names, known) for node in nodes)
        return known[key]

    def _pure_node(self, node, names: set[str], known: dict) -> bool:
        kind = type(node)
        if kind in (ast.Number, ast.String, ast.Boolean, ast.Keyword):
            return True
        if kind is ast.Name:
            if node.name in names:
                return True
            if node.name in self.global_names or (node.name, 0) not in self.overloads:
                return False
            return self._pure_function((node.name, 0), known)
        if kind is ast.Call:
            name, count = node.name, len(node.args)
            if name in OCCLUSION or name in CONTEXT_QUERIES:
                return False
            if self._is_user_call(name, count):
                if (name, count) not in self.overloads:
                    return False
                pure = self._pure_function((name, count), known)
            else:
                pure = (
                    name in PURE_FUNCTIONS
                    and name not in _READS_STATE
                    and name not in self.readers
                    and name not in self.files
                )
            return pure and all(self._pure_node(a, names, known) for a in node.args)
        if kind is ast.Unary:
            return self._pure_node(node.operand, names, known)
        if kind is ast.Binary:
            return self._pure_node(node.left, names, known) and self._pure_node(
                node.right, names, known
            )
        if kind is ast.CaseExpression:
            parts = [node.otherwise]
            for branch in node.branches:
                parts += [branch.condition, branch.value]
            return all(self._pure_node(part, names, known) for part in parts)
        return False  # arrays, indices, shape attributes, random choices: not looked into

    def compile_tail(self, node: ast.Expression, params: dict[str, int]) -> Compiled:
        """:meth:`compile` for a function's body: a call of a user function in tail position
        (the body, or a value of its ``case`` or stochastic choice) gives a :class:`TailCall`
        that the calling site runs in its loop, so a tail recursion (``f(i, acc) = case i ==
        0: acc else: f(i - 1, acc + 1)``) runs as deep as the work clock and ``max_calls``
        allow without nesting Python frames, as CityEngine evaluates it."""
        if isinstance(node, ast.CaseExpression):
            return self._CaseExpression(node, params, tail=True)
        if isinstance(node, ast.StochasticExpression):
            return self._StochasticExpression(node, params, tail=True)
        if isinstance(node, ast.Call) and self._is_user_call(node.name, len(node.args)):
            words = FUNCTION_KEYWORDS.get(node.name, frozenset())
            arguments = tuple(
                self._keyword(arg, params, words) or self.compile(arg, params) for arg in node.args
            )
            return self._call_user(node, node.name, arguments, tail=True)
        if (
            isinstance(node, ast.Name)
            and node.name not in params
            and node.name not in self.global_names
            and node.name in self.function_nodes
        ):
            return self._call_user(node, node.name, (), tail=True)
        return self.compile(node, params)

    def _is_user_call(self, name: str, count: int) -> bool:
        """A call of ``name`` with ``count`` arguments calls a user function (which may
        overload a builtin with another number of parameters)."""
        if name in OCCLUSION or name in CONTEXT_QUERIES:
            return False
        return (name, count) in self.overloads or (
            name in self.function_nodes and name not in BUILTIN_FUNCTIONS
        )

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
        if self.grammar.dialect == "cga" and BUILTIN_FUNCTIONS.get(name, (1,))[0] == 0:
            # CityEngine calls a builtin that takes no argument without its () (rand, uid)
            return self.compile(ast.Call(name, (), location=node.location), params)
        raise self.error(node, f"unknown name {name!r}")

    def _ShapeAttribute(self, node: ast.ShapeAttribute, params) -> Compiled:
        key = f"{node.obj}.{node.field}" if node.field else node.obj
        arguments = tuple(
            self._geometry_selector(arg, params) if node.obj == "geometry" else None
            for arg in node.args
        )
        arguments = tuple(
            given or self.compile(arg, params)
            for given, arg in zip(arguments, node.args, strict=True)
        )
        try:
            reader = shape_reader(node.obj, node.field, self.grammar)
        except ValueError as exc:
            raise self.error(node, str(exc)) from None
        if reader is None:
            raise self.error(node, f"the shape attribute {key!r} is not supported by shapegen")
        error = self.error
        plain = getattr(reader, "plain", None)
        if plain is not None and not arguments:  # scope.sx, split.index...: read as they are

            def read_plain(args, state):
                try:
                    return plain(state)
                except (ValueError, KeyError) as exc:
                    message = exc.args[0] if exc.args else str(exc)
                    raise error(node, f"{key}: {message}") from None

            return read_plain

        def read(args, state):
            values = [a(args, state) for a in arguments]
            try:
                return reader(state, *values)
            except (ValueError, KeyError) as exc:
                message = exc.args[0] if exc.args else str(exc)
                raise error(node, f"{key}: {message}") from None

        return read

    def _geometry_selector(self, node, params) -> Compiled | None:
        return self._keyword(node, params, GEOMETRY_KEYWORDS)

    def _keyword(
        self, node, params, words: frozenset[str], selector_only: bool = True
    ) -> Compiled | None:
        """A selector among ``words`` (``maxSlope`` of geometry.angle, ``tx`` of assetInfo,
        ``world.up``) read as its name. Where only a selector may stand (``selector_only``:
        CGA has no selector values, so an attr, const or parameter cannot be one) the keyword
        wins over any name the rule defines (a function that takes arguments included, as
        ``y(i)`` beside ``alignScopeToAxes(y)``); where a value may stand too (convert's
        coordinates) a parameter, attr, const or function of that name is the value."""
        if not isinstance(node, ast.Name) or node.name not in words:
            return None
        name = node.name
        defined = name in params or name in self.global_names or name in self.function_nodes
        if defined and not selector_only:
            return None
        return lambda args, state: name

    def _ArrayLiteral(self, node: ast.ArrayLiteral, params) -> Compiled:
        rows = [[self._item(item, params) for item in row] for row in node.rows]
        error = self.error

        def array(args, state):
            values = []
            for row in rows:
                items = []
                for item, colon in row:
                    value = item(args, state)
                    if colon:  # a range is a row of numbers
                        items.append(Array(tuple(value), 1 if value else 0, len(value), float))
                    else:
                        items.append(value)
                values.append(items)
            try:
                return concatenated(values)
            except ValueError as exc:
                raise error(node, str(exc)) from None

        return array

    def _item(self, item, params) -> tuple[Compiled, bool]:
        """An array item: a value, or a :class:`~shapegen.grammar.ast.Colon` range (a list)."""
        if not isinstance(item, ast.Colon):
            return self.compile(item, params), False
        if item.start is None:
            raise self.error(item, "a lone ':' is only an index (a[:, 0])")
        start, stop = self.compile(item.start, params), self.compile(item.stop, params)
        step = self.compile(item.step, params) if item.step is not None else None
        error = self.error

        def values(args, state):
            numbers = [start(args, state), step(args, state) if step else 1.0, stop(args, state)]
            if any(type(v) is not float for v in numbers):
                raise error(item, "a range a:b or a:step:b needs numbers")
            try:
                return colon_range(*numbers)
            except ValueError as exc:
                raise error(item, str(exc)) from None

        return values, True

    def _Colon(self, node: ast.Colon, params) -> Compiled:
        raise self.error(node, "a range a:b is written inside brackets: [1:5] or a[0:2]")

    def _Index(self, node: ast.Index, params) -> Compiled:
        target = self.compile(node.target, params)
        indices = []
        for index in node.indices:
            if isinstance(index, ast.Colon) and index.start is None:
                indices.append((None, False))
            else:
                indices.append(self._item(index, params))
        error = self.error

        def index(args, state):
            array = target(args, state)
            values = []
            for k, (item, colon) in enumerate(indices):
                if item is None:  # ':' takes every row or column
                    length = array.rows if k == 0 else array.columns
                    values.append(Array(tuple(map(float, range(length))), 1, length))
                elif colon:
                    numbers = item(args, state)
                    values.append(Array(tuple(numbers), 1, len(numbers)))
                else:
                    values.append(item(args, state))
            try:
                return _index_array(array, values)
            except ValueError as exc:
                raise error(node, str(exc)) from None

        return index

    def _ComponentValues(self, node: ast.ComponentValues, params) -> Compiled:
        return self.component_values(self, node, params)

    def _Unary(self, node: ast.Unary, params) -> Compiled:
        operand = self.compile(node.operand, params)
        error = self.error
        if node.op.startswith("."):  # .! .- .+ on an array

            def each(args, state):
                try:
                    return elementwise_unary(node.op, operand(args, state))
                except ValueError as exc:
                    raise error(node, str(exc)) from None

            return each
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
        if op in ELEMENTWISE_OPERATORS:
            ieee = self.grammar.dialect == "cga"

            def each(args, state):
                try:
                    return elementwise(op, left(args, state), right(args, state), ieee)
                except ValueError as exc:
                    raise error(node, str(exc)) from None

            return each
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
        if op in ARITHMETIC:
            function = ARITHMETIC[op]
            ieee = self.grammar.dialect == "cga"

            def arithmetic(args, state):
                a = left(args, state)
                b = right(args, state)
                if type(a) is not float or type(b) is not float:
                    raise error(
                        node, f"'{op}' needs numbers, got a {type_name(a)} and a {type_name(b)}"
                    )
                try:
                    return function(a, b)
                except (ZeroDivisionError, ValueError, OverflowError):
                    if ieee:  # .cga: CityEngine's doubles give inf or nan, and it goes on
                        return ieee_arithmetic(op, a, b)
                    if b == 0.0:
                        raise error(node, "division by zero") from None
                    raise error(  # fmod of an infinity
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
        if op in ORDER:
            numbers = _NUMBER_ORDER[op]

            def compare(args, state):
                a = left(args, state)
                b = right(args, state)
                if type(a) is float and type(b) is float:  # the common case, as ordered's
                    return numbers(a, b)
                try:
                    return ordered(op, a, b)
                except ValueError as exc:
                    raise error(node, str(exc)) from None

            return compare
        raise self.error(node, f"unknown operator {op!r}")

    def _Call(self, node: ast.Call, params) -> Compiled:
        name = node.name
        if name in OCCLUSION:
            return self.calls.occlusion(node, params)
        if name in CONTEXT_QUERIES:
            return self.calls.context(node, params)
        words = FUNCTION_KEYWORDS.get(name, frozenset())
        selectors = FUNCTION_SELECTOR_POSITIONS.get(name)
        arguments = tuple(
            self._keyword(arg, params, words, selectors is None or k in selectors)
            or self.compile(arg, params)
            for k, arg in enumerate(node.args)
        )
        if self._is_user_call(name, len(arguments)):
            return self._call_user(node, name, arguments)
        if name == "rand":
            return self._call_rand(node, arguments)
        if name in ("p", "listRandom", "fileRandom"):
            return self.calls.random_choice(node, name, arguments)
        if name == "print":
            return self.calls.printed(node, arguments)
        if name == "convert":
            return self.calls.pure(node, convert_value, arguments, with_state=True)
        if name == "isTagged":
            return self.calls.pure(node, is_tagged, arguments, with_state=True)
        if name in self.readers:
            return self.calls.pure(node, self.readers[name], arguments, with_state=True)
        function = self.files.get(name) or PURE_FUNCTIONS.get(name)
        if function is not None:
            return self.calls.pure(node, function, arguments)
        raise self.error(node, f"the CGA function {name}() is not supported by shapegen")

    def _call_user(self, node, name: str, arguments: tuple, tail: bool = False) -> Compiled:
        functions = self.functions
        key = (name, len(arguments))
        if key not in self.overloads:
            counts = [n for f, n in sorted(self.overloads) if f == name]
            expected = " or ".join(str(n) for n in counts)
            noun = "argument" if counts == [1] else "arguments"
            if isinstance(node, ast.Name):  # written bare where a value stands
                raise self.error(
                    node, f"function {name!r} takes {expected} {noun}: write {name}(...)"
                )
            raise self.error(
                node, f"function {name!r} takes {expected} {noun}, got {len(arguments)}"
            )
        if tail:
            values_of = _values_of(arguments)

            def tail_call(args, state):
                return TailCall(key, values_of(args, state), node)

            return tail_call

        error = self.error

        values_of = _values_of(arguments)

        def call(args, state):
            values = values_of(args, state)
            run = state.run
            run.enter_call(node, name)
            try:
                result = functions[key](values, state)
                # calls in tail position: one after the other, at this call's depth
                while type(result) is TailCall:
                    run.enter_call(result.node, result.key[0], nested=False)
                    result = functions[result.key](result.values, state)
                return result
            except RecursionError:
                raise error(
                    node,
                    f"function {name!r} calls itself too deeply for Python's stack (endless "
                    f"recursion?) {limit_hint('max_call_depth', run.limits)}",
                ) from None
            finally:
                run.call_depth -= 1

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

    def _CaseExpression(self, node: ast.CaseExpression, params, tail: bool = False) -> Compiled:
        value_of = self.compile_tail if tail else self.compile
        branches = [
            (self.compile(b.condition, params), value_of(b.value, params), b) for b in node.branches
        ]
        otherwise = value_of(node.otherwise, params)
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

    def _StochasticExpression(
        self, node: ast.StochasticExpression, params, tail: bool = False
    ) -> Compiled:
        value_of = self.compile_tail if tail else self.compile
        fractions = tuple(float(b.percent) / 100.0 for b in node.branches)
        values = (*(value_of(b.value, params) for b in node.branches),
                  value_of(node.otherwise, params))  # fmt: skip

        def stochastic(args, state):
            return values[choice(state.random, fractions)](args, state)

        return stochastic


def _values_of(arguments: tuple) -> Callable:
    """``(args, state) -> tuple`` of the compiled ``arguments``' values, in order: written out
    for the few arguments most calls have (a generator's cost was a call's largest part)."""
    count = len(arguments)
    if count == 0:
        return lambda args, state: ()
    if count == 1:
        (a,) = arguments
        return lambda args, state: (a(args, state),)
    if count == 2:
        a, b = arguments
        return lambda args, state: (a(args, state), b(args, state))
    if count == 3:
        a, b, c = arguments
        return lambda args, state: (a(args, state), b(args, state), c(args, state))
    return lambda args, state: tuple([a(args, state) for a in arguments])


_NUMBER_ORDER = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
"""ORDER's comparisons of two numbers, as C functions."""


_READS_STATE = frozenset({"rand", "p", "listRandom", "fileRandom", "print", "convert", "isTagged"})
"""Builtins that read the shape or a random stream, or print, whatever their table says."""
_REMEMBERED_KEPT = 4096  # a pure function's answers kept, per function


def _remembered(body: Compiled) -> Compiled:
    """A pure user function (:meth:`ExpressionCompiler._pure_function`) that keeps its value
    for each tuple of arguments that are all numbers or strings (none of them zero, whose
    sign the key would not tell): Building_From_FootprintSMALL's textures ask the same
    file name's tile and floor counts for every facade. A call in tail position that the
    body returns is not kept: the calling site makes it, in its loop."""
    kept: dict[tuple, object] = {}

    def function(values, state):
        for value in values:
            kind = type(value)
            if (kind is not float and kind is not str) or value == 0.0:
                return body(values, state)
        found = kept.get(values, kept)
        if found is not kept:
            return found
        result = body(values, state)
        if type(result) is TailCall:  # the calling site makes it, without nesting frames
            return result
        if len(kept) >= _REMEMBERED_KEPT:
            kept.clear()
        kept[values] = result
        return result

    return function
