"""Operation calls -> operation nodes: :class:`OperationCalls`, one builder per operation.

The parser's transformer (:class:`~shapegen.grammar.transformer.AstBuilder`) hands every call
``name(args) { block }*`` to :meth:`OperationCalls.node` with its arguments
(:class:`~shapegen.grammar.ast.CallArgument`) and block
(:class:`~shapegen.grammar.ast.EntryGroup`) as written. :meth:`~OperationCalls.node` checks the
number of arguments and the block, then either builds the operation's own node (``comp(f) {
front : A }`` -> :class:`~shapegen.grammar.ast.Comp` in :meth:`OperationCalls._comp`) or, for
the other forms and every other CGA operation, a generic :class:`~shapegen.grammar.ast.Operation`.
Arguments that the syntax lets through but the operation cannot use (an unknown split axis, a
``'`` where it means nothing) become problems, not exceptions.
"""

from __future__ import annotations

import math

from shapegen.errors import SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.ast import BlockEntry, CallArgument, EntryGroup
from shapegen.grammar.names import (
    BLOCK_OPERATIONS,
    CENTER_MODES,
    CGA_OPERATIONS,
    COMP_KINDS,
    COMP_SELECTORS,
    OPERATIONS,
    ROTATE_PIVOTS,
    SPLIT_AXES,
)
from shapegen.grammar.problems import Problem, plural

_UV_DIRECTIONS = {"u": "x", "v": "y"}
_UV_SPACES = ("unitSpace", "uvSpace")

__all__ = ["OperationCalls", "prefix_in_words"]


