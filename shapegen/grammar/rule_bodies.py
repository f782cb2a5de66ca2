"""Rule-body nodes of the .grammar AST: the operations and successors of a sequence, and the
sequence, conditional and stochastic bodies that hold them.

The whole tree is described in :mod:`shapegen.grammar.ast`, which re-exports these classes.
"""

from __future__ import annotations

import dataclasses
from dataclasses import field
from typing import Literal

from shapegen.errors import SourceLocation
from shapegen.grammar.expressions import Expression, Keyword
from shapegen.grammar.tree import location_field, node

__all__ = [
    "BlockEntry",
    "Body",
    "CallArgument",
    "Center",
    "Comp",
    "CompBranch",
    "ConditionalBody",
    "ConditionalBranch",
    "Coordinate",
    "DynamicImport",
    "EntryGroup",
    "Extrude",
    "Insert",
    "Item",
    "Label",
    "Nil",
    "Operation",
    "OperationArgument",
    "OperationBranch",
    "Print",
    "Push",
    "Report",
    "Rotate",
    "Scale",
    "Sequence",
    "Set",
    "SizeMode",
    "Split",
    "SplitGroup",
    "SplitEntry",
    "StochasticBody",
    "StochasticBranch",
    "Successor",
    "Translate",
]


# --------------------------------------------------------------------------------------------
# Operations and successors (items of a sequence)


@node
class Coordinate:
    """One component of ``t`` or ``s``; ``relative`` for the ``'`` prefix (fraction of scope)."""

    value: Expression
    relative: bool = False
    location: SourceLocation = location_field()


@node
class Successor:
    """``Name``, ``Name(args)`` or the explicit leaf ``Name.`` (``leaf=True``); ``called`` is
    True when written with parentheses (``Name()``), which a rule must then define."""

    name: str
    args: tuple[Expression, ...] = ()
    leaf: bool = False
    called: bool = field(default=False, compare=False)
    location: SourceLocation = location_field()


@node
class Nil:
    """``NIL``: the current shape is deleted."""

    location: SourceLocation = location_field()


@node
class Push:
    """``[ body ]``: apply ``body`` to a copy of the shape state, then resume the original."""

    body: Body
    location: SourceLocation = location_field()


@node
class Extrude:
    """``extrude(height)``: ``height`` in metres along the scope's y axis."""

    height: Expression
    location: SourceLocation = location_field()


SizeMode = Literal["absolute", "relative", "floating"]


@node
class SplitEntry:
    """``size : body`` in a split; ``mode`` from the prefix (none, ``'``, ``~``)."""

    size: Expression
    mode: SizeMode
    body: Body
    location: SourceLocation = location_field()


@node
class SplitGroup:
    """``{ part | ... }``, repeated to fill the scope when ``repeat`` (``{ ... }*``)."""

    parts: tuple[SplitEntry | SplitGroup, ...]
    repeat: bool = False
    location: SourceLocation = location_field()


@node
class Split:
    """``split(axis) { ... }``: ``axis`` is ``"x"``, ``"y"`` or ``"z"``; ``adjust`` False for
    ``split(axis, noAdjust)`` (the pieces keep the cut scope, not one fitted to their geometry)."""

    axis: Literal["x", "y", "z"]
    group: SplitGroup
    adjust: bool = True
    #: For a UV split (``split(u|v, space, uvSet)``): ``"unitSpace"`` or ``"uvSpace"``.
    texture: str | None = None
    location: SourceLocation = location_field()


@node
class CompBranch:
    """``selector : body`` (or ``selector = body`` with ``merge=True``) in ``comp(f)``;
    ``connected`` for ``selector =: body`` (CGA 2025.0: a shape per connected set of the selected
    faces; ``merge`` is set too)."""

    selector: str
    body: Body
    merge: bool = False
    location: SourceLocation = location_field()
    connected: bool = False


@node
class Comp:
    """``comp(f) { selector : body | ... }``: faces to 2D shapes, selectors exclusive in order."""

    kind: Literal["f"]
    branches: tuple[CompBranch, ...]
    location: SourceLocation = location_field()


@node
class Translate:
    """``t(x, y, z)`` along the scope axes, metres (or fraction of the scope size with ``'``)."""

    x: Coordinate
    y: Coordinate
    z: Coordinate
    location: SourceLocation = location_field()


@node
class Rotate:
    """``r(x, y, z)`` in degrees; ``pivot`` is ``"center"`` for ``r(scopeCenter, x, y, z)``."""

    x: Expression
    y: Expression
    z: Expression
    pivot: Literal["origin", "center"] = "origin"
    location: SourceLocation = location_field()


@node
class Scale:
    """``s(x, y, z)``: new scope size, metres (or fraction of the current size with ``'``)."""

    x: Coordinate
    y: Coordinate
    z: Coordinate
    location: SourceLocation = location_field()


@node
class Center:
    """``center(axes)``: centre the scope in the parent's scope along ``axes`` (e.g. ``"xz"``)."""

    axes: str
    location: SourceLocation = location_field()


@node
class Label:
    """``label(name)``: tag the shape (and every block below it) with ``name``."""

    name: Expression
    location: SourceLocation = location_field()


@node
class Set:
    """``set(attribute, value)``: override ``attribute`` for the current shape's subtree."""

    attribute: str
    value: Expression
    location: SourceLocation = location_field()


@node
class Insert:
    """``i(primitive, key=value, ...)``: insert a template primitive sized to the scope."""

    primitive: Expression
    parameters: tuple[Keyword, ...] = ()
    location: SourceLocation = location_field()
    options: tuple[Expression, ...] = ()  # an asset's upAxis, insertMode, cleanupMode (op_i)


