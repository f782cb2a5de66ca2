"""Syntax errors in plain words, and where to resume parsing after one.

Lark reports the terminals it expected by name (``RPAR``, ``__ANON_3``); these helpers say
"expected ')' or ','" instead, and find the next definition so that one run can report the syntax
errors of several definitions.
"""

from __future__ import annotations

import re

from lark import Token
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from shapegen.errors import SourceLocation
from shapegen.grammar.lexer import lark_parser
from shapegen.grammar.problems import Problem

__all__ = ["syntax_problem", "resume_offset", "blank_before", "error_offset"]


# Plain words for the terminals lark reports as expected.
_TERMINAL_WORDS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "PROBABILITY": "a percentage like '30%'",
    "ARROW": "'-->'",
    "OR_OP": "'||'",
    "AND_OP": "'&&'",
    "EQ_OP": "'==' or '!='",
    "REL_OP": "a comparison ('<', '<=', '>', '>=')",
    "$END": "end of file",
    "QUOTE": "a relative value ('0.5)",
    "TILDE": "a floating size (~1)",
    "_IMPORT": "'import'",
    "_STYLE": "'style'",
    "_EXTENSION": "'extension'",
    "_START": "'start'",
    "_ATTR": "'attr'",
    "_CONST": "'const'",
    "_VERSION": "'version'",
    "SETBACK_COLON": "':'",
    "_WITH": "'with'",
    "_INLINE": "'inline'",
    "BOOL_OP": "'union', 'subtract' or 'intersect'",
    "ALT_LBRACE": "'{'",
    "BARE_LBRACE": "'{'",
}
_SINGLE_ARROW = re.compile(r"[ \t]*(\([^()\n]*\))?[ \t]*(?P<arrow>->)")
_EXPRESSION_STARTS = {"NUMBER", "STRING", "NAME", "LPAR", "MINUS", "PLUS", "BANG", "LSQB"}
_OPERATORS = {
    *("OR_OP", "AND_OP", "EQ_OP", "REL_OP", "PLUS", "MINUS", "STAR", "SLASH", "PERCENT"),
    *("DOT_PLUS", "DOT_MINUS", "DOT_STAR", "DOT_SLASH", "DOT_PERCENT", "DOT_BANG"),
}


def _describe_token(token: Token) -> str:
    if token.type == "$END":
        return "end of file"
    if token.type in ("NAME", "DEF_NAME"):
        return f"name '{token.value}'"
    if token.type == "NUMBER":
        return f"number {token.value}"
    if token.type == "STRING":
        return f"string {token.value}"
    return f"'{token.value}'"


def _describe_expected(expected: set[str]) -> str:
    parser = lark_parser()
    expected = set(expected)
    words = []
    if "DEF_NAME" in expected:
        if {"_ATTR", "_CONST"} & expected:
            words.append("a definition (attr, const, function or rule)")
            expected -= {"_ATTR", "_CONST", "_EXTENSION", "_IMPORT", "_STYLE", "_START"}
        else:
            words.append("a name")
        expected.discard("DEF_NAME")
    if {"NUMBER", "NAME"} <= expected:
        words.append("an expression")
        expected -= _EXPRESSION_STARTS
    if len(expected & _OPERATORS) > 3:
        words.append("an operator")
        expected -= _OPERATORS
    for name in sorted(expected):
        if name in _TERMINAL_WORDS:
            words.append(_TERMINAL_WORDS[name])
            continue
        try:
            pattern = parser.get_terminal(name).pattern
        except KeyError:
            words.append(name.lower())
            continue
        if pattern.type != "str":
            words.append(name.lower())
        elif "'" in pattern.value:
            words.append(f'"{pattern.value}"')
        else:
            words.append(f"'{pattern.value}'")
    leading = [w for w in words if w.startswith(("an expression", "an operator", "a definition"))]
    rest = sorted({w for w in words if w not in leading}, key=lambda w: (not w[0].isalpha(), w))
    words = leading + rest
    if not words:
        return ""
    if len(words) == 1:
        return words[0]
    return ", ".join(words[:-1]) + " or " + words[-1]


