"""What reading a rule file finds wrong: a :data:`Problem` is a ``(location, message)`` pair;
:class:`Findings` collects the problems and warnings of one load-time check; :func:`plural`,
:func:`arity` and :func:`show_number` word the counts and numbers in their messages.
"""

from __future__ import annotations

from shapegen.errors import SourceLocation

__all__ = ["Findings", "Problem", "arity", "plural", "show_number"]

#: A problem found in a rule file: where (None for the file as a whole) and what.
Problem = tuple[SourceLocation | None, str]


class Findings:
    """The problems and warnings of one check of a rule file of the dialect ``cga`` or not.

    A problem stops the file from loading; a warning is what CityEngine's compiler only warns
    about, which in a ``.cga`` file is a warning and in a ``.grammar`` file, a strict dialect, a
    problem (:meth:`warn`).
    """

    def __init__(self, cga: bool):
        self.cga = cga
        self.problems: list[Problem] = []
        self.warnings: list[Problem] = []

    def report(self, location: SourceLocation | None, message: str) -> None:
        self.problems.append((location, message))

    def warn(self, location: SourceLocation | None, message: str) -> None:
        """A problem CityEngine's compiler only warns about: in a ``.cga`` file a warning, and
        the file loads; in a ``.grammar`` file an error, as that dialect is strict."""
        if self.cga:
            self.warnings.append((location, message))
        else:
            self.report(location, message)

    def demote_since(self, count: int, suffix: str) -> None:
        """Turn the problems reported after the first ``count`` into warnings that end with
        ``suffix`` (the check that found them only reads a hint CityEngine ignores)."""
        found = self.problems[count:]
        del self.problems[count:]
        for location, message in found:
            self.warn(location, message + suffix)


def plural(count: int, word: str) -> str:
    """``1 argument``, ``2 arguments``."""
    return f"{count} {word}" if count == 1 else f"{count} {word}s"


def arity(low: int, high: int) -> str:
    """How many arguments a signature takes: ``1 argument``, ``2 to 3 arguments``."""
    if low == high:
        return plural(low, "argument")
    return f"{low} to {high} arguments"


def show_number(value: float) -> str:
    """A number as a message shows it: ``3``, ``0.25``, ``1e+06``."""
    return f"{value:g}"
