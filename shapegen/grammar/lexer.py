"""Lexing the .grammar language: the lark parser and the post-lexer that marks definitions.

A rule body is a run of items with no terminator, so the name that starts the next definition
(``B --> ...``, ``f(a) = ...``, ``g = ...``) cannot be told from one more successor with one token
of lookahead. :class:`DefinitionNames` looks further ahead and re-types such names as DEF_NAME,
which keeps the grammar (``cga.lark``, package data) LALR(1).
"""

from __future__ import annotations

import functools
import importlib.resources
from collections import deque
from collections.abc import Iterator

import lark
from lark import Token

from shapegen.limits import current_limits

__all__ = ["BlocksTooDeep", "DefinitionNames", "DefinitionTooLong", "lark_parser"]

_GRAMMAR_FILE = "cga.lark"


# Words that are keywords only at bracket depth 0 and before these tokens.
# Tokens looked at to tell a block of operations (scatter's) from a block of branches.
_BARE_BLOCK_LOOKAHEAD = 5000

_KEYWORDS = {"import": ("NAME", "STRING"), "style": ("NAME",), "extension": ("NAME",)}
# ``start Name --> ...`` (start.html) marks the start rule: a keyword only first on its line and
# before a rule's name, so that a successor or rule called ``start`` stays one.
_START = "start"
# ``Name with (x := ...) = ...`` (with.html): a keyword at depth 0 after a definition's name or
# parameters, before its parenthesis.
_WITH = "with"
# op_boolOp's operations take a block of alternatives; op_inline's keyword form takes the item
# after it (the operation form, inline(unify), is an ordinary call)
_BOOLEAN_OPERATIONS = frozenset({"union", "subtract", "intersect"})
_INLINE = "inline"
_NOT_AFTER_INLINE = frozenset(
    {"LPAR", "EQUAL", "ARROW", "COLON", "RBRACE", "VBAR", "RSQB", "DOT", "COMMA", "RPAR"}
)
# Blocks ``{ ... }`` open at once: the parse tree's builder recurses per block and gives up
# (RecursionError) near 150, so a file nested deeper is refused where it passes this depth,
# before the rest of it is read.
MAX_BLOCK_NESTING = 1000
# Tokens that begin a new definition at bracket depth 0 (for max_definition_tokens).
_DEFINITION_STARTS = frozenset(
    {"DEF_NAME", "_START", "_IMPORT", "_STYLE", "_EXTENSION", "AT", "_ATTR", "_CONST", "_VERSION"}
)
# attr.html, const.html: keywords at bracket depth 0 before a name (or a misplaced ``=``) on their
# line, so that a parameter called ``attr`` stays a name in ``f(attr) = attr``; version.html:
# ``version`` only before the version string (``attr version = 2`` is fine).
_DEFINITION_KEYWORDS = {"attr": "_ATTR", "const": "_CONST"}
_VERSION = "version"
# Tokens that end a splitAndSetbackPerimeter entry's depth or show that a colon is not its first
# one (a case or stochastic body, a definition).
_NOT_IN_DEPTH = frozenset({"CASE", "ELSE", "PROBABILITY", "ARROW", "EQUAL", "SEMICOLON"})
_DEPTH_LOOKAHEAD = 2000


class DefinitionTooLong(Exception):
    """Raised by the post-lexer when one definition has more tokens than the work limits allow;
    ``token`` is where the definition started."""

    def __init__(self, token: Token, limit: int):
        super().__init__(token, limit)
        self.token = token
        self.limit = limit


_OPENERS = frozenset({"LPAR", "LSQB", "LBRACE"})
_CLOSERS = frozenset({"RPAR", "RSQB", "RBRACE"})


