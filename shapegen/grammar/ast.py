"""Abstract syntax tree of the .grammar language: frozen dataclasses, one per construct.

The parser (:mod:`shapegen.grammar.parser`) turns a .grammar text into a :class:`RuleFile`; the
interpreter walks these nodes and never sees a parse tree. Every node carries the place it came
from in ``location`` (a :class:`~shapegen.errors.SourceLocation`, keyword-only, excluded from
equality so that two trees with the same structure compare equal wherever they were written).

The classes live in :mod:`~shapegen.grammar.expressions` (expressions),
:mod:`~shapegen.grammar.rule_bodies` (operations, successors and rule bodies) and
:mod:`~shapegen.grammar.definitions` (annotations, definitions and the file), over the shared
node machinery of :mod:`~shapegen.grammar.tree`; this module gathers them under one name.

File and definitions
--------------------
:class:`RuleFile`
    The whole file: ``version`` (the text of ``version "..."`` or None), ``definitions`` (every
    :class:`Attribute`, :class:`Constant`, :class:`Function` and :class:`Rule` in source order),
    ``filename`` and ``source`` (the text, for error carets). Properties ``attrs``, ``consts``,
    ``functions``, ``rules`` filter ``definitions``; ``rule(name)``, ``start_rule``.
:class:`Annotation`
    ``@Name`` or ``@Name(args, key=value)`` in front of a definition: ``@StartRule``,
    ``@Range(min=0, max=10)`` or ``@Range(0, 10)``, ``@Hidden``, ``@Description("...")``,
    ``@Free``, ``@Lot(width, depth)``. ``args`` are positional expressions, ``keywords`` named ones.
:class:`Attribute`
    ``attr name = expr``: a parameter that callers may override (``--set``, Python API).
:class:`Constant`
    ``const name = expr``: evaluated once, not overridable.
:class:`Function`
    ``name(a, b) = expr`` (or ``name = expr`` without parameters, as in CGA). The body is an
    expression, possibly a :class:`CaseExpression` or :class:`StochasticExpression`.
:class:`Rule`
    ``Name --> body`` or ``Name(a, b) --> body``. The body is a :class:`Body`.
:class:`Parameter`
    One formal parameter of a function or rule.

Rule bodies
-----------
``Body = Sequence | ConditionalBody | StochasticBody``

:class:`Sequence`
    Operations and successors applied left to right to the current shape: ``extrude(3) A B``.
:class:`ConditionalBody`
    ``case cond : body  case cond : body ... else : body`` (``else`` required, as in CGA).
:class:`StochasticBody`
    ``30% : body  20% : body ... else : body``; ``percent`` is in percent (30.0 for ``30%``).

Items of a sequence (``Item``)
------------------------------
:class:`Successor`
    ``Name``, ``Name(args)`` or the explicit leaf ``Name.`` (``leaf=True``). A name without a rule
    is a leaf shape (not an error).
:class:`Push`
    ``[ body ]``: save the shape state, apply ``body``, restore.
:class:`Nil`
    ``NIL``: delete the current shape.
:class:`Extrude`
    ``extrude(h)``: ``height`` in metres along the scope's y axis.
:class:`Split`
    ``split(x) { size : body | ... }`` with ``axis`` in ``"x"``, ``"y"``, ``"z"``; the top-level
    pattern is ``group`` (a :class:`SplitGroup`, whose ``repeat`` is set for ``{ ... }*``).
:class:`SplitGroup`
    ``{ part | part | ... }`` with ``repeat`` for a trailing ``*``; parts are :class:`SplitEntry`
    or nested :class:`SplitGroup` (``{ 1 : A | { 2 : B }* | 1 : C }``).
:class:`SplitEntry`
    ``size : body``; ``mode`` is ``"absolute"`` (``3``), ``"relative"`` (``'0.3``, a fraction of
    the scope size) or ``"floating"`` (``~3``); ``size`` is the expression after the prefix.
:class:`Comp`
    ``comp(f) { front : A | side : B | ... }``: ``kind`` is ``"f"`` (faces); branches are
    :class:`CompBranch` (``selector`` in front back left right top bottom side vertical
    horizontal all, or a face index written as digits, ``"0"``; ``merge`` is True for the CGA
    form ``side = B``, one shape of all selected faces).
:class:`Translate`, :class:`Scale`
    ``t(x, y, z)`` and ``s(x, y, z)``; each component is a :class:`Coordinate`, whose
    ``relative`` flag marks the ``'`` prefix (a fraction of the current scope size).
:class:`Rotate`
    ``r(x, y, z)`` in degrees about the scope origin, or ``r(scopeCenter, x, y, z)`` about its
    centre (``pivot`` ``"origin"`` or ``"center"``).
:class:`Center`
    ``center(xz)``: ``axes`` is one of ``x y z xy xz yz xyz``.
:class:`Label`
    ``label("column")``: adds a label to the shape and the blocks below it.
:class:`Set`
    ``set(attr, value)``: overrides an attribute for the current shape's subtree.
:class:`Insert`
    ``i("box", key=value, ...)``: insert a template primitive sized to the scope.
:class:`Operation`
    Every other CityEngine operation, generic: ``name``, ``arguments``
    (:class:`OperationArgument`), ``branches`` (:class:`OperationBranch`) and ``repeat``.
:class:`Print`
    ``print(expr, ...)``: print values while deriving.
:class:`Report`
    ``report("key", value)``: collect a value into the build report.

Expressions (``Expression``)
----------------------------
:class:`Number` (float), :class:`String`, :class:`Boolean`, :class:`Name` (attribute, constant,
parameter or parameterless function), :class:`ShapeAttribute` (``scope.sx``, ``split.index``,
``comp.total``...), :class:`Unary` (``-``, ``+``, ``!``), :class:`Binary` (``+ - * / %``,
``== != < <= > >=``, ``&& ||``; ``+`` concatenates when either side is a string), :class:`Call`
(builtin or user function), :class:`CaseExpression` and :class:`StochasticExpression` (function
bodies ``case a > 1 : 2 else : 3`` and ``30% : 1 else : 2``).

Operation calls before they are known
-------------------------------------
:class:`CallArgument`, :class:`BlockEntry` and :class:`EntryGroup` hold a call's arguments and
``{ ... }`` block as written, while the parser's transformer hands them to
:class:`~shapegen.grammar.operation_calls.OperationCalls`, which makes one of the nodes above of
them; no finished tree holds them.

Walking the tree
----------------
:func:`children` gives the nodes directly below a node, in field order; :func:`walk` gives a
node and every node below it. Checks that look for one kind of node (every :class:`Name`, every
:class:`Successor`) filter ``walk(...)`` instead of spelling out the tree's shape again.
"""

from __future__ import annotations

# the node classes live in three modules; this one gathers their names (each module's
# __all__), so that a new node is listed once, where it is defined
from shapegen.grammar import definitions, expressions, rule_bodies
from shapegen.grammar.definitions import *  # noqa: F403
from shapegen.grammar.expressions import *  # noqa: F403
from shapegen.grammar.rule_bodies import *  # noqa: F403
from shapegen.grammar.tree import NOWHERE, children, node, walk

__all__ = [
    "NOWHERE",
    "children",
    "node",
    "walk",
    *definitions.__all__,
    *expressions.__all__,
    *rule_bodies.__all__,
]
