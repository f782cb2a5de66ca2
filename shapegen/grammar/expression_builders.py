"""Parse tree -> AST for expressions: the builders :class:`~shapegen.grammar.transformer.AstBuilder`
takes for numbers, strings, names (a shape attribute such as ``scope.sx``, a dotted
``prefix.attr``, ``true``/``false``), calls, operators, arrays, indexes and the ``comp()``
function's values."""

from __future__ import annotations

__all__ = ["ExpressionBuilders", "unescape"]

from lark import v_args

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.names import SHAPE_ATTRIBUTES, SHAPE_VALUES


def unescape(literal: str) -> str:
    """The value of a double-quoted string literal (``\\n``, ``\\t``, ``\\"``, ``\\\\``)."""
    escapes = {"n": "\n", "t": "\t", '"': '"', "\\": "\\"}
    out = []
    chars = iter(literal[1:-1])
    for char in chars:
        if char == "\\":
            escaped = next(chars, "")
            if escaped == "u":  # \uXXXX, as CGA writes its NULL string "\ue000"
                digits = "".join(next(chars, "") for _ in range(4))
                try:
                    out.append(chr(int(digits, 16)))
                except ValueError:
                    out.append("\\u" + digits)
                continue
            out.append(escapes.get(escaped, "\\" + escaped))
        else:
            out.append(char)
    return "".join(out)


class ExpressionBuilders:
    """The expression part of the AST builder; the builder provides ``_at`` and ``_problem``."""

    @v_args(meta=True)
    def binary(self, meta, children):
        left, operator, right = children
        return ast.Binary(str(operator), left, right, location=self._at(operator))

    @v_args(meta=True)
    def add_op(self, meta, children):
        return children[0]

    mul_op = add_op
    unary_op = add_op

    @v_args(meta=True)
    def unary(self, meta, children):
        operator, operand = children
        return ast.Unary(str(operator), operand, location=self._at(operator))

    @v_args(meta=True)
    def number(self, meta, children):
        (token,) = children
        return ast.Number(float(token), location=self._at(token))

    @v_args(meta=True)
    def string(self, meta, children):
        (token,) = children
        return ast.String(unescape(token), location=self._at(token))

    @v_args(meta=True)
    def name(self, meta, children):
        (token,) = children
        if token in ("true", "false"):
            return ast.Boolean(token == "true", location=self._at(token))
        return _dotted_name(str(token), (), self._at(token), call=False)

    @v_args(meta=True)
    def call(self, meta, children):
        name, *args = children
        return _dotted_name(str(name), tuple(args), self._at(name), call=True)

    @v_args(meta=True)
    def component_values(self, meta, children):
        name, *rest = children
        args = tuple(c for c in rest if not isinstance(c, ast.ComponentValue))
        branches = tuple(c for c in rest if isinstance(c, ast.ComponentValue))
        if name != "comp":
            self._problem(self._at(name), "only comp() takes a { ... } block in an expression")
        return ast.ComponentValues(args, branches, location=self._at(name))

    @v_args(meta=True)
    def comp_value(self, meta, children):
        return ast.ComponentValue(children[0], children[1], location=self._at(meta))

    @v_args(meta=True)
    def comp_value_merged(self, meta, children):
        return ast.ComponentValue(children[0], children[1], merge=True, location=self._at(meta))

    @v_args(meta=True)
    def comp_value_connected(self, meta, children):
        return ast.ComponentValue(
            children[0], children[1], merge=True, connected=True, location=self._at(meta)
        )

    @v_args(meta=True)
    def array(self, meta, children):
        return ast.ArrayLiteral(tuple(children), location=self._at(meta))

    @v_args(meta=True)
    def array_row(self, meta, children):
        return tuple(children)

    @v_args(meta=True)
    def index(self, meta, children):
        target, *indices = children
        return ast.Index(target, tuple(indices), location=self._at(meta))

    @v_args(meta=True)
    def colon(self, meta, children):
        if len(children) == 2:
            return ast.Colon(children[0], None, children[1], location=self._at(meta))
        start, step, stop = children
        return ast.Colon(start, step, stop, location=self._at(meta))

    @v_args(meta=True)
    def colon_all(self, meta, children):
        return ast.Colon(None, None, None, location=self._at(meta))


#: Objects whose dotted names are shape attributes (``scope.sx``, ``geometry.area``...).
_SHAPE_OBJECTS = frozenset({*SHAPE_ATTRIBUTES, "material"})


def _dotted_name(name: str, args: tuple, location: SourceLocation, *, call: bool):
    """A name as written: a shape attribute (``scope.sx``, ``geometry.area()``, ``seedian``), a
    call, or a plain (possibly dotted: ``prefix.attr``, ``world.up``) name."""
    head, _, rest = name.partition(".")
    if rest and head in _SHAPE_OBJECTS:
        return ast.ShapeAttribute(head, rest, args, location=location)
    if name in SHAPE_VALUES and not call:
        return ast.ShapeAttribute(name, "", location=location)
    if call:
        return ast.Call(name, args, location=location)
    return ast.Name(name, location=location)
