"""Operation calls -> operation nodes: one builder per operation (``extrude``, ``split``...).

:class:`OperationBuilders` is mixed into :class:`~shapegen.grammar.transformer.AstBuilder`, whose
``operation`` callback picks the builder by the call's name and checks the number of arguments; a
builder decides what each argument means. Arguments that the syntax lets through but the operation
cannot use (an unknown split axis, a ``'`` where it means nothing) become problems, not exceptions.
"""

from __future__ import annotations

import dataclasses
import math

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.names import (
    CENTER_MODES,
    COMP_KINDS,
    COMP_SELECTORS,
    OPERATIONS,
    ROTATE_PIVOTS,
    SPLIT_AXES,
)

_UV_DIRECTIONS = {"u": "x", "v": "y"}
_UV_SPACES = ("unitSpace", "uvSpace")

__all__ = ["Argument", "EntryGroup", "BlockEntry", "OperationBuilders", "prefix_in_words"]


@dataclasses.dataclass(frozen=True)
class Argument:
    """One argument of an operation call before it is known which operation it belongs to."""

    kind: str  # "plain", "relative", "floating", "keyword"
    value: ast.Expression
    location: SourceLocation
    name: str | None = None


@dataclasses.dataclass(frozen=True)
class BlockEntry:
    """``size : body`` (``selector = body`` with ``merge``) before split or comp claims it."""

    mode: ast.SizeMode
    key: ast.Expression
    body: ast.Body
    merge: bool
    location: SourceLocation
    connected: bool = False  # ``=:``
    depth: ast.Expression | None = None  # splitAndSetbackPerimeter's ``length : depth : ops``


@dataclasses.dataclass(frozen=True)
class EntryGroup:
    """``{ entry | ... }``; ``repeat`` for a trailing ``*``."""

    entries: tuple[BlockEntry | EntryGroup, ...]
    repeat: bool
    location: SourceLocation


