"""Compilers of rule bodies and shape operations: each turns an AST node into a closure, at
one width or two.

A compiled operation is called as ``op(state, args, out)``
(:data:`~shapegen.engine.derivation.state.Operation`): it changes the shape ``state``, appends
the successors it creates to ``out`` and returns False when the shape was replaced by others (a
split, a comp...). :class:`OperationCompiler` compiles them for one grammar: a rule body here
(a sequence, ``case``, a stochastic choice), every item of a body through the one registry of
operations (:mod:`~shapegen.engine.operations.registry`: ``extrude`` is found under its name
whether the parser made an :class:`~shapegen.grammar.ast.Extrude` or a generic
:class:`~shapegen.grammar.ast.Operation` of it).

Each compiled body and item also carries its batch form, ``op.batch(batch, out)``: the same
rule on many shapes at once (a city's lots, :mod:`shapegen.engine.batch`), made from the
operation's registered batch form, or one that raises
:class:`~shapegen.engine.operations.registry.Unsupported` (with the reason) where it has none.
The width is chosen by the caller: :meth:`Program.derive
<shapegen.engine.program.interpreter.Program.derive>` calls ``op``,
:func:`~shapegen.engine.batch.lots.derive_lots` calls ``op.batch``.
"""

from __future__ import annotations

__all__ = ["OperationCompiler"]

from collections.abc import Mapping

import numpy as np

# each of these registers its operations (the registry's one-shape and batch forms): those of
# the parser's own nodes here, the others when a rule first names one (cga.register_all)
import shapegen.engine.operations.cga.extrusion  # noqa: F401
import shapegen.engine.operations.cga.splitting  # noqa: F401
import shapegen.engine.operations.cga.topology  # noqa: F401
import shapegen.engine.operations.cga.transforms  # noqa: F401
import shapegen.engine.operations.rule_items  # noqa: F401
import shapegen.engine.operations.template_primitives  # noqa: F401
from shapegen.engine.derivation.cga_errors import carrying_on
from shapegen.engine.derivation.finite import checked_operation, finite_parameter
from shapegen.engine.derivation.random_streams import choice, draw
from shapegen.engine.derivation.state import Operation
from shapegen.engine.expressions.compiler import ExpressionCompiler, type_name
from shapegen.engine.operations.cga import register_all
from shapegen.engine.operations.hole_guard import keeps_holes, refusing_holes
from shapegen.engine.operations.registry import Unsupported, forms_of, value_kind
from shapegen.errors import GrammarError, OperationError
from shapegen.grammar import ast


