"""What the designer chooses of a design besides the rule file: their attr values, the seed and
the lot (:class:`Inputs`, one step of the undo history), and the search's settings (which attrs
are free, its margin), with the checks on the values a client sends for them
(``POST /api/settings``).

:class:`SettingsMixin` is mixed into :class:`~shapegen.editor.session.EditorSession`, which
provides ``grammar``, ``attrs``, ``seed``, ``lot``, ``margin``, ``_free`` and the change
machinery (``_take_work``, ``_apply``, ``_changed``, ``state``).
"""

from __future__ import annotations

__all__ = [
    "MAX_SEED",
    "UNCHANGED",
    "Inputs",
    "SettingsMixin",
    "checked_free",
    "checked_lot",
    "checked_margin",
    "checked_seed",
    "valid_attrs",
]

from collections.abc import Mapping
from dataclasses import dataclass

from shapegen.editor.attrs import RequestError
from shapegen.errors import LotError, ShapegenError
from shapegen.model.lot import Lot
from shapegen.search.defaults import DEFAULT_MARGIN

UNCHANGED = object()  # an argument not given (None is a value: the file's @Lot)
MAX_SEED = 2**63 - 1


@dataclass(frozen=True)
class Inputs:
    """What the designer chose of a design: their attr values, the seed, the lot (None: the
    file's ``@Lot``), the attrs the search varies (None: the file's ``@Free`` ones) and its
    margin; one step of the undo history."""

    attrs: dict
    seed: int
    lot: Lot | None
    free: list[str] | None = None
    margin: float = DEFAULT_MARGIN

    def builds_as(self, other: Inputs) -> bool:
        """Whether ``other`` builds the same design (the search's settings aside)."""
        return (self.attrs, self.seed, self.lot) == (other.attrs, other.seed, other.lot)


class SettingsMixin:
    """The search's settings and the derivation's, on the page."""

    @property
    def free_attrs(self) -> list[str]:
        """The attrs the search varies and the stable ranges cover: the ``@Free`` ones, or
        those the designer chose (``POST /api/settings``) that the grammar still has with a
        ``@Range``."""
        if self._free is None:
            return list(self.grammar.free_parameters)
        ranged = self._ranged_numbers()
        return [name for name in self._free if name in ranged]

    def _ranged_numbers(self) -> set[str]:
        try:
            ranges = self.grammar.parameter_ranges(self._current_values())
        except ShapegenError:
            return set()
        defaults = self.grammar.attrs
        return {n for n in ranges if isinstance(defaults.get(n), float)}

    def settings(self, payload: object) -> dict:
        """The search's settings and the derivation's: ``{"free": [names] | null, "margin":
        0.1, "seed": 3, "lot": [width, depth] | [[x, z], ...] | null}``, any of them. ``free``
        null (and ``lot`` null) give back the file's ``@Free`` attrs (its ``@Lot``). Each change is
        a step of the undo history, as an attr's is; a new seed or lot rebuilds the design,
        new free attrs restart the stable-range scans."""
        if not isinstance(payload, dict) or not payload:
            raise RequestError(
                'send a JSON object with any of "free", "margin", "seed", "lot", such as'
                ' {"margin": 0.2}'
            )  # fmt: skip
        unknown = sorted(set(payload) - {"free", "margin", "seed", "lot"})
        if unknown:
            raise RequestError(
                f"the settings are free, margin, seed and lot; got {unknown[0]!r}"
            )  # fmt: skip
        free, margin = self._free, self.margin
        if "free" in payload:
            free = checked_free(payload["free"], self.grammar, self._ranged_numbers())
        if "margin" in payload:
            margin = checked_margin(payload["margin"])
        seed = checked_seed(payload["seed"]) if "seed" in payload else self.seed
        lot = checked_lot(payload["lot"]) if "lot" in payload else self.lot
        if not self._take_work():
            raise RequestError("a search is running; wait for it or POST /api/cancel", 409)
        try:
            return self._apply(Inputs(dict(self.attrs), seed, lot, free, margin))
        finally:
            self._work.release()


def valid_attrs(grammar, attrs: Mapping[str, object]) -> dict:
    """The values of ``attrs`` that mean something in ``grammar``: an attr it has, of the
    same type, within its range (a value of the history may predate a reload)."""
    kept = {}
    defaults = grammar.attrs
    for name, value in attrs.items():
        if name in defaults and type(defaults[name]) is type(value):
            kept[name] = value
    try:
        ranges = grammar.parameter_ranges(kept)
    except ShapegenError:
        return {}
    return {
        name: value
        for name, value in kept.items()
        if name not in ranges
        or not isinstance(value, float)
        or ranges[name]["min"] <= value <= ranges[name]["max"]
    }


def checked_free(value: object, grammar, ranged: set[str]) -> list[str] | None:
    if value is None:
        return None
    if not isinstance(value, list) or not all(isinstance(n, str) for n in value):
        raise RequestError('"free" is a list of attr names, such as ["span"], or null')
    for name in value:
        if name not in grammar.attrs:
            raise RequestError(f"the grammar has no attr {name!r}")
        if name not in ranged:
            raise RequestError(
                f"attr {name!r} cannot be free: the search varies numbers within a @Range"
            )  # fmt: skip
    return list(dict.fromkeys(value))


def checked_margin(value: object) -> float:
    """The margin a client sends, checked by the one margin check; its refusal is a 4xx."""
    from shapegen.errors import OptionError
    from shapegen.statics.options import checked_margin as margin_check

    try:
        return margin_check(value)
    except OptionError as exc:
        raise RequestError(f'"margin": {exc}') from None


def checked_seed(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= MAX_SEED:
        raise RequestError(f'"seed" is a whole number from 0 to {MAX_SEED}; got {value!r}')
    return value


def checked_lot(value: object) -> Lot | None:
    """A lot from JSON: null (the file's ``@Lot``), ``[width, depth]`` (m) or ``[[x, z], ...]``
    (m), checked by the one lot check; its refusal is a 422 naming ``"lot"``."""
    if value is None:
        return None
    try:
        return Lot.of(value)
    except LotError as exc:
        raise RequestError(f'"lot": {exc}', 422) from None
