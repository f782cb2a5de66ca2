"""The functions that search the rule file's project (func_fileExists, func_fileSearch,
func_filesSearch, fileRandom's candidates), answered from the files of the project, read once."""

from __future__ import annotations

__all__ = ["file_functions", "project_files"]

import fnmatch
import os
import re
from collections.abc import Callable
from pathlib import Path

from shapegen.engine.expressions.arrays import Array
from shapegen.grammar.import_paths import project_folder
from shapegen.readers.archives import unpacked_package, within


def project_files(rule_file: str | None) -> tuple[Path | None, list[str]]:
    """The project folder of a rule file and every file in it, as CityEngine names them.

    The project is the nearest folder above the rule file that holds a ``rules/`` folder (an
    extracted ``.rpk`` or a CityEngine project), else the rule file's own folder. Paths are
    relative to it, with ``/``, sorted, so that every answer is deterministic.
    """
    if not rule_file or rule_file.startswith("<"):
        return None, []
    folder = Path(rule_file).resolve().parent
    project = project_folder(folder) or folder  # the one rule imports use too
    names = []
    for root, _, files in os.walk(project):
        for name in files:
            names.append(Path(root, name).relative_to(project).as_posix())
            if len(names) > 100_000:
                break
    return project, sorted(names)


def _search_terms(query: str) -> list[str]:
    """func_fileSearch: whitespace means AND; a term in single quotes keeps its spaces."""
    terms = re.findall(r"'([^']*)'|(\S+)", query)
    return [quoted or plain for quoted, plain in terms]


def _search_term(term: str) -> Callable[[str], bool]:
    """A term as a test of a path: a regular expression after ``$``, else ``*`` and ``?``
    wildcards; the whole path must match."""
    if term.startswith("$"):
        try:
            pattern = re.compile(term[1:])
        except re.error as exc:
            raise ValueError(f"bad regular expression {term[1:]!r}: {exc}") from None
    else:
        pattern = re.compile(fnmatch.translate(term.lstrip("/")))
    return lambda path: pattern.fullmatch(path.lstrip("/")) is not None


def _search_forms(project: Path, name: str) -> tuple[str, ...]:
    """A project file's paths a query is matched against (func_fileSearch's pseudocode):
    relative to the assets folder, to the project and to the workspace."""
    forms = [name, f"{project.name}/{name}"]
    if name.startswith("assets/"):
        forms.append(name.removeprefix("assets/"))
    return tuple(forms)


_ANSWERS_KEPT = 1024  # file queries whose answers a rule file's functions keep


def file_functions(rule_file: str | None) -> dict[str, Callable[..., object]]:
    """``fileExists``, ``fileSearch``, ``filesSearch`` and the candidates of ``fileRandom``,
    answered from the files of the rule file's project (:func:`project_files`), read once."""
    cache: list = []

    def files() -> tuple[Path | None, list[str]]:
        if not cache:
            cache.append(project_files(rule_file))
        return cache[0]

    answers: dict[str, tuple[str, ...]] = {}  # a query's files: the project is read once

    def matching(query: object) -> list[str]:
        if type(query) is not str:
            raise ValueError("a file search query is a string")
        found = answers.get(query)
        if found is None:
            project, names = files()
            tests = [_search_term(term) for term in _search_terms(query)]
            if len(answers) >= _ANSWERS_KEPT:  # queries built from numbers: kept bounded
                answers.clear()
            found = answers[query] = tuple(
                "/" + name
                for name in (names if project is not None else ())
                if tests
                and all(any(t(form) for form in _search_forms(project, name)) for t in tests)
            )
        return list(found)

    def exists(path: object) -> bool:
        if type(path) is not str:
            raise ValueError("fileExists() needs a path (a string)")
        project, _ = files()
        if project is None:
            return False
        folder = Path(rule_file).resolve().parent
        candidates = [project / path.lstrip("/"), folder / path]
        package = unpacked_package(rule_file)
        return any(
            candidate.is_file() and (package is None or within(candidate, [package]))
            for candidate in candidates
        )

    def search(query: object) -> str:  # func_fileSearch: a string list, each entry with ";"
        return "".join(f"{name};" for name in matching(query))

    def search_all(query: object) -> Array:
        found = matching(query)
        return Array(tuple(found), 1 if found else 0, len(found))

    return {
        "fileExists": exists,
        "fileSearch": search,
        "filesSearch": search_all,
        "fileRandom": matching,
    }