class OperationBuilders:
    """The builders of operation nodes from their call's arguments and ``{ ... }`` block."""

    problems: list[tuple[SourceLocation | None, str]]

    def _problem(self, location: SourceLocation, message: str) -> None:
        self.problems.append((location, message))

    def _plain(self, operation: str, argument: Argument) -> ast.Expression:
        if argument.kind not in ("plain", "keyword"):
            self._problem(
                argument.location,
                f"{prefix_in_words(argument)} is not allowed in the arguments of {operation}()",
            )
        return argument.value

    def _keyword_choice(
        self, operation: str, what: str, argument: Argument, valid: tuple[str, ...]
    ) -> str:
        value = argument.value
        if argument.kind == "plain" and isinstance(value, ast.Name) and value.name in valid:
            return value.name
        if argument.kind == "plain" and isinstance(value, ast.String) and value.value in valid:
            return value.value
        if isinstance(value, ast.Name) and argument.kind == "plain":
            message = f"unknown {what} '{value.name}' in {operation}(); valid: {', '.join(valid)}"
        else:
            message = f"the {what} of {operation}() must be one of: {', '.join(valid)}"
        self._problem(argument.location, message)
        return valid[0]

    def _coordinate(self, operation: str, argument: Argument) -> ast.Coordinate:
        if argument.kind not in ("plain", "relative"):
            self._problem(
                argument.location, f"{prefix_in_words(argument)} is not allowed in {operation}()"
            )
        return ast.Coordinate(
            argument.value, relative=argument.kind == "relative", location=argument.location
        )

    def _dedicated(self, name: str, arguments: list[Argument], block: EntryGroup | None) -> bool:
        """True when the call fits the operation's node of its own (``extrude(h)``, ``comp(f)``
        with named or numbered selectors...); other forms become a generic Operation."""
        if name not in OPERATIONS:
            return False
        positional = [a for a in arguments if a.kind != "keyword"]
        if name == "split":
            first = positional[0].value if positional else None
            if isinstance(first, ast.Name) and first.name in _UV_DIRECTIONS:
                return len(positional) <= 3
            return len(positional) == 1 or (
                len(positional) == 2
                and isinstance(positional[1].value, ast.Name)
                and positional[1].value.name in ("adjust", "noAdjust")
            )
        if name == "extrude":
            return len(positional) == 1
        if name == "i":  # i(asset[, upAxis[, insertMode[, cleanupMode]]])
            return 1 <= len(positional) <= 4
        if name == "comp":
            kind = positional[0].value if len(positional) == 1 else None
            if not (isinstance(kind, ast.Name) and kind.name in COMP_KINDS) or block.repeat:
                return False
            return all(
                isinstance(entry, BlockEntry)
                and entry.mode == "absolute"
                and (
                    (isinstance(entry.key, ast.Name) and entry.key.name in COMP_SELECTORS)
                    or _is_face_index(entry.mode, entry.key)
                )
                for entry in block.entries
            )
        low, high = OPERATIONS[name]
        return low <= len(positional) <= high

    def _generic(self, name: str, arguments: list[Argument], block: EntryGroup | None, location):
        """A generic :class:`~shapegen.grammar.ast.Operation` node for the call."""
        branches = []
        if name == "comp" and block is not None and block.repeat:
            self._problem(block.location, "a comp block cannot be repeated with '*'")
        for entry in block.entries if block is not None else ():
            if isinstance(entry, EntryGroup):
                self._problem(entry.location, f"{name} branches cannot be grouped with {{ }}")
                continue
            if name == "comp" and entry.mode != "absolute":
                valid = ", ".join(COMP_SELECTORS[:6])
                self._problem(
                    entry.location,
                    f"a comp selector must be a face index or one of: {valid}...",
                )
            if entry.depth is not None and name != "splitAndSetbackPerimeter":
                self._problem(
                    entry.location, f"{name}() takes 'key : operations' entries, not three parts"
                )
            if entry.connected and name not in ("comp", "modify"):
                self._problem(entry.location, f"'=:' is only for comp and modify, not {name}()")
            branches.append(
                ast.OperationBranch(
                    entry.key,
                    entry.mode,
                    entry.body,
                    merge=entry.merge,
                    location=entry.location,
                    connected=entry.connected,
                    depth=entry.depth,
                )
            )
        return ast.Operation(
            name,
            tuple(
                ast.OperationArgument(a.kind, a.value, a.name, location=a.location)
                for a in arguments
            ),
            tuple(branches),
            repeat=block is not None and block.repeat,
            location=location,
        )

    def _op_extrude(self, arguments, block, location):
        return ast.Extrude(self._plain("extrude", arguments[0]), location=location)

    def _op_split(self, arguments, block, location):
        first = arguments[0].value
        if isinstance(first, ast.Name) and first.name in _UV_DIRECTIONS:
            return self._uv_split(arguments, block, location)
        axis = self._keyword_choice("split", "axis", arguments[0], SPLIT_AXES)
        adjust = len(arguments) == 1 or arguments[1].value.name == "adjust"
        return ast.Split(axis, self._split_group(block), adjust=adjust, location=location)

    def _uv_split(self, arguments, block, location):
        """op_split's UV split, ``split(u|v, uvSpace|unitSpace, uvSet)``: shapegen keeps no
        texture coordinates, so it runs along the scope's x (u) or y (v), as a facade's
        ``setupProjection(0, scope.xy, ...)`` lays them; uvSpace sizes are fractions of the
        scope's extent. The derivation warns that it did so."""
        direction = _UV_DIRECTIONS[arguments[0].value.name]
        space = "unitSpace"
        if len(arguments) > 1:
            space = self._keyword_choice(
                "split", "surface parameterization", arguments[1], _UV_SPACES
            )
        return ast.Split(
            direction, self._split_group(block), adjust=True, texture=space, location=location
        )

    def _split_group(self, block: EntryGroup) -> ast.SplitGroup:
        parts = []
        for entry in block.entries:
            if isinstance(entry, EntryGroup):
                parts.append(self._split_group(entry))
                continue
            if entry.merge:
                self._problem(entry.location, "'=' is only for comp branches; use ':' in a split")
            if entry.depth is not None:
                self._problem(
                    entry.location,
                    "a split part is 'size : operations' (three parts are "
                    "splitAndSetbackPerimeter's)",
                )
            parts.append(ast.SplitEntry(entry.key, entry.mode, entry.body, location=entry.location))
        return ast.SplitGroup(tuple(parts), block.repeat, location=block.location)

    def _op_comp(self, arguments, block, location):
        kind = self._keyword_choice("comp", "component type", arguments[0], COMP_KINDS)
        if block.repeat:
            self._problem(block.location, "a comp block cannot be repeated with '*'")
        branches = []
        for entry in block.entries:
            if isinstance(entry, EntryGroup):
                self._problem(entry.location, "comp branches cannot be grouped with { }")
                continue
            key = entry.key
            if (
                entry.mode == "absolute"
                and isinstance(key, ast.Name)
                and key.name in (COMP_SELECTORS)
            ):
                selector = key.name
            elif _is_face_index(entry.mode, key):
                selector = str(int(key.value))
            else:
                valid = ", ".join(COMP_SELECTORS)
                if isinstance(key, ast.Name) and entry.mode == "absolute":
                    message = f"unknown comp selector '{key.name}'; valid: {valid}"
                else:
                    message = f"a comp selector must be a face index or one of: {valid}"
                self._problem(entry.location, message)
                selector = COMP_SELECTORS[-1]
            branches.append(
                ast.CompBranch(
                    selector,
                    entry.body,
                    merge=entry.merge,
                    location=entry.location,
                    connected=entry.connected,
                )
            )
        return ast.Comp(kind, tuple(branches), location=location)

    def _op_t(self, arguments, block, location):
        x, y, z = (self._coordinate("t", a) for a in arguments)
        return ast.Translate(x, y, z, location=location)

    def _op_s(self, arguments, block, location):
        x, y, z = (self._coordinate("s", a) for a in arguments)
        return ast.Scale(x, y, z, location=location)

    def _op_r(self, arguments, block, location):
        pivot = "origin"
        if len(arguments) == 4:
            pivot_name = self._keyword_choice("r", "pivot", arguments[0], tuple(ROTATE_PIVOTS))
            pivot = ROTATE_PIVOTS[pivot_name]
            arguments = arguments[1:]
        x, y, z = (self._plain("r", a) for a in arguments)
        return ast.Rotate(x, y, z, pivot=pivot, location=location)

    def _op_center(self, arguments, block, location):
        axes = self._keyword_choice("center", "axes", arguments[0], CENTER_MODES)
        return ast.Center(axes, location=location)

    def _op_label(self, arguments, block, location):
        return ast.Label(self._plain("label", arguments[0]), location=location)

    def _op_set(self, arguments, block, location):
        target, value = arguments
        if target.kind == "plain" and isinstance(target.value, ast.Name):
            attribute = target.value.name
        elif target.kind == "plain" and isinstance(target.value, ast.ShapeAttribute):
            attribute = f"{target.value.obj}.{target.value.field}"
        else:
            self._problem(target.location, "set() needs an attribute name as its first argument")
            attribute = ""
        return ast.Set(attribute, self._plain("set", value), location=location)

    def _op_i(self, arguments, block, location):
        primitive, *rest = arguments
        if primitive.kind == "keyword":
            self._problem(primitive.location, "i() needs the primitive's name first")
        keywords, options = [], []
        for argument in rest:
            if argument.kind == "keyword":
                keywords.append(
                    ast.Keyword(argument.name, argument.value, location=argument.location)
                )
            else:  # i(asset, yUp, keepSizeAlignPosition): read by the asset insert
                options.append(self._plain("i", argument))
        return ast.Insert(
            self._plain("i", primitive), tuple(keywords), location=location, options=tuple(options)
        )

    def _op_print(self, arguments, block, location):
        values = tuple(self._plain("print", a) for a in arguments)
        return ast.Print(values, location=location)

    def _op_report(self, arguments, block, location):
        key, value = (self._plain("report", a) for a in arguments)
        return ast.Report(key, value, location=location)


def _is_face_index(mode: str, key: ast.Expression) -> bool:
    return (
        mode == "absolute"
        and isinstance(key, ast.Number)
        and math.isfinite(key.value)
        and key.value >= 0
        and key.value == int(key.value)
    )


def prefix_in_words(argument: Argument) -> str:
    """How the user wrote a non-plain argument, in words."""
    if argument.kind == "relative":
        return "a relative value (')"
    if argument.kind == "floating":
        return "a floating size (~)"
    return f"a keyword argument ({argument.name}=)"
