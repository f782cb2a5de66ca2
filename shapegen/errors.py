"""The one error hierarchy of shapegen.

Every mistake a user can make (a malformed grammar, an impossible dimension, an unreadable file)
raises a subclass of :class:`ShapegenError`. The command line prints its message and exits with
status 2; it never shows a traceback for these. A solver outcome (infeasible, not converged) is not
an error: it is a status on the result.
"""

from __future__ import annotations

__all__ = [
    "ShapegenError",
    "GrammarError",
    "OperationError",
    "GeometryError",
    "StaticsError",
    "InputFormatError",
    "LotError",
    "OptionError",
    "PluginError",
    "SourceLocation",
    "WorkLimitError",
    "did_you_mean",
]

import difflib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass


class ShapegenError(Exception):
    """Root of every error shapegen raises for a user's mistake."""


@dataclass(frozen=True)
class SourceLocation:
    """A place in a text file: 1-based line and column."""

    file: str
    line: int
    column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


#: Characters of a source line shown under an error; a longer line is shown around the caret.
_SHOWN_LINE = 160


class GrammarError(ShapegenError):
    """A problem in a .grammar file, with its place and the offending source line.

    Several problems found in one pass are carried together in ``problems`` (each a
    ``(SourceLocation | None, message)`` pair); ``str()`` renders them all, each with its source
    line and a caret under the column.
    """

    def __init__(
        self,
        message: str,
        location: SourceLocation | None = None,
        source: str | None = None,
        problems: list[tuple[SourceLocation | None, str]] | None = None,
    ):
        self.location = location
        self.source = source
        found = problems if problems is not None else [(location, message)]
        # The same problem at the same place is shown once (error recovery may meet it twice).
        self.problems = list(dict.fromkeys(found))
        self.message = message
        super().__init__(self._render())

    @property
    def line(self) -> int | None:
        return self.location.line if self.location else None

    @property
    def column(self) -> int | None:
        return self.location.column if self.location else None

    def _render(self) -> str:
        lines = self.source.splitlines() if self.source is not None else []
        parts = []
        for location, message in self.problems:
            if location is None:
                parts.append(message)
                continue
            text = f"{location}: {message}"
            if 1 <= location.line <= len(lines):
                source_line = lines[location.line - 1].expandtabs(1)
                column = max(location.column - 1, 0)
                if len(source_line) > _SHOWN_LINE:  # a window around the caret
                    start = max(0, min(column - _SHOWN_LINE // 2, len(source_line) - _SHOWN_LINE))
                    source_line = source_line[start : start + _SHOWN_LINE]
                    column -= start
                    if start > 0:
                        source_line, column = "..." + source_line[3:], column
                    if start + _SHOWN_LINE < len(lines[location.line - 1]):
                        source_line = source_line[:-3] + "..."
                caret = " " * column + "^"
                text += f"\n    {source_line}\n    {caret}"
            parts.append(text)
        return "\n".join(parts)


class OperationError(GrammarError):
    """An operation met a bad argument or degenerate geometry while deriving (``extrude()`` of
    a face with no area, a roof's overhang larger than its face). In a ``.cga`` file it is a CGA
    error of CityEngine's runtime: a warning at its place, the operation is skipped and the
    derivation carries on; in a ``.grammar`` file it stops the derivation."""


class GeometryError(ShapegenError):
    """An impossible or degenerate shape: zero volume, non-convex block, NaN, interpenetration."""


class StaticsError(ShapegenError):
    """A model that cannot be analysed as given (no support, disconnected blocks...)."""


class InputFormatError(ShapegenError):
    """A file that cannot be read: unknown format, missing keys, wrong types."""


class LotError(InputFormatError):
    """What cannot be a lot (:class:`~shapegen.model.lot.Lot`): one line without the place it
    came from, which each front end adds in its own words (``--lot '0,0 1,1': ...``, the
    design page's ``"lot": ...``, a city's failed row)."""


class OptionError(ShapegenError):
    """A choice that means nothing for what it was given to: a value outside an option's range
    or list, an option that does not apply (refused, never dropped), an unknown structure or
    primitive name, a ``@Structure`` argument of the wrong kind.

    ``option`` names the option refused, where one is (a field of an options type), so that a
    front end can say it in its own words (``--kern`` on the command line)."""

    def __init__(self, message: str, option: str | None = None):
        super().__init__(message)
        self.option = option


class PluginError(ShapegenError):
    """An extension that cannot be used as installed: a plug-in package that fails to load, or
    a primitive or structure registered under a name another one holds."""


class WorkLimitError(ShapegenError):
    """Work past one of the work limits (:mod:`shapegen.limits`) where no rule's place is at
    hand (a geometry kernel's loop, a writer); the message names the limit and how to raise it.
    A derivation reports it at the operation that ran, and never carries on past it."""


def did_you_mean(
    name: object,
    known: Iterable[str],
    *,
    most: int = 1,
    cutoff: float = 0.6,
    parenthesised: bool = False,
    shown: Mapping[str, str] | None = None,
) -> str:
    """The hint an error gives after a name nothing has: ``; did you mean 'x'?`` for the
    closest of ``known`` (up to ``most`` of them, joined by "or"), `` (did you mean 'x'?)``
    with ``parenthesised``, or ``""`` when none is close (``cutoff``: difflib's ratio, 0 to 1).
    ``shown`` gives the name shown for a known one where they differ (a file's stem, compared,
    and its file name, shown).
    Every "did you mean" of the package is this one, so each near miss reads alike.

    >>> did_you_mean("heigth", ["height", "width"])
    "; did you mean 'height'?"
    >>> did_you_mean("arc", ["arch", "dome"], parenthesised=True)
    " (did you mean 'arch'?)"
    >>> did_you_mean("spam", ["height"])
    ''
    """
    close = difflib.get_close_matches(str(name), sorted(set(known)), n=most, cutoff=cutoff)
    if not close:
        return ""
    shown = shown or {}
    hint = f"did you mean {' or '.join(repr(shown.get(c, c)) for c in close)}?"
    return f" ({hint})" if parenthesised else f"; {hint}"