class OperationCompiler:
    """The compilers of rule bodies, their items and the operations' arguments, for one grammar.

    Parameters
    ----------
    grammar
        The parsed file: its dialect and its file name (where assets are searched from).
    expressions
        The grammar's expression compiler (arguments, conditions, values).
    rules
        ``(name, arity) -> rule`` of the grammar, read when a successor is compiled; a rule's
        ``body`` is read only while deriving, so the rules' bodies may be compiled after.
    """

    def __init__(
        self,
        grammar: ast.RuleFile,
        expressions: ExpressionCompiler,
        rules: Mapping[tuple[str, int], object],
    ):
        self.grammar = grammar
        self.expressions = expressions
        self.rules = rules
        self.arities: dict[str, list[int]] = {}
        for name, arity in rules:
            self.arities.setdefault(name, []).append(arity)
        self.attr_names = frozenset(a.name for a in grammar.attrs)
        self.const_names = frozenset(c.name for c in grammar.consts)
        # CityEngine rule files (.cga) get CityEngine's semantics: its scope after extruding a
        # comp face, its repeat counts, and its leniency (CGA errors carried on past).
        self.cga_dialect = grammar.dialect == "cga"

    def error(self, node, message: str) -> GrammarError:
        """The error at ``node`` of the grammar (file, line, column and caret)."""
        return self.expressions.error(node, message)

    def body(self, node: ast.Body, params: dict[str, int]) -> Operation:
        """The operation of a rule body (a sequence, a case or a stochastic choice) whose
        parameters are ``params`` (name -> index in the arguments), with its batch form."""
        if isinstance(node, ast.Sequence):
            items = tuple(self._item(item, params) for item in node.items)

            def sequence(state, args, out):
                for item in items:
                    if not item(state, args, out):
                        return False
                return True

            sequence.batch = _batch_sequence(tuple(item.batch for item in items))
            return sequence
        if isinstance(node, ast.ConditionalBody):
            branches = [
                (self.expressions.compile(b.condition, params), self.body(b.body, params), b)
                for b in node.branches
            ]
            otherwise = self.body(node.otherwise, params)
            error = self.error

            def conditional(state, args, out):
                for condition, body, branch in branches:
                    test = condition(args, state)
                    if type(test) is not bool:
                        raise error(
                            branch, f"a case condition must be a boolean, got a {type_name(test)}"
                        )
                    if test:
                        return body(state, args, out)
                return otherwise(state, args, out)

            conditional.batch = _batch_conditional(
                [(branch.condition, body.batch) for _, body, branch in branches], otherwise.batch
            )
            return conditional
        if isinstance(node, ast.StochasticBody):
            fractions = tuple(float(b.percent) / 100.0 for b in node.branches)
            bodies = (*(self.body(b.body, params) for b in node.branches),
                      self.body(node.otherwise, params))  # fmt: skip

            def stochastic(state, args, out):
                return bodies[choice(state.random, fractions)](state, args, out)

            stochastic.batch = _batch_stochastic(fractions, [body.batch for body in bodies])
            return stochastic
        raise self.error(node, f"unsupported rule body {type(node).__name__}")

    def _item(self, node, params: dict[str, int]) -> Operation:
        """The operation of one item of a body, through the registry: its one-shape form
        wrapped in the checks every operation gets, and its batch form."""
        forms = forms_of(node)
        if forms is None:
            register_all()
            forms = forms_of(node)
        if forms is None:
            if isinstance(node, ast.Operation):
                raise self.error(
                    node, f"the CGA operation {node.name!r} is not supported by shapegen"
                )
            raise self.error(node, f"unsupported operation {type(node).__name__}")
        operation = checked_operation(self, node, forms.one(self, node, params))
        if not keeps_holes(node):
            operation = refusing_holes(operation, node, self)
        if self.cga_dialect and not isinstance(node, _CANNOT_FAIL):
            operation = carrying_on(operation, node, self)  # CityEngine records a CGA error
        batch = self._batch_item(forms, node, params)
        try:
            if hasattr(operation, "batch"):  # a closure shared by nodes
                raise AttributeError
            operation.batch = batch
        except AttributeError:  # one of its own for this node, to carry its batch form
            operation = _own(operation)
            operation.batch = batch
        return operation

    def _batch_item(self, forms, node, params):
        """The batch form of ``node``'s operation, or one that says why it has none."""
        if forms.batch is None:
            name = node.name if isinstance(node, ast.Operation) else forms.name
            return _unsupported(f"the operation {name}")
        try:
            return forms.batch(self, node, params)
        except Unsupported as exc:
            return _unsupported(str(exc))

    def operation_error(self, node, message: str) -> OperationError:
        """The error of an operation's bad argument or degenerate geometry met while deriving:
        a CGA error that the shape carries on past in a ``.cga`` file
        (engine/derivation/cga_errors.py), an error in a ``.grammar`` file."""
        error = self.error(node, message)
        return OperationError(message, error.location, error.source)

    def number(self, node, expression, params, what: str):
        """A compiled expression that must give a finite number (``what`` names it in the
        error: ``"extrude height"``)."""
        compiled = self.expressions.compile(expression, params)
        error = self.error

        def number(args, state):
            value = compiled(args, state)
            if type(value) is not float:
                raise error(node, f"{what} must be a number, got a {type_name(value)}")
            return finite_parameter(self, node, state, value, what)

        return number


# Items that call no operation of their own: nothing to carry on past.
_CANNOT_FAIL = (ast.Successor, ast.Nil, ast.Push)


def _own(operation: Operation) -> Operation:
    """``operation`` in a closure of its own (to carry one node's batch form)."""

    def own(state, args, out):
        return operation(state, args, out)

    return own


def _unsupported(reason: str):
    def unsupported(batch, out):
        raise Unsupported(reason)

    return unsupported


# ---------------------------------------------------------------------- the bodies' batch forms
# The batch (engine/batch/lots.py's ShapeBatch) is the shapes of many lots standing at the same
# place of their trees; ``case`` and a stochastic choice split it by masks into parts, each part
# derived by its branch (a part a branch cannot derive falls back alone).
def _batch_sequence(items):
    def sequence_batch(batch, out):
        for item in items:
            item(batch, out)
        if not batch.children:  # no successor: the shapes are leaves
            batch.leaf()
        return True

    return sequence_batch


def _batch_conditional(branches, otherwise):
    def conditional_batch(batch, out):
        remaining = np.ones(batch.size, dtype=bool)
        for condition, body in branches:
            if not remaining.any():
                return True
            part = batch.part(remaining)
            test = part.value(condition)
            if value_kind(test) is not bool:
                raise Unsupported("a case condition that is not a boolean")
            chosen = np.zeros(batch.size, dtype=bool)
            chosen[np.flatnonzero(remaining)] = np.broadcast_to(test, (part.size,))
            if chosen.any():
                batch.branch(chosen, body, out)
            remaining &= ~chosen
        if remaining.any():
            batch.branch(remaining, otherwise, out)
        return True

    return conditional_batch


class _LotStream:
    """One lot's stream of the batch's shape, for :func:`random_streams.choice`."""

    __slots__ = ("x",)

    def __init__(self, x: int):
        self.x = x

    def random(self) -> float:
        self.x, u = draw(self.x)
        return u


def _batch_stochastic(fractions, bodies):
    def stochastic_batch(batch, out):
        # the one-shape choice, lot by lot, each from its own stream of this shape
        streams = batch.streams
        picks = np.empty(batch.size, dtype=np.int64)
        for j, k in enumerate(batch.index.tolist()):
            stream = _LotStream(int(streams[k]))
            picks[j] = choice(stream.random, fractions)
            streams[k] = stream.x
        for index, body in enumerate(bodies):
            chosen = picks == index
            if chosen.any():
                batch.branch(chosen, body, out)
        return True

    return stochastic_batch
