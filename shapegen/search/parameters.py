"""The parameters a search may change: the grammar's ``@Free`` attrs (or those named), in their
``@Range``, with the attrs held fixed."""

from __future__ import annotations

__all__ = ["FreeParameter", "RangeWarning", "select_parameters"]

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from shapegen.errors import GrammarError


class RangeWarning(UserWarning):
    """A search was given a starting value outside the attr's ``@Range``: it starts from the
    nearest bound (a search stays within the ranges; a build uses the value as given)."""


@dataclass(frozen=True)
class FreeParameter:
    """A parameter the search may change: its attr name, starting value and bounds."""

    name: str
    initial: float
    lower: float
    upper: float

    @property
    def span(self) -> float:
        return self.upper - self.lower


def select_parameters(
    grammar,
    free: Sequence[str] | None = None,
    fix: Mapping[str, object] | None = None,
    attrs: Mapping[str, object] | None = None,
) -> tuple[list[FreeParameter], dict[str, object]]:
    """The parameters to search and the attrs to build every design with.

    ``free`` names attrs to search (each needs a ``@Range``); by default the ``@Free`` attrs.
    ``fix`` pins attrs (also removing them from the free set). Returns the free parameters and
    the attr overrides (``attrs`` with ``fix`` over them) every evaluated design is built with.
    """
    attrs = dict(attrs or {})
    fix = dict(fix or {})
    catalogue = grammar.catalogue
    unknown = catalogue.first_unknown([*(free or []), *fix])
    if unknown is not None:
        raise GrammarError(f"{grammar.name}: {catalogue.no_attr(unknown)}")
    attrs.update(fix)
    ranges = catalogue.ranges(attrs)
    names = list(free) if free else list(catalogue.free)
    names = [n for n in names if n not in fix]
    if not names:
        raise GrammarError(
            f"{grammar.name}: nothing to optimize: no attr is marked @Free (or all are fixed); "
            "name some with --free"
        )
    parameters = []
    for name in names:
        if catalogue[name].kind != "number":
            raise GrammarError(f"{grammar.name}: attr {name!r} is not a number")
        if name not in ranges:
            raise GrammarError(
                f"{grammar.name}: attr {name!r} has no @Range, so it cannot be a free parameter"
            )
        spec = ranges[name]
        lower, upper, initial = spec["min"], spec["max"], float(spec["value"])
        if not (lower < upper):
            raise GrammarError(f"{grammar.name}: attr {name!r} has an empty @Range")
        start = min(max(initial, lower), upper)
        if start != initial:
            warnings.warn(
                RangeWarning(
                    f"{name} = {initial:g} is outside its @Range [{lower:g}, {upper:g}]: the"
                    f" search starts from the nearest bound, {start:g}"
                ),
                stacklevel=3,
            )
        parameters.append(FreeParameter(name, start, lower, upper))
    return parameters, attrs
