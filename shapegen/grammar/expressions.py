"""Expression nodes of the .grammar AST: literals, names, operators, calls, function bodies.

The whole tree is described in :mod:`shapegen.grammar.ast`, which re-exports these classes.
"""

from __future__ import annotations

from typing import Literal

from shapegen.errors import SourceLocation
from shapegen.grammar.tree import location_field, node

__all__ = [
    "ArrayLiteral",
    "Colon",
    "ComponentValue",
    "ComponentValues",
    "Index",
    "Binary",
    "Boolean",
    "Call",
    "CaseBranch",
    "CaseExpression",
    "Expression",
    "Keyword",
    "Name",
    "Number",
    "ShapeAttribute",
    "StochasticExpression",
    "StochasticValue",
    "String",
    "Unary",
]


@node
class Number:
    """A numeric literal (always a float; ``3`` is ``3.0``)."""

    value: float
    location: SourceLocation = location_field()


@node
class String:
    """A string literal, escapes resolved."""

    value: str
    location: SourceLocation = location_field()


@node
class Boolean:
    """``true`` or ``false``."""

    value: bool
    location: SourceLocation = location_field()


@node
class Name:
    """A reference to a parameter, attribute, constant or parameterless function."""

    name: str
    location: SourceLocation = location_field()


@node
class ShapeAttribute:
    """A property of the current shape: ``scope.sx``, ``split.index``, ``comp.total``...

    ``obj`` is the part before the first dot (``"scope"``, ``"split"``, ``"comp"``) and ``field``
    the part after it; valid pairs are listed in :data:`shapegen.grammar.names.SHAPE_ATTRIBUTES`.
    ``args`` holds the arguments of the call form (``geometry.isRectangular(15)``); the call
    without arguments (``geometry.area()``) and the attribute form (``geometry.area``) are one.
    ``seedian`` has ``field`` ``""``.
    """

    obj: str
    field: str
    args: tuple[Expression, ...] = ()
    location: SourceLocation = location_field()


@node
class Unary:
    """``-x``, ``+x`` or ``!x``."""

    op: Literal["-", "+", "!"]
    operand: Expression
    location: SourceLocation = location_field()


@node
class Binary:
    """``left op right`` with op one of ``+ - * / % == != < <= > >= && ||``."""

    op: str
    left: Expression
    right: Expression
    location: SourceLocation = location_field()


@node
class Call:
    """A call of a builtin function (``sin``, ``rand``...) or a user function."""

    name: str
    args: tuple[Expression, ...]
    location: SourceLocation = location_field()


@node
class ArrayLiteral:
    """``[1, 2, 3]`` (one row) or ``[1, 2; 3, 4]`` (rows split by ``;``), as CGA writes arrays.
    An item may be a :class:`Colon` range (``[1:5]``)."""

    rows: tuple[tuple[Expression, ...], ...]
    location: SourceLocation = location_field()


@node
class Colon:
    """``start : stop`` or ``start : step : stop`` inside brackets (``[1:2:9]``, ``a[0:2]``);
    all three None for a lone ``:`` (every row or column of an index)."""

    start: Expression | None
    step: Expression | None
    stop: Expression | None
    location: SourceLocation = location_field()


@node
class Index:
    """``array[i]`` or ``array[row, column]``; an index may be an array or a :class:`Colon`."""

    target: Expression
    indices: tuple[Expression, ...]
    location: SourceLocation = location_field()


@node
class ComponentValue:
    """``selector : value`` (``selector = value`` with ``merge``) in a :class:`ComponentValues`;
    ``connected`` for ``selector =: value`` (CGA 2025.0: one value per connected set of the
    selected components; ``merge`` is set too, as it is the nearest older form)."""

    selector: Expression
    value: Expression
    merge: bool = False
    location: SourceLocation = location_field()
    connected: bool = False


@node
class ComponentValues:
    """The comp function (func_comp): ``comp(fe) { all : 2 }``, an array with one value per
    selected component; ``arguments`` as in the comp operation."""

    arguments: tuple[Expression, ...]
    branches: tuple[ComponentValue, ...]
    location: SourceLocation = location_field()


@node
class CaseBranch:
    """``case condition : value`` inside a :class:`CaseExpression`."""

    condition: Expression
    value: Expression
    location: SourceLocation = location_field()


@node
class CaseExpression:
    """``case c1 : v1 case c2 : v2 ... else : v`` as a function body; first true branch wins."""

    branches: tuple[CaseBranch, ...]
    otherwise: Expression
    location: SourceLocation = location_field()


@node
class StochasticValue:
    """``30% : value`` inside a :class:`StochasticExpression`; ``percent`` in percent."""

    percent: float
    value: Expression
    location: SourceLocation = location_field()


@node
class StochasticExpression:
    """``30% : v1 20% : v2 else : v`` as a function body; the ``else`` takes the remainder."""

    branches: tuple[StochasticValue, ...]
    otherwise: Expression
    location: SourceLocation = location_field()


Expression = (
    Number
    | String
    | Boolean
    | Name
    | ShapeAttribute
    | Unary
    | Binary
    | Call
    | ArrayLiteral
    | Colon
    | Index
    | ComponentValues
    | CaseExpression
    | StochasticExpression
)


# --------------------------------------------------------------------------------------------
# Keyword arguments (of ``i(...)`` and of annotations)


@node
class Keyword:
    """``name = value`` argument (of ``i(...)`` and of annotations)."""

    name: str
    value: Expression
    location: SourceLocation = location_field()
