"""Abstract syntax tree of the .grammar language: frozen dataclasses, one per construct.

The parser (:mod:`shapegen.grammar.parser`) turns a .grammar text into a :class:`Grammar`; the
interpreter walks these nodes and never sees a parse tree. Every node carries the place it came
from in ``location`` (a :class:`~shapegen.errors.SourceLocation`, keyword-only, excluded from
equality so that two trees with the same structure compare equal wherever they were written).

File and definitions
--------------------
:class:`Grammar`
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
    ``{ part | part | ... }`` with ``repeat`` for a trailing ``*``; parts are :class:`SplitPart`
    or nested :class:`SplitGroup` (``{ 1 : A | { 2 : B }* | 1 : C }``).
:class:`SplitPart`
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

Walking the tree
----------------
:func:`children` gives the nodes directly below a node, in field order; :func:`walk` gives a
node and every node below it. Checks that look for one kind of node (every :class:`Name`, every
:class:`Successor`) filter ``walk(...)`` instead of spelling out the tree's shape again.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, fields
from typing import Literal

from shapegen.errors import SourceLocation

__all__ = [
    "NOWHERE",
    "Annotation",
    "Attribute",
    "Binary",
    "Body",
    "Boolean",
    "Call",
    "CaseBranch",
    "CaseExpression",
    "Center",
    "Comp",
    "CompBranch",
    "ConditionalBody",
    "ConditionalBranch",
    "Constant",
    "Coordinate",
    "Definition",
    "Expression",
    "Extrude",
    "Function",
    "Grammar",
    "Insert",
    "Item",
    "Keyword",
    "Label",
    "Name",
    "Nil",
    "Number",
    "Parameter",
    "Print",
    "Push",
    "Report",
    "Rotate",
    "Rule",
    "Scale",
    "Sequence",
    "Set",
    "ShapeAttribute",
    "SizeMode",
    "Split",
    "SplitGroup",
    "SplitPart",
    "StochasticBody",
    "StochasticBranch",
    "StochasticExpression",
    "StochasticValue",
    "String",
    "Successor",
    "Translate",
    "Unary",
    "children",
    "walk",
]

#: Placeholder location for nodes built by hand (tests, programmatic grammars).
NOWHERE = SourceLocation("<unknown>", 0, 0)


def _location():
    return field(default=NOWHERE, compare=False, repr=False, kw_only=True)


# Per node class, the names of the fields that may hold nodes (not its location).
_NODE_FIELDS: dict[type, tuple[str, ...]] = {}


def node(cls: type) -> type:
    """Make ``cls`` a frozen dataclass and an AST node that :func:`walk` descends into."""
    cls = dataclass(frozen=True)(cls)
    _NODE_FIELDS[cls] = tuple(f.name for f in fields(cls) if f.name != "location")
    return cls


def children(tree: object) -> Iterator[object]:
    """The nodes directly below ``tree``, in field order (tuples item by item)."""
    for name in _NODE_FIELDS.get(type(tree), ()):
        value = getattr(tree, name)
        if type(value) in _NODE_FIELDS:
            yield value
        elif isinstance(value, tuple):
            yield from (item for item in value if type(item) in _NODE_FIELDS)


def walk(tree: object) -> Iterator[object]:
    """``tree`` and every node below it, depth first, each node's children in field order.

    Field order is source order, except that a definition's annotations come after its value or
    body. Iterative, so a deeply nested expression (``1 + 1 + ... + 1``) does not reach Python's
    recursion limit.
    """
    stack = [tree]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(reversed(tuple(children(current))))


# --------------------------------------------------------------------------------------------
# Expressions


@node
class Number:
    """A numeric literal (always a float; ``3`` is ``3.0``)."""

    value: float
    location: SourceLocation = _location()


@node
class String:
    """A string literal, escapes resolved."""

    value: str
    location: SourceLocation = _location()


@node
class Boolean:
    """``true`` or ``false``."""

    value: bool
    location: SourceLocation = _location()


@node
class Name:
    """A reference to a parameter, attribute, constant or parameterless function."""

    name: str
    location: SourceLocation = _location()


@node
class ShapeAttribute:
    """A property of the current shape: ``scope.sx``, ``split.index``, ``comp.total``...

    ``obj`` is the part before the dot (``"scope"``, ``"split"``, ``"comp"``) and ``field`` the
    part after it; valid pairs are listed in :data:`shapegen.grammar.names.SHAPE_ATTRIBUTES`.
    """

    obj: str
    field: str
    location: SourceLocation = _location()


@node
class Unary:
    """``-x``, ``+x`` or ``!x``."""

    op: Literal["-", "+", "!"]
    operand: Expression
    location: SourceLocation = _location()


@node
class Binary:
    """``left op right`` with op one of ``+ - * / % == != < <= > >= && ||``."""

    op: str
    left: Expression
    right: Expression
    location: SourceLocation = _location()


@node
class Call:
    """A call of a builtin function (``sin``, ``rand``...) or a user function."""

    name: str
    args: tuple[Expression, ...]
    location: SourceLocation = _location()


@node
class CaseBranch:
    """``case condition : value`` inside a :class:`CaseExpression`."""

    condition: Expression
    value: Expression
    location: SourceLocation = _location()


@node
class CaseExpression:
    """``case c1 : v1 case c2 : v2 ... else : v`` as a function body; first true branch wins."""

    branches: tuple[CaseBranch, ...]
    otherwise: Expression
    location: SourceLocation = _location()


@node
class StochasticValue:
    """``30% : value`` inside a :class:`StochasticExpression`; ``percent`` in percent."""

    percent: float
    value: Expression
    location: SourceLocation = _location()


@node
class StochasticExpression:
    """``30% : v1 20% : v2 else : v`` as a function body; the ``else`` takes the remainder."""

    branches: tuple[StochasticValue, ...]
    otherwise: Expression
    location: SourceLocation = _location()


Expression = (
    Number
    | String
    | Boolean
    | Name
    | ShapeAttribute
    | Unary
    | Binary
    | Call
    | CaseExpression
    | StochasticExpression
)


# --------------------------------------------------------------------------------------------
# Operations and successors (items of a sequence)


@node
class Keyword:
    """``name = value`` argument (of ``i(...)`` and of annotations)."""

    name: str
    value: Expression
    location: SourceLocation = _location()


@node
class Coordinate:
    """One component of ``t`` or ``s``; ``relative`` for the ``'`` prefix (fraction of scope)."""

    value: Expression
    relative: bool = False
    location: SourceLocation = _location()


