"""Parse .grammar text into the AST of :mod:`shapegen.grammar.ast`.

The language's syntax lives in ``cga.lark`` (package data, see :mod:`shapegen.grammar.lexer`).
Lark parses it (LALR(1)); :class:`~shapegen.grammar.transformer.AstBuilder` turns the parse tree
into frozen AST nodes, so nothing downstream sees a lark object. Syntax errors become
:class:`~shapegen.errors.GrammarError` with plain-words messages; after a syntax error the parser
resumes at the next definition, so one run reports the syntax errors of several definitions.
"""

from __future__ import annotations

import dataclasses
import re

import lark
from lark.exceptions import UnexpectedInput

from shapegen.errors import GrammarError, SourceLocation
from shapegen.grammar import ast
from shapegen.grammar.lexer import BlocksTooDeep, DefinitionTooLong, lark_parser
from shapegen.grammar.problems import Problem
from shapegen.grammar.syntax_errors import (
    blank_before,
    error_offset,
    resume_offset,
    syntax_problem,
)
from shapegen.grammar.transformer import AstBuilder
from shapegen.limits import current_limits, limit_hint

__all__ = ["parse", "parse_with_problems", "source_too_long", "Problem", "MAX_SYNTAX_ERRORS"]

#: Syntax errors reported from one file before giving up.
MAX_SYNTAX_ERRORS = 10

_TOO_DEEP = (
    "the file nests too deeply to process (parentheses, brackets, braces or a very long "
    "chain of operators)"
)


def parse_with_problems(
    text: str, filename: str = "<string>"
) -> tuple[ast.RuleFile, list[Problem]]:
    """Parse ``text``; return the AST and the problems found while building it.

    Syntax errors raise :class:`GrammarError` (all of them, up to a limit); problems that only
    show once the tree is built (an unknown split axis, a misplaced ``'``) come back in the list
    so that :func:`shapegen.grammar.load` can report them together with the semantic checks.
    """
    if len(text) > current_limits().max_source_chars:
        raise GrammarError(f"{filename}: {source_too_long(len(text), 'characters')}")
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    parser = lark_parser()
    syntax: list[Problem] = []
    tree = None
    original = text
    attempt = text = blank_viewport_hints(text)
    started_at = -1
    while True:
        try:
            parsed = parser.parse(attempt)
            if not syntax:
                tree = parsed
            break
        except UnexpectedInput as error:
            syntax.append(syntax_problem(error, attempt, filename))
            if len(syntax) >= MAX_SYNTAX_ERRORS:
                break
            offset = error_offset(error, attempt)
            resume = resume_offset(attempt, offset, started_at)
            if resume is None:
                break
            started_at = resume
            attempt = blank_before(text, resume)
        except RecursionError:
            syntax.append((SourceLocation(filename, 1, 1), _TOO_DEEP))
            break
        except DefinitionTooLong as long:
            location = SourceLocation(filename, long.token.line or 1, long.token.column or 1)
            message = f"this definition has more than {long.limit} tokens " + limit_hint(
                "max_definition_tokens"
            )
            raise GrammarError(message, location, source=original) from None
        except BlocksTooDeep as deep:
            location = SourceLocation(filename, deep.token.line or 1, deep.token.column or 1)
            raise GrammarError(_TOO_DEEP, location, source=original) from None
    if syntax:
        raise GrammarError(syntax[0][1], syntax[0][0], source=original, problems=syntax)
    builder = AstBuilder(filename)
    try:
        grammar = builder.transform(tree)
    except RecursionError:
        location = SourceLocation(filename, 1, 1)
        raise GrammarError(_TOO_DEEP, location, source=original) from None
    except lark.exceptions.VisitError as error:
        if isinstance(error.orig_exc, RecursionError):
            location = SourceLocation(filename, 1, 1)
            raise GrammarError(_TOO_DEEP, location, source=original) from None
        raise
    grammar = dataclasses.replace(grammar, source=original)
    return grammar, builder.problems


#: CityEngine's viewport and export hints, whose arguments shapegen never reads and which real
#: files fill with CityEngine's own notation (``@Handle(shape=Curb^4, translate={.1,0,0})``).
VIEWPORT_HINTS = ("Handle", "Location", "Out", "Macro")
_VIEWPORT_HINT = re.compile(r"@(?:" + "|".join(VIEWPORT_HINTS) + r")\s*\(")


def blank_viewport_hints(text: str) -> str:
    """``text`` with the arguments of every viewport hint (:data:`VIEWPORT_HINTS`) turned into
    spaces, newlines kept, so that every other place keeps its line and column."""
    pieces = []
    done = 0
    for match in _VIEWPORT_HINT.finditer(text):
        start = match.end()
        if start <= done:
            continue
        end = _closing_parenthesis(text, start)
        if end is None:
            continue  # the parser reports the unclosed parenthesis
        pieces += [text[done:start], re.sub(r"[^\n]", " ", text[start:end])]
        done = end
    return "".join(pieces) + text[done:] if pieces else text


def _closing_parenthesis(text: str, start: int) -> int | None:
    """The index of the ``)`` closing the ``(`` just before ``start``, skipping strings."""
    depth = 1
    index = start
    while index < len(text):
        character = text[index]
        if character == '"':
            end = text.find('"', index + 1)
            while end != -1 and text[end - 1] == "\\":
                end = text.find('"', end + 1)
            if end == -1:
                return None
            index = end
        elif character == "(":
            depth += 1
        elif character == ")":
            depth -= 1
            if depth == 0:
                return index
        index += 1
    return None


def source_too_long(size: int, unit: str) -> str:
    """The message for grammar source over ``max_source_chars`` (refused before parsing)."""
    limit = current_limits().max_source_chars
    return f"the grammar source has {size} {unit}, more than {limit} characters " + limit_hint(
        "max_source_chars"
    )


def parse(text: str, filename: str = "<string>") -> ast.RuleFile:
    """Parse .grammar ``text`` into an :class:`~shapegen.grammar.ast.RuleFile`.

    Parameters
    ----------
    text : str
        The file's contents.
    filename : str
        Name shown in error messages.

    Raises
    ------
    GrammarError
        For syntax errors and for malformed operations (unknown split axis, comp selector or
        center mode, wrong operation argument counts). Names are not resolved here; see
        :func:`shapegen.grammar.check`.
    """
    grammar, problems = parse_with_problems(text, filename)
    if problems:
        problems = sorted(problems, key=_problem_order)
        raise GrammarError(problems[0][1], problems[0][0], source=grammar.source, problems=problems)
    return grammar


def _problem_order(problem: Problem) -> tuple[int, int]:
    location = problem[0]
    return (location.line, location.column) if location is not None else (0, 0)
