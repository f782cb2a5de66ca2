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

__all__ = ["DefinitionNames", "DefinitionTooLong", "lark_parser"]

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
# Tokens that begin a new definition at bracket depth 0 (for max_definition_tokens).
_DEFINITION_STARTS = frozenset({"DEF_NAME", "_START", "_IMPORT", "_STYLE", "_EXTENSION", "AT"})


class DefinitionTooLong(Exception):
    """Raised by the post-lexer when one definition has more tokens than the work limits allow;
    ``token`` is where the definition started."""

    def __init__(self, token: Token, limit: int):
        super().__init__(token, limit)
        self.token = token
        self.limit = limit


class DefinitionNames:
    """Post-lexer: a NAME that starts a definition becomes DEF_NAME.

    At bracket depth 0, a NAME followed by ``=`` or ``-->``, directly or after one balanced
    ``( ... )``, names a new attr, const, function or rule; anywhere else it is a successor, a
    parameter or a reference.
    """

    always_accept: tuple[str, ...] = ()

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        pending: deque[Token] = deque()
        source = iter(stream)
        exhausted = False

        def peek(index: int) -> Token | None:
            nonlocal exhausted
            while len(pending) <= index and not exhausted:
                try:
                    pending.append(next(source))
                except StopIteration:
                    exhausted = True
            return pending[index] if index < len(pending) else None

        depth = 0
        previous: Token | None = None
        limit = current_limits().max_definition_tokens
        started: Token | None = None  # the first token of the definition being read
        count = 0
        while peek(0) is not None:
            token = pending.popleft()
            count += 1
            if token.type == "NAME" and (following := peek(0)) is not None:
                if token.value in _BOOLEAN_OPERATIONS and following.type == "LBRACE":
                    # union { A | B }: alternatives, not a split's block
                    yield Token.new_borrow_pos("BOOL_OP", token.value, token)
                    brace = pending.popleft()
                    depth += 1
                    previous = Token.new_borrow_pos("ALT_LBRACE", brace.value, brace)
                    yield previous
                    continue
                if token.value == _INLINE and following.type not in _NOT_AFTER_INLINE:
                    token = Token.new_borrow_pos("_INLINE", token.value, token)
            if count > limit and started is not None:
                raise DefinitionTooLong(started, limit)
            if token.type == "LBRACE" and self._bare_block(peek):
                token = Token.new_borrow_pos("BARE_LBRACE", token.value, token)
                depth += 1
            elif token.type in ("LPAR", "LSQB", "LBRACE"):
                depth += 1
            elif token.type in ("RPAR", "RSQB", "RBRACE"):
                depth = max(depth - 1, 0)
            elif (
                token.type == "NAME"
                and token.value == _START
                and depth == 0
                and (previous is None or previous.end_line < token.line)
                and (following := peek(0)) is not None
                and following.type == "NAME"
                and self._starts_definition(lambda k: peek(k + 1))
            ):
                token = Token.new_borrow_pos("_START", token.value, token)
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
            previous = token
            yield token

    @staticmethod
    def _bare_block(peek) -> bool:
        """True for a ``{`` whose block holds operations without ``key :`` (scatter's)."""
        first = peek(0)
        if first is None or first.type == "LBRACE":  # a group of split parts: {{ ... }*}
            return False
        nesting = 0
        index = 0
        while (token := peek(index)) is not None and index < _BARE_BLOCK_LOOKAHEAD:
            if token.type in ("LPAR", "LSQB", "LBRACE"):
                nesting += 1
            elif token.type in ("RPAR", "RSQB"):
                nesting -= 1
            elif token.type == "RBRACE":
                if nesting == 0:
                    return index > 0
                nesting -= 1
            elif nesting == 0 and token.type in ("COLON", "EQUAL", "VBAR", "PROBABILITY"):
                return False
            elif nesting < 0:
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