@node
class Successor:
    """``Name``, ``Name(args)`` or the explicit leaf ``Name.`` (``leaf=True``)."""

    name: str
    args: tuple[Expression, ...] = ()
    leaf: bool = False
    location: SourceLocation = _location()


@node
class Nil:
    """``NIL``: the current shape is deleted."""

    location: SourceLocation = _location()


@node
class Push:
    """``[ body ]``: apply ``body`` to a copy of the shape state, then resume the original."""

    body: Body
    location: SourceLocation = _location()


@node
class Extrude:
    """``extrude(height)``: ``height`` in metres along the scope's y axis."""

    height: Expression
    location: SourceLocation = _location()


SizeMode = Literal["absolute", "relative", "floating"]


@node
class SplitPart:
    """``size : body`` in a split; ``mode`` from the prefix (none, ``'``, ``~``)."""

    size: Expression
    mode: SizeMode
    body: Body
    location: SourceLocation = _location()


@node
class SplitGroup:
    """``{ part | ... }``, repeated to fill the scope when ``repeat`` (``{ ... }*``)."""

    parts: tuple[SplitPart | SplitGroup, ...]
    repeat: bool = False
    location: SourceLocation = _location()


@node
class Split:
    """``split(axis) { ... }``: ``axis`` is ``"x"``, ``"y"`` or ``"z"``."""

    axis: Literal["x", "y", "z"]
    group: SplitGroup
    location: SourceLocation = _location()


@node
class CompBranch:
    """``selector : body`` (or ``selector = body`` with ``merge=True``) in ``comp(f)``."""

    selector: str
    body: Body
    merge: bool = False
    location: SourceLocation = _location()


@node
class Comp:
    """``comp(f) { selector : body | ... }``: faces to 2D shapes, selectors exclusive in order."""

    kind: Literal["f"]
    branches: tuple[CompBranch, ...]
    location: SourceLocation = _location()


@node
class Translate:
    """``t(x, y, z)`` along the scope axes, metres (or fraction of the scope size with ``'``)."""

    x: Coordinate
    y: Coordinate
    z: Coordinate
    location: SourceLocation = _location()


@node
class Rotate:
    """``r(x, y, z)`` in degrees; ``pivot`` is ``"center"`` for ``r(scopeCenter, x, y, z)``."""

    x: Expression
    y: Expression
    z: Expression
    pivot: Literal["origin", "center"] = "origin"
    location: SourceLocation = _location()


@node
class Scale:
    """``s(x, y, z)``: new scope size, metres (or fraction of the current size with ``'``)."""

    x: Coordinate
    y: Coordinate
    z: Coordinate
    location: SourceLocation = _location()


@node
class Center:
    """``center(axes)``: centre the scope in the parent's scope along ``axes`` (e.g. ``"xz"``)."""

    axes: str
    location: SourceLocation = _location()


@node
class Label:
    """``label(name)``: tag the shape (and every block below it) with ``name``."""

    name: Expression
    location: SourceLocation = _location()


@node
class Set:
    """``set(attribute, value)``: override ``attribute`` for the current shape's subtree."""

    attribute: str
    value: Expression
    location: SourceLocation = _location()


@node
class Insert:
    """``i(primitive, key=value, ...)``: insert a template primitive sized to the scope."""

    primitive: Expression
    parameters: tuple[Keyword, ...] = ()
    location: SourceLocation = _location()


@node
class Print:
    """``print(value, ...)``."""

    values: tuple[Expression, ...]
    location: SourceLocation = _location()