@node
class Print:
    """``print(value, ...)``."""

    values: tuple[Expression, ...]
    location: SourceLocation = location_field()


@node
class Report:
    """``report(key, value)``: add ``value`` under ``key`` in the build report."""

    key: Expression
    value: Expression
    location: SourceLocation = location_field()


@node
class OperationArgument:
    """One argument of a generic :class:`Operation` call: ``kind`` is ``"plain"``,
    ``"relative"`` (``'x``), ``"floating"`` (``~x``) or ``"keyword"`` (``name=x``, with
    ``name``)."""

    kind: Literal["plain", "relative", "floating", "keyword"]
    value: Expression
    name: str | None = None
    location: SourceLocation = location_field()


@node
class OperationBranch:
    """``key : body`` (``key = body`` with ``merge``) in the ``{ ... }`` block of a generic
    :class:`Operation` (``offset(-1) { inside : A | border : B }``, ``setback(2) { front : A |
    remainder : B }``, ``comp(e) { all : E }``). ``key`` is the expression before the colon,
    usually a :class:`~shapegen.grammar.expressions.Name` selector; ``mode`` its prefix. ``key``
    is None for scatter's block of operations without keys (``scatter(surface, 10, uniform)
    { Tree }``). splitAndSetbackPerimeter's second block (``{ remainder : ops }``) follows the
    first block's branches, keyed ``remainder``."""

    key: Expression | None
    mode: SizeMode
    body: Body
    merge: bool = False
    location: SourceLocation = location_field()
    #: ``=:`` (comp, modify: connected components, CGA 2025.0; ``merge`` is set too)
    connected: bool = False
    #: splitAndSetbackPerimeter's ``length : depth : operations``: the depth expression
    depth: Expression | None = None


@node
class Operation:
    """A CityEngine operation without a node of its own: ``name(arguments) { branches }``.

    The parser makes one for every name in :data:`shapegen.grammar.names.CGA_OPERATIONS` that
    is not one of the dedicated nodes above (``color("#ff0000")``, ``offset(-1) { ... }``,
    ``roofHip(30)``, ``alignScopeToAxes(y)``...); the interpreter dispatches on ``name``.
    ``repeat`` is set for a trailing ``*`` after the block.
    """

    name: str
    arguments: tuple[OperationArgument, ...] = ()
    branches: tuple[OperationBranch, ...] = ()
    repeat: bool = False
    location: SourceLocation = location_field()


@node
class DynamicImport:
    """``prefix(attr = value, ...).Rule(args)``: the imported rule set re-initialised with these
    values for one invocation (import.html, dynamic imports). Only the parser makes it; merging
    the imports (:mod:`shapegen.grammar.imports`) replaces it by a :class:`Push` that sets every
    attr of the import (``overrides`` where given, else its own definition, in dependency order)
    and calls ``prefix.Rule``, so the interpreter never meets one."""

    prefix: str
    overrides: tuple[Keyword, ...]
    rule: str
    args: tuple[Expression, ...] = ()
    location: SourceLocation = location_field()


Item = (
    Successor
    | Operation
    | Nil
    | Push
    | Extrude
    | Split
    | Comp
    | Translate
    | Rotate
    | Scale
    | Center
    | Label
    | Set
    | Insert
    | Print
    | Report
)


# --------------------------------------------------------------------------------------------
# Rule bodies


@node
class Sequence:
    """Items applied left to right to the current shape."""

    items: tuple[Item, ...]
    location: SourceLocation = location_field()


@node
class ConditionalBranch:
    """``case condition : body``."""

    condition: Expression
    body: Body
    location: SourceLocation = location_field()


@node
class ConditionalBody:
    """``case ... : body ... else : body``; the first true condition wins."""

    branches: tuple[ConditionalBranch, ...]
    otherwise: Body
    location: SourceLocation = location_field()


@node
class StochasticBranch:
    """``30% : body``; ``percent`` in percent."""

    percent: float
    body: Body
    location: SourceLocation = location_field()


@node
class StochasticBody:
    """``30% : body 20% : body else : body``, drawn with the derivation's seeded generator."""

    branches: tuple[StochasticBranch, ...]
    otherwise: Body
    location: SourceLocation = location_field()


Body = Sequence | ConditionalBody | StochasticBody


# --------------------------------------------------------------------------------------------
# An operation call before it is known which operation it is: what the parser's transformer
# hands to :class:`~shapegen.grammar.operation_calls.OperationCalls`, which turns it into one of
# the nodes above. No finished tree holds these.


@dataclasses.dataclass(frozen=True)
class CallArgument:
    """One argument of an operation call: ``kind`` says how it was written (``"plain"``,
    ``"relative"`` for ``'x``, ``"floating"`` for ``~x``, ``"keyword"`` for ``name = x``)."""

    kind: str
    value: Expression
    location: SourceLocation
    name: str | None = None


@dataclasses.dataclass(frozen=True)
class BlockEntry:
    """``size : body`` (``selector = body`` with ``merge``) before split or comp claims it."""

    mode: SizeMode
    key: Expression
    body: Body
    merge: bool
    location: SourceLocation
    connected: bool = False  # ``=:``
    depth: Expression | None = None  # splitAndSetbackPerimeter's ``length : depth : ops``


@dataclasses.dataclass(frozen=True)
class EntryGroup:
    """``{ entry | ... }``; ``repeat`` for a trailing ``*``."""

    entries: tuple[BlockEntry | EntryGroup, ...]
    repeat: bool
    location: SourceLocation
