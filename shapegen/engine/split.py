"""Split-size resolution: CityEngine's rules for absolute, relative, floating and repeated parts.

A split pattern is a sequence of :class:`SplitPart` (a size with its mode) and :class:`SplitRepeat`
(a ``{ ... }*`` group, possibly nested). :func:`resolve_split` turns a pattern and the length of
the scope along the split axis into the pieces to create, each with its start and size (metres).

The rules, as CityEngine documents them:

- absolute ``2`` is exactly 2 m; relative ``'0.3`` is 0.3 x the scope's length along the axis;
  floating ``~2`` is a weight: the floating parts share what the absolute and relative parts leave,
  in proportion to their sizes (``{ 3.3:Z | ~3:Y | 5:X }`` on 10 gives Y = 1.7);
- a size <= 0 creates no piece and takes no room;
- pieces are laid out from the scope's origin; a piece running past the scope's end is cut there
  and a piece starting at or past the end is dropped; with no floating part, room left over stays
  empty;
- a repeat ``{ ... }*`` made only of absolute and relative parts is laid out as many times as it
  fits and then once more, cut at the end (``{ 2:X | 1:Y }*`` on 10 gives X Y X Y X Y X, the last
  X 1 m long); a repeat with floating parts is laid out a whole number n >= 1 of times, n chosen so
  that one repetition is as close as possible to its nominal length, and the floating parts absorb
  the difference (``{ ~2.1:G }*`` on 10 gives 5 pieces of 2).

Where the documentation is silent, shapegen decides (and docs/grammar.md says so): a repeat group
nested in a sequence behaves like a floating part whose weight is its nominal length (the sum of
its parts' sizes), and a nested group makes an enclosing repeat adjustable like a floating part.
"""

from __future__ import annotations

__all__ = [
    "ABSOLUTE",
    "FLOATING",
    "RELATIVE",
    "PieceLimitError",
    "SplitPart",
    "SplitPiece",
    "SplitRepeat",
    "resolve_split",
]

import math
from collections.abc import Sequence
from dataclasses import dataclass

from shapegen.tolerances import REPEAT_SLACK, SPLIT_SLACK_REL

ABSOLUTE = "absolute"
RELATIVE = "relative"
FLOATING = "floating"


@dataclass(frozen=True)
class SplitPart:
    """One part of a split pattern: ``size`` (m, a fraction for relative, a weight for floating),
    its ``mode`` (:data:`ABSOLUTE`, :data:`RELATIVE` or :data:`FLOATING`) and a ``key`` that comes
    back with each piece the part creates (the interpreter passes the part's operations)."""

    size: float
    mode: str = ABSOLUTE
    key: object = None


@dataclass(frozen=True)
class SplitRepeat:
    """A repeat group ``{ ... }*`` of parts and nested groups."""

    items: tuple[SplitPart | SplitRepeat, ...]


@dataclass(frozen=True)
class SplitPiece:
    """A piece to create: the ``key`` of its part, its ``start`` and ``size`` along the axis (m)."""

    key: object
    start: float
    size: float


SplitItem = SplitPart | SplitRepeat


class PieceLimitError(ValueError):
    """A split would create more pieces than the caller allows."""


def resolve_split(
    total: float,
    pattern: Sequence[SplitItem] | SplitRepeat,
    *,
    max_pieces: int = 1_000_000,
) -> list[SplitPiece]:
    """The pieces a split of a scope ``total`` metres long creates, in order along the axis.

    Parameters
    ----------
    total
        Length of the scope along the split axis, m.
    pattern
        The parts in order; pass a :class:`SplitRepeat` for a top-level ``{ ... }*``.
    max_pieces
        Raise :class:`PieceLimitError` (a ``ValueError``) if the split would create more pieces
        than this (a runaway repeat such as ``{ 0.000001 : A }*``).

    Returns
    -------
    list[SplitPiece]
        Only pieces of positive size inside ``[0, total]``.

    Examples
    --------
    >>> [round(p.size, 6) for p in resolve_split(10, [SplitPart(3.3), SplitPart(3, FLOATING),
    ...                                               SplitPart(5)])]
    [3.3, 1.7, 5.0]
    """
    total = float(total)
    if not math.isfinite(total) or total <= 0:
        return []
    resolver = _Resolver(total, max_pieces)
    items = (pattern,) if isinstance(pattern, SplitRepeat) else tuple(pattern)
    for item in _all_parts(items):
        if not math.isfinite(item.size):
            raise ValueError(f"split size {item.size} is not a finite number")
    resolver.sequence(items, 0.0, total)
    return resolver.pieces