@node
class Report:
    """``report(key, value)``: add ``value`` under ``key`` in the build report."""

    key: Expression
    value: Expression
    location: SourceLocation = _location()


Item = (
    Successor
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
    location: SourceLocation = _location()


@node
class ConditionalBranch:
    """``case condition : body``."""

    condition: Expression
    body: Body
    location: SourceLocation = _location()


@node
class ConditionalBody:
    """``case ... : body ... else : body``; the first true condition wins."""

    branches: tuple[ConditionalBranch, ...]
    otherwise: Body
    location: SourceLocation = _location()


@node
class StochasticBranch:
    """``30% : body``; ``percent`` in percent."""

    percent: float
    body: Body
    location: SourceLocation = _location()


@node
class StochasticBody:
    """``30% : body 20% : body else : body``, drawn with the derivation's seeded generator."""

    branches: tuple[StochasticBranch, ...]
    otherwise: Body
    location: SourceLocation = _location()


Body = Sequence | ConditionalBody | StochasticBody


# --------------------------------------------------------------------------------------------
# Definitions and the file


@node
class Annotation:
    """``@Name`` or ``@Name(args, key=value)``."""

    name: str
    args: tuple[Expression, ...] = ()
    keywords: tuple[Keyword, ...] = ()
    location: SourceLocation = _location()

    def argument(self, keyword: str, position: int) -> Expression | None:
        """The argument given as ``keyword=...`` or else at ``position``, or None."""
        for kw in self.keywords:
            if kw.name == keyword:
                return kw.value
        if 0 <= position < len(self.args):
            return self.args[position]
        return None


class _Annotated:
    """Lookup of annotations on a definition."""

    annotations: tuple[Annotation, ...]

    def annotation(self, name: str) -> Annotation | None:
        """The first annotation called ``name`` (without ``@``), or None."""
        for annotation in self.annotations:
            if annotation.name == name:
                return annotation
        return None

    def has_annotation(self, name: str) -> bool:
        return self.annotation(name) is not None


@node
class Parameter:
    """A formal parameter of a function or rule."""

    name: str
    location: SourceLocation = _location()


@node
class Attribute(_Annotated):
    """``attr name = value``."""

    name: str
    value: Expression
    annotations: tuple[Annotation, ...] = ()
    location: SourceLocation = _location()

    @property
    def range(self) -> tuple[Expression, Expression] | None:
        """The ``(min, max)`` expressions of its ``@Range``, or None without one."""
        annotation = self.annotation("Range")
        if annotation is None:
            return None
        low = annotation.argument("min", 0)
        high = annotation.argument("max", 1)
        if low is None or high is None:
            return None
        return low, high

    @property
    def free(self) -> bool:
        """True for an ``@Free`` attribute (a parameter the optimizer may change)."""
        return self.has_annotation("Free")


@node
class Constant(_Annotated):
    """``const name = value``."""

    name: str
    value: Expression
    annotations: tuple[Annotation, ...] = ()
    location: SourceLocation = _location()


@node
class Function(_Annotated):
    """``name(params) = body`` (``params`` may be empty)."""

    name: str
    params: tuple[Parameter, ...]
    body: Expression
    annotations: tuple[Annotation, ...] = ()
    location: SourceLocation = _location()


@node
class Rule(_Annotated):
    """``Name(params) --> body``."""

    name: str
    params: tuple[Parameter, ...]
    body: Body
    annotations: tuple[Annotation, ...] = ()
    location: SourceLocation = _location()

    @property
    def start(self) -> bool:
        """True for an ``@StartRule`` rule."""
        return self.has_annotation("StartRule")


Definition = Attribute | Constant | Function | Rule


@node
class Grammar:
    """A whole .grammar file.

    Attributes
    ----------
    definitions : tuple
        Every attr, const, function and rule, in source order.
    version : str or None
        The text of the ``version "..."`` line.
    filename : str
        Name used in error messages.
    source : str
        The file's text (for error carets); excluded from equality.
    """

    definitions: tuple[Definition, ...]
    version: str | None = None
    filename: str = "<string>"
    source: str = field(default="", compare=False, repr=False)
    location: SourceLocation = _location()

    @property
    def attrs(self) -> tuple[Attribute, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Attribute))

    @property
    def consts(self) -> tuple[Constant, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Constant))

    @property
    def functions(self) -> tuple[Function, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Function))

    @property
    def rules(self) -> tuple[Rule, ...]:
        return tuple(d for d in self.definitions if isinstance(d, Rule))

    def rule(self, name: str) -> Rule | None:
        """The rule called ``name``, or None (a successor without a rule is a leaf)."""
        for definition in self.definitions:
            if isinstance(definition, Rule) and definition.name == name:
                return definition
        return None

    @property
    def start_rule(self) -> Rule | None:
        """The ``@StartRule`` rule, else the first rule, else None."""
        rules = self.rules
        for rule in rules:
            if rule.start:
                return rule
        return rules[0] if rules else None