def syntax_problem(error: UnexpectedInput, text: str, filename: str) -> Problem:
    location = SourceLocation(filename, error.line or 0, error.column or 0)
    if isinstance(error, UnexpectedCharacters):
        character = error.char
        if character == '"':
            return location, "unterminated string (no closing '\"' before the end of the file)"
        return location, f"unexpected character {character!r}"
    if isinstance(error, UnexpectedEOF):
        expected = _describe_expected(set(error.expected))
        return location, "unexpected end of file" + (f"; expected {expected}" if expected else "")
    if isinstance(error, UnexpectedToken):
        token = error.token
        if token.type == "$END":
            location = _end_location(error, filename)
        accepted = _accepted_terminals(error)
        expected = _describe_expected(accepted)
        message = f"unexpected {_describe_token(token)}"
        start = token.start_pos
        following = text[start : start + 2] if start is not None else ""
        arrow = _single_arrow_after(token, text)
        if token.type == "MINUS" and following == "->":
            message = "unexpected '->'; a rule is written 'Name --> ...'"
            expected = ""
        elif arrow is not None:
            line, column = arrow
            location = SourceLocation(filename, line, column)
            message = "unexpected '->'; a rule is written 'Name --> ...'"
            expected = ""
        elif token.type == "SLASH" and following == "/*":
            return location, "unterminated '/*' comment (no '*/' after it)"
        elif token.type == "DEF_NAME" and "DEF_NAME" not in accepted:
            message += " (it starts a new definition here)"
        return location, message + (f"; expected {expected}" if expected else "")
    return location, "syntax error"


def _single_arrow_after(token: Token, text: str) -> tuple[int, int] | None:
    """Line and column of a ``->`` after ``token`` (and its parameter list) on its line."""
    end = getattr(token, "end_pos", None)
    if token.type not in ("NAME", "DEF_NAME", "RPAR") or end is None:
        return None
    match = _SINGLE_ARROW.match(text, end)
    if match is None:
        return None
    return token.end_line, token.end_column + match.start("arrow") - end


def _accepted_terminals(error: UnexpectedToken) -> set[str]:
    """Terminals the parser would really accept at the error (lark's ``expected`` is wider)."""
    interactive = getattr(error, "interactive_parser", None)
    if interactive is not None:
        try:
            return set(interactive.accepts())
        except Exception:  # noqa: BLE001 - fall back to lark's coarser set
            pass
    return set(error.expected)


def _end_location(error: UnexpectedToken, filename: str) -> SourceLocation:
    token = error.token
    line = getattr(token, "end_line", None) or token.line or 1
    column = getattr(token, "end_column", None) or token.column or 1
    return SourceLocation(filename, line, column)


def blank_before(text: str, offset: int) -> str:
    """``text`` with everything before ``offset`` turned to spaces (newlines kept)."""
    prefix = "".join("\n" if ch == "\n" else " " for ch in text[:offset])
    return prefix + text[offset:]


def resume_offset(text: str, error_at: int, previous: int) -> int | None:
    """Where to parse again after a syntax error at offset ``error_at``, or None.

    That is the first line start at or after the error's own line where a definition begins
    (``@``, ``attr``, ``const`` or a DEF_NAME in the first column after indentation), strictly
    after ``previous`` (the last place parsing started), so that every retry makes progress.
    """
    parser = lark_parser()
    line_start = text.rfind("\n", 0, error_at)
    while True:
        candidate = line_start + 1
        start = len(text) - len(text[candidate:].lstrip(" \t"))
        if previous < start < len(text):
            try:
                first = next(iter(parser.lex(text[start:])), None)
            except UnexpectedInput:
                first = None
            if first is not None and first.column == 1 and first.line == 1:
                if first.type in ("DEF_NAME", "_ATTR", "_CONST", "AT"):
                    return start
        line_start = text.find("\n", candidate)
        if line_start == -1:
            return None


def error_offset(error: UnexpectedInput, text: str) -> int:
    position = getattr(error, "pos_in_stream", None)
    if position is None and isinstance(error, UnexpectedToken):
        position = getattr(error.token, "start_pos", None)
    if position is None:
        return len(text)
    return max(int(position), 0)