class OperationCalls:
    """Builds the node of each operation call; collects the problems it finds in ``problems``.

    A call whose number of arguments fits none of the operation's signatures may call a rule of
    the operation's name (a ``.cga`` file may define one): it becomes a successor call, and
    :meth:`settle` decides once every rule of the file is known.
    """

    def __init__(self, problems: list[Problem]):
        self.problems = problems
        # calls whose arity fits no signature: (location, message, name, number of arguments)
        self._rule_named_calls: list[tuple[SourceLocation, str, str, int]] = []

    def _problem(self, location: SourceLocation, message: str) -> None:
        self.problems.append((location, message))

    def node(
        self,
        name: str,
        arguments: list[CallArgument],
        block: EntryGroup | None,
        location: SourceLocation,
    ):
        """The node of the call ``name(arguments) block``: an operation's node, a generic
        :class:`~shapegen.grammar.ast.Operation`, a successor call, or ``Nil`` after a problem."""
        positional = [a for a in arguments if a.kind != "keyword"]
        if name in CGA_OPERATIONS:
            low, high = CGA_OPERATIONS[name]
            if not low <= len(positional) <= high:
                message = _count_message(name, low, high, len(positional))
                if block is None and all(a.kind == "plain" for a in arguments):
                    # a rule of the operation's name and this arity is called (a .cga file may
                    # define one: 'settle' decides once every rule is known)
                    self._rule_named_calls.append((location, message, name, len(arguments)))
                    args = tuple(a.value for a in arguments)
                    return ast.Successor(name, args, called=True, location=location)
                self._problem(location, message)
                return ast.Nil(location=location)
            if name in ("split", "comp") and block is None:
                self._problem(location, f"{name}() needs a {{ ... }} block of branches after it")
                return ast.Nil(location=location)
            if block is not None and name not in BLOCK_OPERATIONS:
                self._problem(block.location, f"{name}() takes no {{ ... }} block")
                block = None
            bare = block is not None and any(
                isinstance(e, BlockEntry) and e.key is None for e in block.entries
            )
            if bare and name not in ("scatter", "inline"):  # inline(unify) { operations }
                self._problem(block.location, f"{name}() needs 'key : operations' in its block")
                return ast.Nil(location=location)
            if self._dedicated(name, arguments, block):
                if name != "i":
                    for argument in arguments:
                        if argument.kind == "keyword":
                            self._problem(
                                argument.location,
                                f"{name}() takes no keyword arguments (got '{argument.name}=')",
                            )
                return _DEDICATED[name](self, arguments, block, location)
            return self.generic(name, arguments, block, location)
        if block is not None:
            self._problem(
                block.location,
                f"'{name}' is not a CGA operation, and only operations take a {{ ... }} block",
            )
        args = []
        for argument in arguments:
            if argument.kind != "plain":
                self._problem(
                    argument.location,
                    f"arguments of the successor '{name}' are plain expressions "
                    f"({prefix_in_words(argument)} is not allowed here)",
                )
            args.append(argument.value)
        return ast.Successor(name, tuple(args), called=True, location=location)

    def settle(self, rules: set[tuple[str, int]], cga: bool) -> None:
        """Report the calls of an operation with a number of arguments none of its signatures
        takes, unless ``rules`` (``(name, number of parameters)``) has a rule they call and the
        file is a ``.cga`` one."""
        for location, message, name, count in self._rule_named_calls:
            if (name, count) not in rules or not cga:
                self._problem(location, message)

    def _plain(self, operation: str, argument: CallArgument) -> ast.Expression:
        if argument.kind not in ("plain", "keyword"):
            self._problem(
                argument.location,
                f"{prefix_in_words(argument)} is not allowed in the arguments of {operation}()",
            )
        return argument.value

    def _keyword_choice(
        self, operation: str, what: str, argument: CallArgument, valid: tuple[str, ...]
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

    def _coordinate(self, operation: str, argument: CallArgument) -> ast.Coordinate:
        if argument.kind not in ("plain", "relative"):
            self._problem(
                argument.location, f"{prefix_in_words(argument)} is not allowed in {operation}()"
            )
        return ast.Coordinate(
            argument.value, relative=argument.kind == "relative", location=argument.location
        )

    def _dedicated(
        self, name: str, arguments: list[CallArgument], block: EntryGroup | None
    ) -> bool:
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

    def generic(self, name: str, arguments: list[CallArgument], block: EntryGroup | None, location):
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

    def _extrude(self, arguments, block, location):
        return ast.Extrude(self._plain("extrude", arguments[0]), location=location)

    def _split(self, arguments, block, location):
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

    def _comp(self, arguments, block, location):
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

    def _t(self, arguments, block, location):
        x, y, z = (self._coordinate("t", a) for a in arguments)
        return ast.Translate(x, y, z, location=location)

    def _s(self, arguments, block, location):
        x, y, z = (self._coordinate("s", a) for a in arguments)
        return ast.Scale(x, y, z, location=location)

    def _r(self, arguments, block, location):
        pivot = "origin"
        if len(arguments) == 4:
            pivot_name = self._keyword_choice("r", "pivot", arguments[0], tuple(ROTATE_PIVOTS))
            pivot = ROTATE_PIVOTS[pivot_name]
            arguments = arguments[1:]
        x, y, z = (self._plain("r", a) for a in arguments)
        return ast.Rotate(x, y, z, pivot=pivot, location=location)

    def _center(self, arguments, block, location):
        axes = self._keyword_choice("center", "axes", arguments[0], CENTER_MODES)
        return ast.Center(axes, location=location)

    def _label(self, arguments, block, location):
        return ast.Label(self._plain("label", arguments[0]), location=location)

    def _set(self, arguments, block, location):
        target, value = arguments
        if target.kind == "plain" and isinstance(target.value, ast.Name):
            attribute = target.value.name
        elif target.kind == "plain" and isinstance(target.value, ast.ShapeAttribute):
            attribute = f"{target.value.obj}.{target.value.field}"
        else:
            self._problem(target.location, "set() needs an attribute name as its first argument")
            attribute = ""
        return ast.Set(attribute, self._plain("set", value), location=location)

    def _i(self, arguments, block, location):
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

    def _print(self, arguments, block, location):
        values = tuple(self._plain("print", a) for a in arguments)
        return ast.Print(values, location=location)

    def _report(self, arguments, block, location):
        key, value = (self._plain("report", a) for a in arguments)
        return ast.Report(key, value, location=location)


#: The operations that have a node of their own, and the method of :class:`OperationCalls` that
#: builds it (the call's form decides first, :meth:`OperationCalls._dedicated`).
_DEDICATED = {
    "extrude": OperationCalls._extrude,
    "split": OperationCalls._split,
    "comp": OperationCalls._comp,
    "t": OperationCalls._t,
    "s": OperationCalls._s,
    "r": OperationCalls._r,
    "center": OperationCalls._center,
    "label": OperationCalls._label,
    "set": OperationCalls._set,
    "i": OperationCalls._i,
    "print": OperationCalls._print,
    "report": OperationCalls._report,
}


def _is_face_index(mode: str, key: ast.Expression) -> bool:
    return (
        mode == "absolute"
        and isinstance(key, ast.Number)
        and math.isfinite(key.value)
        and key.value >= 0
        and key.value == int(key.value)
    )


def prefix_in_words(argument: CallArgument) -> str:
    """How the user wrote a non-plain argument, in words."""
    if argument.kind == "relative":
        return "a relative value (')"
    if argument.kind == "floating":
        return "a floating size (~)"
    return f"a keyword argument ({argument.name}=)"


def _count_message(name: str, low: int, high: int, got: int) -> str:
    if low == high:
        wanted = plural(low, "argument")
    elif high >= 1_000_000:
        wanted = f"at least {plural(low, 'argument')}"
    else:
        wanted = f"{low} to {high} arguments"
    return f"{name}() takes {wanted}, got {got}"