def _all_parts(items):
    for item in items:
        if isinstance(item, SplitRepeat):
            yield from _all_parts(item.items)
        else:
            yield item


class _Resolver:
    """Lays pieces out into ``pieces``, cutting each at the end of the span it belongs to."""

    def __init__(self, total: float, max_pieces: int):
        self.total = total
        # Rounding in running sums must not create slivers or drop a last full piece.
        self.eps = SPLIT_SLACK_REL * total
        self.max_pieces = max_pieces
        self.pieces: list[SplitPiece] = []

    def nominal(self, item: SplitItem) -> float:
        """Length of an item before any floating adjustment, m (0 for non-positive sizes)."""
        if isinstance(item, SplitRepeat):
            return sum(self.nominal(sub) for sub in item.items)
        size = item.size * self.total if item.mode == RELATIVE else item.size
        return float(size) if size > 0 else 0.0

    @staticmethod
    def flexible(item: SplitItem) -> bool:
        return isinstance(item, SplitRepeat) or item.mode == FLOATING

    def sequence(self, items: tuple[SplitItem, ...], start: float, length: float) -> None:
        """Lay out ``items`` once over ``[start, start + length]``; floating parts fill the rest."""
        nominal = [self.nominal(item) for item in items]
        fixed = sum(n for item, n in zip(items, nominal, strict=True) if not self.flexible(item))
        weights = sum(n for item, n in zip(items, nominal, strict=True) if self.flexible(item))
        room = length - fixed
        scale = room / weights if room > self.eps and weights > 0 else 0.0
        end = start + length
        cursor = start
        for item, n in zip(items, nominal, strict=True):
            size = n * scale if self.flexible(item) else n
            if size <= 0:
                continue
            if cursor >= end - self.eps:
                return
            size = min(size, end - cursor)
            if size <= self.eps:
                return
            if isinstance(item, SplitRepeat):
                self.repeat(item.items, cursor, size)
            else:
                self.add(SplitPiece(item.key, cursor, size))
            cursor += size

    def repeat(self, items: tuple[SplitItem, ...], start: float, length: float) -> None:
        """Lay out a repeat group over ``[start, start + length]``."""
        period = sum(self.nominal(item) for item in items)
        if period <= 0:
            return
        # A period far below the span (5e-324 of 10 m) asks for more pieces than any limit, or
        # than a float can count: refuse it before converting the count to an int.
        self._check_count(length / period, items)
        if any(self.flexible(item) and self.nominal(item) > 0 for item in items):
            count = _closest_count(length, period)
            self._check_count(count, items)
            step = length / count
            for k in range(count):
                self.sequence(items, start + k * step, step)
            return
        # Only fixed sizes: whole repetitions, then one more cut at the end.
        count = math.floor(length / period + REPEAT_SLACK) + 1
        self._check_count(count, items)
        end = start + length
        for k in range(count):
            offset = start + k * period
            if offset >= end - self.eps:
                break
            self.sequence(items, offset, min(period, end - offset))

    def _check_count(self, count: float, items: tuple[SplitItem, ...]) -> None:
        pieces = count * len(items)
        if not pieces <= self.max_pieces:  # also true for an infinite count
            shown = f"{pieces:.3g}" if pieces < 1e15 else "more than 1e15"
            raise PieceLimitError(
                f"the repeat would create about {shown} pieces, more than the limit "
                f"of {self.max_pieces}"
            )

    def add(self, piece: SplitPiece) -> None:
        self.pieces.append(piece)
        if len(self.pieces) > self.max_pieces:
            raise PieceLimitError(f"the split creates more than {self.max_pieces} pieces")


def _closest_count(length: float, period: float) -> int:
    """The number n >= 1 of repetitions whose length ``length / n`` is closest to ``period``."""
    ratio = length / period
    low = max(1, math.floor(ratio))
    high = low + 1
    return low if abs(length / low - period) <= abs(length / high - period) else high
