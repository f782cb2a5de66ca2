"""Compiling the calls of CGA builtins that need more than their arguments: the shape's random
generator (``p``, ``listRandom``, ``fileRandom``), the console (``print``), the occlusion
queries (``inside``, ``overlaps``, ``touches``, answered by
``shapegen.engine.derivation.occlusion``) and the context queries (``contextCount``,
``contextCompare``, ``minimumDistance``, answered by
``shapegen.engine.derivation.context_queries``).

:class:`~shapegen.engine.expressions.compiler.ExpressionCompiler` makes one
:class:`BuiltinCalls` and hands it these calls.
"""

from __future__ import annotations

__all__ = ["CONTEXT_QUERIES", "OCCLUSION", "PARTIAL_FUNCTIONS", "BuiltinCalls"]

from collections.abc import Callable

from shapegen.engine.derivation.context_queries import COMPARISONS, CONTEXT_QUERIES, context_query
from shapegen.engine.expressions.arrays import format_value, type_name
from shapegen.errors import GrammarError
from shapegen.grammar import ast

OCCLUSION = ("inside", "overlaps", "touches")

_ONE_LOT = "inter answers as if alone: shapegen derives one lot at a time"
#: Builtins compiled here that differ from the reference, in a few words.
PARTIAL_FUNCTIONS: dict[str, str] = dict.fromkeys((*OCCLUSION, *CONTEXT_QUERIES), _ONE_LOT)


class BuiltinCalls:
    """The compilers of one grammar's calls of these builtins.

    Parameters
    ----------
    compile
        ``compile(node, params)``: the grammar's expression compiler, for an argument compiled
        here (a query's label).
    error
        ``error(node, message)``: the grammar's error at a node (file, line, column and caret).
    files
        The project's file functions (``file_search.file_functions``): ``fileRandom`` for
        ``fileRandom()``.
    """

    def __init__(self, compile: Callable, error: Callable[..., GrammarError], files: dict):
        self.compile = compile
        self.error = error
        self.files = files

    def pure(self, node, function, arguments: tuple, *, with_state: bool = False):
        """``function(*values)`` (``function(state, *values)`` with ``with_state``); its
        ValueError is the user's message, located at the call."""
        error = self.error
        name = node.name

        def failed(exc, values) -> Exception:
            message = str(exc) if isinstance(exc, ValueError) else None
            if message and with_state:
                message = f"{name}(): {message}"
            if not message:
                shown = ", ".join(format_value(v) for v in values)
                message = f"{name}({shown}) is not defined"
            return error(node, message)

        if not with_state and len(arguments) == 1:  # float(x), str(x)...: one argument
            (only,) = arguments

            def call_one(args, state):
                value = only(args, state)
                try:
                    return function(value)
                except (ValueError, TypeError, OverflowError, ZeroDivisionError) as exc:
                    raise failed(exc, [value]) from None

            return call_one

        def call(args, state):
            values = [a(args, state) for a in arguments]
            try:
                return function(state, *values) if with_state else function(*values)
            except (ValueError, TypeError, OverflowError, ZeroDivisionError) as exc:
                raise failed(exc, values) from None

        return call

    def random_choice(self, node, name: str, arguments: tuple):
        error = self.error
        files = self.files

        def call(args, state):
            value = arguments[0](args, state)
            if name == "p":
                if type(value) is not float:
                    raise error(node, f"p() needs a probability (a number), got {type_name(value)}")
                return state.random() < value
            if type(value) is not str:
                raise error(node, f"{name}() needs a string, got a {type_name(value)}")
            try:
                items = files["fileRandom"](value) if name == "fileRandom" else _list(value)
            except ValueError as exc:
                raise error(node, str(exc)) from None
            if not items:
                return ""
            return items[min(int(state.random() * len(items)), len(items) - 1)]

        return call

    def printed(self, node, arguments: tuple):
        def call(args, state):
            value = arguments[0](args, state)
            print(format_value(value))
            return value

        return call

    def occlusion(self, node, params):
        name = node.name
        target = "all"
        label = None
        if node.args:
            first = node.args[0]
            if not (isinstance(first, ast.Name) and first.name in ("intra", "inter", "all")):
                raise self.error(node, f"{name}()'s target is intra, inter or all")
            target = first.name
        if len(node.args) == 2:
            label = self.compile(node.args[1], params)
        error = self.error

        def call(args, state):
            try:
                from shapegen.engine.derivation import occlusion
            except ImportError:
                raise error(node, f"{name}() is not supported by shapegen") from None
            query = getattr(occlusion, name)
            if label is None:
                return query(state, target)
            return query(state, target, label(args, state))

        return call

    def context(self, node, params):
        name = node.name
        _, count = CONTEXT_QUERIES[name]
        if len(node.args) != count:
            raise self.error(node, f"{name}() takes {count} arguments, got {len(node.args)}")
        first = node.args[0]
        if not (isinstance(first, ast.Name) and first.name in ("intra", "inter", "all")):
            raise self.error(node, f"{name}()'s target is intra, inter or all")
        target = first.name
        label = self.compile(node.args[1], params)
        comparison = ""
        if count == 3:
            third = node.args[2]
            if not (isinstance(third, ast.Name) and third.name in COMPARISONS):
                raise self.error(
                    node, f"{name}()'s comparison is one of {', '.join(sorted(COMPARISONS))}"
                )
            comparison = third.name
        error = self.error

        def call(args, state):
            try:
                return context_query(name, state, target, label(args, state), comparison)
            except GrammarError as exc:
                raise error(node, str(exc)) from None

        return call


def _list(text: str) -> list[str]:
    """The items of a CGA string list (``"a;b;c;"``)."""
    items = text.split(";")
    if items and items[-1] == "":
        items.pop()
    return items
