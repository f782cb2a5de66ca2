"""The one registry of shape operations: each operation's one-shape form and, where it has one,
its batch form, side by side.

An operation is registered by its CGA name with :func:`operation` on the compiler of its
one-shape form, ``compiler(program, node, params) -> op``, where ``op(state, args, out) -> bool``
is an :data:`~shapegen.engine.derivation.state.Operation` on one
:class:`~shapegen.engine.derivation.state.ShapeState`. ``program`` is the grammar's
:class:`~shapegen.engine.operations.compiler.OperationCompiler`: ``program.expressions`` (compile
an argument), ``program.number(node, expression, params, what)`` (an argument that must be a
finite number), ``program.body(body, params)`` (compile a branch's body),
``program.error(node, message)`` (an error at load time), ``program.operation_error(node,
message)`` (a CGA error while deriving), ``program.cga_dialect`` and ``program.grammar``.

Where the operation can act on many shapes at once (a city's lots standing at one rule, as
:class:`~shapegen.engine.batch.lots.ShapeBatch`), its batch form is registered beside it with
:func:`batch_form`: ``compiler(program, node, params) -> batch_op``, ``batch_op(batch, out)``,
which changes every shape of ``batch`` together and appends the successors it makes to ``out``
as ``(batch, rule)``, or raises :class:`Unsupported` for what it does not implement (those
shapes are derived one at a time, the reason counted). Rule bodies (a sequence, ``case``, a
stochastic choice) have both forms too (:meth:`OperationCompiler.body
<shapegen.engine.operations.compiler.OperationCompiler.body>`), so one compiled rule is derived
at either width.

``node`` is the AST node of a call: a node of its own for the operations the parser knows
(``extrude(h)`` is :class:`~shapegen.grammar.ast.Extrude`, ``comp(f) { ... }``
:class:`~shapegen.grammar.ast.Comp`...), the generic :class:`~shapegen.grammar.ast.Operation`
for the others (``color``, ``offset``, ``extrude(world.up, h)``...). One compiler per name
takes every node of that name (``nodes=``). An operation honoured with a difference from
CityEngine's reference is registered with the difference in a few words, ``partial="..."``;
:func:`partial_notes` lists them (the coverage table of docs/cga-compatibility.md is made from
them).

Importing :mod:`shapegen.engine.operations.compiler` imports every module that registers.
"""

from __future__ import annotations

__all__ = [
    "OperationForms",
    "Unsupported",
    "batch_form",
    "compiler_for",
    "forms_of",
    "is_column",
    "operation",
    "partial_notes",
    "registered_names",
    "value_kind",
    "warn_at",
]

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from shapegen.grammar import ast

Compiler = Callable[..., Callable]


class Unsupported(Exception):
    """What a batch form does not implement (the message says what): derive these shapes one at
    a time."""


def is_column(value) -> bool:
    """Whether a value in a batch differs between its shapes: a numpy column with one entry per
    shape (else one Python value shared by all of them)."""
    return isinstance(value, np.ndarray)


def value_kind(value) -> type:
    """The CGA type of a value in a batch (``float``, ``bool``, ``str``), a column's too."""
    if isinstance(value, np.ndarray):
        return bool if value.dtype == np.bool_ else float
    return type(value)


@dataclass
class OperationForms:
    """One operation's entry: its ``name`` in CGA, the AST node types it is written as, its
    one-shape compiler ``one``, its batch compiler ``batch`` (None: no batch form) and what of
    the reference it does not honour (``partial``)."""

    name: str
    nodes: tuple[type, ...]
    one: Compiler
    batch: Compiler | None = None
    partial: str | None = None


_BY_NAME: dict[str, OperationForms] = {}
_BY_NODE: dict[type, OperationForms] = {}


def operation(
    *names: str,
    nodes: tuple[type, ...] = (ast.Operation,),
    partial: str | dict[str, str] | None = None,
):
    """Register the decorated function as the one-shape compiler of the operations ``names``,
    written as the AST ``nodes`` (a node type of its own takes one name); ``partial`` says what
    of the reference it does not honour (one text for all the names, or per name)."""

    def register(function: Compiler) -> Compiler:
        for name in names:
            if name in _BY_NAME:
                raise AssertionError(f"two compilers for the operation {name!r}")
            note = partial.get(name) if isinstance(partial, dict) else partial
            forms = OperationForms(name, nodes, function, None, note or None)
            _BY_NAME[name] = forms
            for node_type in nodes:
                if node_type is not ast.Operation:
                    if node_type in _BY_NODE:
                        raise AssertionError(f"two compilers for the node {node_type.__name__}")
                    _BY_NODE[node_type] = forms
        return function

    return register


def batch_form(*names: str):
    """Register the decorated function as the batch compiler of the operations ``names``
    (registered already with :func:`operation`, in the same module: the two forms side by
    side)."""

    def register(function: Compiler) -> Compiler:
        for name in names:
            forms = _BY_NAME[name]
            if forms.batch is not None:
                raise AssertionError(f"two batch forms for the operation {name!r}")
            forms.batch = function
        return function

    return register


def forms_of(node) -> OperationForms | None:
    """The registered forms of the operation written as ``node``, or None when shapegen does
    not implement it."""
    if type(node) is ast.Operation:
        forms = _BY_NAME.get(node.name)
        return forms if forms is not None and ast.Operation in forms.nodes else None
    return _BY_NODE.get(type(node))


def compiler_for(name: str) -> Compiler | None:
    """The one-shape compiler of the operation called ``name`` in a rule, or None when shapegen
    does not implement it."""
    forms = _BY_NAME.get(name)
    return forms.one if forms is not None else None


def registered_names() -> list[str]:
    """Every registered operation's name."""
    return sorted(_BY_NAME)


def partial_notes() -> dict[str, str]:
    """``operation -> what of the reference it does not honour``, for those registered so."""
    return {name: forms.partial for name, forms in _BY_NAME.items() if forms.partial}


def warn_at(state, node, message: str) -> None:
    """A warning of the derivation (CityEngine's runtime warns and carries on), located at the
    operation ``node`` as ``file:line:col: message``."""
    location = getattr(node, "location", None)
    state.run.warn(f"{location}: {message}" if location is not None else message)