class _Lookahead:
    """The tokens read ahead of the post-lexer, with where each bracket read so far closes
    (any closer closes the latest open bracket, as a count of nesting would)."""

    def __init__(self, stream: Iterator[Token]):
        self._source = iter(stream)
        self._pending: deque[Token] = deque()
        self._taken = 0  # tokens handed on: the absolute index of _pending[0]
        self._open: list[int] = []  # absolute indices of the brackets not closed yet
        self._closes: dict[int, int] = {}  # absolute index of a bracket -> of its closer
        self._exhausted = False

    def _read(self) -> bool:
        try:
            token = next(self._source)
        except StopIteration:
            self._exhausted = True
            return False
        position = self._taken + len(self._pending)
        self._pending.append(token)
        if token.type in _OPENERS:
            self._open.append(position)
        elif token.type in _CLOSERS and self._open:
            self._closes[self._open.pop()] = position
        return True

    def peek(self, index: int) -> Token | None:
        """The token ``index`` places ahead (0: the next one), or None past the end."""
        while len(self._pending) <= index and not self._exhausted:
            self._read()
        return self._pending[index] if index < len(self._pending) else None

    def popleft(self) -> Token:
        self._closes.pop(self._taken, None)
        self._taken += 1
        return self._pending.popleft()

    def closing(self, index: int, within: int) -> int | None:
        """Where (places ahead) the bracket ``index`` places ahead closes; None when it does
        not close before ``within`` places ahead or the end."""
        position = self._taken + index
        while position not in self._closes:
            if len(self._pending) > within or not self._read():
                return None
        found = self._closes[position] - self._taken
        return found if found < within else None


class BlocksTooDeep(Exception):
    """Raised by the post-lexer at the ``{`` that opens more than ``MAX_BLOCK_NESTING`` blocks
    at once."""

    def __init__(self, token: Token):
        super().__init__(token)
        self.token = token


