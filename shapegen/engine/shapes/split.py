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

``best_counts=True`` (CityEngine rule files, ``.cga``) follows CityEngine's runtime: op_split
says "the number of repetitions and floating dimensions are adapted to the best solution (best
number of repetitions and least stretching)", and PyPRT lays a group nested in a sequence out
0 or more times, the counts that bring the floating parts' common scale s closest to 1 (least
``|s - 1|``). Checked on candler's windows, ``{ { ~w/n : Window | 0.25 : Wall }* | ~w/n :
Window }`` on w = 1.93 m: one window for n = 1 (no repetition, s = 1), two of 0.84 m for n = 2,
three of 0.48 m for n = 3 (s = 0.74 beats two windows' 1.31).
"""

from __future__ import annotations

__all__ = [
    "BEST_COUNT_COMBINATIONS",
    "ABSOLUTE",
    "FLOATING",
    "RELATIVE",
    "PieceLimitError",
    "SplitPart",
    "SplitPiece",
    "SplitRepeat",
    "resolve_split",
]

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

from shapegen.limits import check_clock
from shapegen.tolerances import REPEAT_SLACK, SPLIT_SLACK_REL

BEST_COUNT_COMBINATIONS = 10_000
"""Most combinations of counts tried for the groups of one sequence (``best_counts``); beyond it
the groups are laid out as floating parts."""

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
    best_counts: bool = False,
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
    best_counts
        Repeat groups nested in a sequence take the counts (0 or more) that stretch the floating
        parts least, as CityEngine's runtime does; else each is a floating part.

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
    items = (pattern,) if isinstance(pattern, SplitRepeat) else tuple(pattern)
    memo = (total, best_counts, _pattern_key(items))
    known = _laid_out.get(memo)
    if known is not None and known[0] <= max_pieces:
        return list(known[1])
    resolver = _Resolver(total, max_pieces, best_counts)
    for item in _all_parts(items):
        if not math.isfinite(item.size):
            raise ValueError(f"split size {item.size} is not a finite number")
    resolver.sequence(items, 0.0, total)
    if len(_laid_out) >= _LAID_OUT_SIZE:
        _laid_out.clear()
    needed = max(resolver.peak, len(resolver.pieces))
    _laid_out[memo] = (needed, tuple(resolver.pieces), items)
    return resolver.pieces


# Layouts already resolved: a building splits its floors and windows over the same lengths
# again and again (candler: 557 splits, 28 distinct). Keyed by the length and the pattern's
# sizes, modes and part keys (by identity: the entry holds the pattern, so its keys stay alive);
# each entry records the piece limit it needs, so a smaller limit is still refused as before.
_LAID_OUT_SIZE = 4096
_laid_out: dict[tuple, tuple] = {}


def _pattern_key(items) -> tuple:
    return tuple(
        ("*", _pattern_key(item.items))
        if isinstance(item, SplitRepeat)
        else (item.size, item.mode, id(item.key))
        for item in items
    )


def _all_parts(items):
    for item in items:
        if isinstance(item, SplitRepeat):
            yield from _all_parts(item.items)
        else:
            yield item


class _Resolver:
    """Lays pieces out into ``pieces``, cutting each at the end of the span it belongs to."""

    def __init__(self, total: float, max_pieces: int, best_counts: bool = False):
        self.total = total
        self.best_counts = best_counts
        # Rounding in running sums must not create slivers or drop a last full piece.
        self.eps = SPLIT_SLACK_REL * total
        self.max_pieces = max_pieces
        self.pieces: list[SplitPiece] = []
        self.peak = 0.0  # the most pieces a repeat count was checked for

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
        if self.best_counts and any(isinstance(item, SplitRepeat) for item in items):
            best = self._best_counts(items, length)
            if best is not None:
                self._counted(items, *best, start, length)
                return
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

    def _weights(self, item: SplitItem) -> tuple[float, float]:
        """``(fixed, floating)`` nominal lengths of one item (a group: of one repetition; a group
        nested in it counts as floating)."""
        if isinstance(item, SplitRepeat):
            parts = [self._weights(sub) if isinstance(sub, SplitPart) else (0.0, self.nominal(sub))
                     for sub in item.items]  # fmt: skip
            return sum(p[0] for p in parts), sum(p[1] for p in parts)
        n = self.nominal(item)
        return (0.0, n) if item.mode == FLOATING else (n, 0.0)

    def _best_counts(self, items, length: float) -> tuple[list[int], float] | None:
        """The repetitions of each group in ``items`` (0 or more) that bring the floating parts'
        scale closest to 1, and that scale; None when there is no floating part or too many
        combinations."""
        fixed = floating = 0.0
        groups = []
        for item in items:
            if isinstance(item, SplitRepeat):
                groups.append(self._weights(item))
            else:
                f, w = self._weights(item)
                fixed, floating = fixed + f, floating + w
        room = length - fixed
        if room < -self.eps or (floating <= 0 and not any(w > 0 for _, w in groups)):
            return None
        ranges = []
        for f, w in groups:
            period = f + w
            if period <= 0:
                ranges.append(range(1))
                continue
            self._check_count(room / period, items)
            ranges.append(range(int(max(room, 0.0) / period) + 2))
        if math.prod(len(r) for r in ranges) > BEST_COUNT_COMBINATIONS:
            return None
        best = None
        for counts in itertools.product(*ranges):
            used = sum(k * f for k, (f, _) in zip(counts, groups, strict=True))
            weight = floating + sum(k * w for k, (_, w) in zip(counts, groups, strict=True))
            left = room - used
            if left < -self.eps:
                continue
            if weight <= 0:
                if left > self.eps:
                    continue
                scale = 1.0
            else:
                scale = left / weight
            key = (round(abs(scale - 1.0), 12), sum(counts), [-k for k in counts])
            if best is None or key < best[0]:
                best = (key, list(counts), scale)
        return None if best is None else (best[1], best[2])

    def _counted(self, items, counts: list[int], scale: float, start: float, length: float):
        """Lay out ``items`` with the groups repeated ``counts`` times and the floating parts
        scaled by ``scale``."""
        counts = iter(counts)
        cursor, end = start, start + length
        for item in items:
            if isinstance(item, SplitRepeat):
                fixed, weight = self._weights(item)
                step = fixed + weight * scale
                for _ in range(next(counts)):
                    check_clock()
                    if step <= 0 or cursor >= end - self.eps:
                        break
                    self.sequence(item.items, cursor, min(step, end - cursor))
                    cursor += step
                continue
            size = self.nominal(item) * (scale if item.mode == FLOATING else 1.0)
            if size <= 0:
                continue
            if cursor >= end - self.eps:
                return
            size = min(size, end - cursor)
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
                check_clock()
                self.sequence(items, start + k * step, step)
            return
        # Only fixed sizes: whole repetitions, then one more cut at the end.
        count = math.floor(length / period + REPEAT_SLACK) + 1
        self._check_count(count, items)
        end = start + length
        for k in range(count):
            check_clock()
            offset = start + k * period
            if offset >= end - self.eps:
                break
            self.sequence(items, offset, min(period, end - offset))

    def _check_count(self, count: float, items: tuple[SplitItem, ...]) -> None:
        pieces = count * len(items)
        self.peak = max(self.peak, pieces)
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
