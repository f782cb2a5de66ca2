"""The .grammar language: CityEngine CGA syntax for rules that build block models.

Public entry points:

- :func:`parse` ``(text, filename="<string>") -> ast.RuleFile``: syntax only;
- :func:`check` ``(grammar) -> ast.RuleFile``: load-time semantic checks (undefined names, argument
  counts, annotations...), raising one :class:`GrammarError` that lists every problem;
- :func:`load` ``(text, filename="<string>", origin=None) -> ast.RuleFile``: both, with the
  problems of the two stages reported together, and the files it imports merged in
  (:mod:`shapegen.grammar.imports`; paths relative to ``origin``'s folder, or to the working
  directory without one).

The AST node classes are in :mod:`shapegen.grammar.ast`; the language's fixed vocabulary
(operations, builtins, selectors, annotations, reserved attrs) in :mod:`shapegen.grammar.names`.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from shapegen.errors import GrammarError, SourceLocation
from shapegen.grammar import ast, names
from shapegen.grammar.checks import check, examine
from shapegen.grammar.imports import resolve_imports, used_definitions
from shapegen.grammar.parser import parse, parse_with_problems

__all__ = ["GrammarError", "FilesGrammarError", "ast", "check", "load", "names", "parse"]


class FilesGrammarError(GrammarError):
    """A :class:`GrammarError` whose problems may lie in several files (an importing file and
    the files it imports): each problem's caret is drawn under its own file's line."""

    def __init__(self, grammar: ast.RuleFile, problems: list[tuple[SourceLocation | None, str]]):
        self.grammar = grammar
        location, message = problems[0]
        file = location.file if location is not None else None
        super().__init__(message, location, source=grammar.source_of(file), problems=problems)

    def _render(self) -> str:
        parts = []
        for location, message in self.problems:
            source = self.grammar.source_of(location.file if location is not None else None)
            parts.append(GrammarError(message, location, source)._render())
        return "\n".join(parts)


def load(
    text: str,
    filename: str = "<string>",
    origin: str | Path | None = None,
    warnings: tuple[str, ...] = (),
    search_folders: tuple[Path, ...] = (),
) -> ast.RuleFile:
    """Parse and check .grammar ``text``, with the files it imports merged in.

    Parameters
    ----------
    text : str
        The file's contents.
    filename : str
        Name shown in error messages (``file:line:col: message``).
    origin : str or Path, optional
        The file the text was read from: its ``import`` paths are relative to its folder (and
        project). Without one they are relative to the working directory.
    warnings : tuple of str
        Warnings of reading the file (its encoding), put first in the grammar's ``warnings``.
    search_folders : tuple of Path
        Folders imports are looked up in after the file's own project (the user's rules path).

    Returns
    -------
    ast.RuleFile
        The checked syntax tree.

    Raises
    ------
    GrammarError
        For the syntax errors of the file, or else for every structural and semantic problem
        found, all in one error (``.problems``), in file order.
    """
    grammar, problems = parse_with_problems(text, filename)
    if grammar.imports or any(isinstance(n, ast.DynamicImport) for n in ast.walk(grammar)):
        grammar, imported, failed = resolve_imports(grammar, origin, search_folders)
        problems = problems + imported
    else:
        failed = set()
    found, found_warnings = examine(grammar)
    problems = problems + [p for p in found if not any(f"'{f}." in p[1] for f in failed)]
    if problems:
        # the importing file's problems first, then each imported file's, each in line order
        files = list(dict.fromkeys([grammar.filename, *(p[0].file for p in problems if p[0])]))
        problems = sorted(
            dict.fromkeys(problems),
            key=lambda p: (
                (files.index(p[0].file), p[0].line, p[0].column) if p[0] is not None else (0, 0, 0)
            ),
        )
        if grammar.sources:
            raise FilesGrammarError(grammar, problems)
        location, message = problems[0]
        raise GrammarError(message, location, source=grammar.source, problems=problems)
    warnings = (*warnings, *grammar.warnings, *(_warning_line(w) for w in found_warnings))
    if warnings:
        grammar = dataclasses.replace(grammar, warnings=warnings)
    return used_definitions(grammar)


def _warning_line(problem: tuple[SourceLocation | None, str]) -> str:
    location, message = problem
    return f"{location}: {message}" if location is not None else message