class DefinitionNames:
    """Post-lexer: a NAME that starts a definition becomes DEF_NAME.

    At bracket depth 0, a NAME followed by ``=`` or ``-->``, directly or after one balanced
    ``( ... )``, names a new attr, const, function or rule; anywhere else it is a successor, a
    parameter or a reference.
    """

    always_accept: tuple[str, ...] = ()

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        ahead = _Lookahead(stream)
        peek = ahead.peek
        depth = 0
        brackets: list[str] = []  # the open brackets' types, innermost last
        previous: Token | None = None
        annotation_end: Token | None = None  # the last token of the latest annotation
        annotation_open = False  # an annotation's name is read, its arguments may follow
        limit = current_limits().max_definition_tokens
        started: Token | None = None  # the first token of the definition being read
        count = 0
        blocks = 0  # braces open
        while peek(0) is not None:
            token = ahead.popleft()
            count += 1
            if token.type == "NAME" and (following := peek(0)) is not None:
                if token.value in _BOOLEAN_OPERATIONS and following.type == "LBRACE":
                    # union { A | B }: alternatives, not a split's block
                    yield Token.new_borrow_pos("BOOL_OP", token.value, token)
                    brace = ahead.popleft()
                    depth += 1
                    brackets.append("ALT_LBRACE")
                    previous = Token.new_borrow_pos("ALT_LBRACE", brace.value, brace)
                    yield previous
                    continue
                if token.value == _INLINE and following.type not in _NOT_AFTER_INLINE:
                    token = Token.new_borrow_pos("_INLINE", token.value, token)
            if count > limit and started is not None:
                raise DefinitionTooLong(started, limit)
            if token.type == "LBRACE":
                blocks += 1
                if blocks > MAX_BLOCK_NESTING:
                    raise BlocksTooDeep(token)
            elif token.type == "RBRACE":
                blocks = max(blocks - 1, 0)
            if token.type == "LBRACE" and self._bare_block(ahead):
                token = Token.new_borrow_pos("BARE_LBRACE", token.value, token)
                depth += 1
                brackets.append(token.type)
            elif token.type in ("LPAR", "LSQB", "LBRACE"):
                depth += 1
                brackets.append(token.type)
            elif token.type in ("RPAR", "RSQB", "RBRACE"):
                depth = max(depth - 1, 0)
                if brackets:
                    brackets.pop()
                if depth == 0 and annotation_open and token.type == "RPAR":
                    annotation_end, annotation_open = token, False
            elif token.type == "COLON" and brackets and brackets[-1] == "LBRACE":
                if self._first_of_three(peek):
                    token = Token.new_borrow_pos("SETBACK_COLON", token.value, token)
            elif (
                token.type == "NAME"
                and token.value == _START
                and depth == 0
                and (
                    previous is None
                    or previous.end_line < token.line
                    or previous is annotation_end
                    or previous.type == "_EXTENSION"
                )
                and self._start_mark(peek)
            ):
                token = Token.new_borrow_pos("_START", token.value, token)
            elif (
                token.type == "NAME"
                and depth == 0
                and token.value in _DEFINITION_KEYWORDS
                and (following := peek(0)) is not None
                and following.type in ("NAME", "EQUAL")
                and following.line == token.end_line
            ):
                token = Token.new_borrow_pos(_DEFINITION_KEYWORDS[token.value], token.value, token)
            elif (
                token.type == "NAME"
                and token.value == _VERSION
                and depth == 0
                and (following := peek(0)) is not None
                and following.type == "STRING"
            ):
                token = Token.new_borrow_pos("_VERSION", token.value, token)
            elif (
                token.type == "NAME"
                and token.value == _WITH
                and depth == 0
                and previous is not None
                and previous.type in ("DEF_NAME", "RPAR")
                and (following := peek(0)) is not None
                and following.type == "LPAR"
            ):
                token = Token.new_borrow_pos("_WITH", token.value, token)
            elif token.type == "NAME" and depth == 0 and self._starts_definition(peek):
                token = Token.new_borrow_pos("DEF_NAME", token.value, token)
            elif token.type == "NAME" and depth == 0 and token.value in _KEYWORDS:
                following = peek(0)
                if following is not None and following.type in _KEYWORDS[token.value]:
                    token = Token.new_borrow_pos("_" + token.value.upper(), token.value, token)
            if depth == 0 and token.type in _DEFINITION_STARTS:
                started, count = token, 0
            if depth == 0 and previous is not None and previous.type == "AT":
                # the annotation's name: it ends here unless its arguments follow
                following = peek(0)
                annotation_open = following is not None and following.type == "LPAR"
                annotation_end = None if annotation_open else token
            previous = token
            yield token

    @staticmethod
    def _bare_block(ahead: _Lookahead) -> bool:
        """True for a ``{`` (just taken) whose block holds operations without ``key :``
        (scatter's). Only the block's own level is read: a nested group is stepped over to
        where it closes, so that blocks nested in blocks are read once each, not once per
        enclosing block."""
        first = ahead.peek(0)
        if first is None or first.type == "LBRACE":  # a group of split parts: {{ ... }*}
            return False
        index = 0
        while index < _BARE_BLOCK_LOOKAHEAD and (token := ahead.peek(index)) is not None:
            if token.type in _OPENERS:
                closing = ahead.closing(index, _BARE_BLOCK_LOOKAHEAD)
                if closing is None:
                    return False
                index = closing
            elif token.type == "RBRACE":
                return index > 0
            elif token.type in ("RPAR", "RSQB", "COLON", "EQUAL", "VBAR", "PROBABILITY"):
                return False
            index += 1
        return False

    @staticmethod
    def _start_mark(peek) -> bool:
        """``start`` is followed by a rule's name (after ``extension``, if written second)."""
        offset = 0
        following = peek(0)
        if following is not None and following.type == "NAME" and following.value == "extension":
            offset = 1
            following = peek(1)
        if following is None or following.type != "NAME":
            return False
        return DefinitionNames._starts_definition(lambda k: peek(k + offset + 1))

    @staticmethod
    def _first_of_three(peek) -> bool:
        """True for the first ``:`` of a ``length : depth : operations`` entry
        (op_splitAndSetbackPerimeter): another ``:`` follows in the same entry, with no case,
        else or percentage before it (their colons are a body's)."""
        nesting = 0
        index = 0
        while (token := peek(index)) is not None and index < _DEPTH_LOOKAHEAD:
            kind = token.type
            if kind in ("LPAR", "LSQB", "LBRACE"):
                nesting += 1
            elif kind in ("RPAR", "RSQB", "RBRACE"):
                if nesting == 0:
                    return False
                nesting -= 1
            elif nesting == 0:
                if kind == "COLON":
                    return index > 0
                if kind == "VBAR" or kind in _NOT_IN_DEPTH:
                    return False
            index += 1
        return False

    @staticmethod
    def _starts_definition(peek) -> bool:
        """``= ...`` or ``--> ...`` follows, after an optional ``(params)`` and an optional
        ``with (...)``."""
        index = 0
        following = peek(0)
        if following is not None and following.type == "LPAR":
            index = DefinitionNames._after_parentheses(peek, 0, params=True)
            if index is None:
                return False
            following = peek(index)
        if following is not None and following.type == "NAME" and following.value == _WITH:
            after = peek(index + 1)
            if after is None or after.type != "LPAR":
                return False
            index = DefinitionNames._after_parentheses(peek, index + 1, params=False)
            if index is None:
                return False
            following = peek(index)
        return following is not None and following.type in ("EQUAL", "ARROW")

    @staticmethod
    def _after_parentheses(peek, index: int, params: bool) -> int | None:
        """The index after the parenthesis opened at ``index`` closes; None when a token that
        cannot be in a parameter list comes first (with ``params``)."""
        nesting = 0
        while (token := peek(index)) is not None:
            if token.type == "LPAR":
                nesting += 1
            elif token.type == "RPAR":
                nesting -= 1
                if nesting == 0:
                    return index + 1
            elif token.type == "ARROW" or (
                params and token.type in ("LBRACE", "RBRACE", "LSQB", "RSQB")
            ):
                return None
            index += 1
        return None


