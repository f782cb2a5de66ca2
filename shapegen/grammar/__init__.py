"""The .grammar language: CityEngine CGA syntax for rules that build block models.

Public entry points:

- :func:`parse` ``(text, filename="<string>") -> ast.Grammar``: syntax only;
- :func:`check` ``(grammar) -> ast.Grammar``: load-time semantic checks (undefined names, argument
  counts, annotations...), raising one :class:`GrammarError` that lists every problem;
- :func:`load` ``(text, filename="<string>") -> ast.Grammar``: both, with the problems of the two
  stages reported together.

The AST node classes are in :mod:`shapegen.grammar.ast`; the language's fixed vocabulary
(operations, builtins, selectors, annotations, reserved attrs) in :mod:`shapegen.grammar.names`.
"""

from __future__ import annotations

from shapegen.errors import GrammarError
from shapegen.grammar import ast, names
from shapegen.grammar.checks import check, find_problems
from shapegen.grammar.parser import parse, parse_with_problems

__all__ = ["GrammarError", "ast", "check", "load", "names", "parse"]


def load(text: str, filename: str = "<string>") -> ast.Grammar:
    """Parse and check .grammar ``text``.

    Parameters
    ----------
    text : str
        The file's contents.
    filename : str
        Name shown in error messages (``file:line:col: message``).

    Returns
    -------
    ast.Grammar
        The checked syntax tree.

    Raises
    ------
    GrammarError
        For the syntax errors of the file, or else for every structural and semantic problem
        found, all in one error (``.problems``), in file order.
    """
    grammar, problems = parse_with_problems(text, filename)
    problems = problems + find_problems(grammar)
    if problems:
        problems = sorted(
            dict.fromkeys(problems),
            key=lambda p: (p[0].line, p[0].column) if p[0] is not None else (0, 0),
        )
        location, message = problems[0]
        raise GrammarError(message, location, source=grammar.source, problems=problems)
    return grammar