class _StartPositions:
    """What lark's ``propagate_positions`` does for where a node starts (its ``line`` and
    ``column``, from its first child, anonymous tokens such as ``(`` included), without where it
    ends, which nothing here reads: half of the parse's time went to the end positions and the
    ``getattr`` calls around them."""

    __slots__ = ("node_builder",)

    def __init__(self, node_builder):
        self.node_builder = node_builder

    def __call__(self, children):
        node = self.node_builder(children)
        if type(node) is not _Tree:
            return node
        for child in children:
            kind = type(child)
            if kind is Token:
                line, column = child.line, child.column
                break
            if kind is _Tree:
                meta = child.meta
                if not meta.empty:
                    line, column = meta.container_line, meta.container_column
                    break
        else:
            return node
        meta = node.meta
        if meta.empty:
            meta.line, meta.column = line, column
            meta.empty = False
        meta.container_line, meta.container_column = line, column
        return node


_Tree = lark.Tree


@functools.lru_cache(maxsize=1)
def lark_parser() -> lark.Lark:
    """The LALR(1) parser of ``cga.lark``, built once. lark keeps the analysed tables in a file
    of the temporary folder, keyed by the grammar's text and options (``cache=True``): a new
    process loads them instead of computing them again (0.3 s of every command's start)."""
    text = importlib.resources.files("shapegen.grammar").joinpath(_GRAMMAR_FILE).read_text()
    parser = lark.Lark(
        text,
        parser="lalr",
        lexer="basic",
        postlex=DefinitionNames(),
        propagate_positions=True,
        maybe_placeholders=False,
        cache=True,
    )
    # lark's position callbacks, each replaced by one that sets start positions only; where a
    # lark version keeps them elsewhere, its own stay (the same positions, more slowly)
    frontend = getattr(parser.parser, "parser", None)
    callbacks = getattr(getattr(frontend, "parser", None), "callbacks", {})
    for rule, callback in list(callbacks.items()):
        builder = getattr(callback, "node_builder", None)
        if type(callback).__name__ == "PropagatePositions" and builder is not None:
            callbacks[rule] = _StartPositions(builder)
    return parser
