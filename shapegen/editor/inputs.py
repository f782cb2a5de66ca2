"""What the designer chooses of a design besides the rule file: their attr values, the seed and
the lot (:class:`Inputs`, one step of the undo history), and the search's settings (which attrs
are free, its margin), with the checks on the values a client sends for them
(``POST /api/settings``, :func:`with_settings`), as functions of the grammar and the values
that :class:`~shapegen.editor.session.EditorSession` passes them.
"""

from __future__ import annotations

__all__ = [
    "MAX_SEED",
    "UNCHANGED",
    "SETTINGS",
    "Inputs",
    "checked_free",
    "checked_lot",
    "checked_margin",
    "checked_seed",
    "free_attrs",
    "ranged_numbers",
    "valid_attrs",
    "with_settings",
]

from collections.abc import Mapping
from dataclasses import dataclass

from shapegen.editor.attrs import RequestError
from shapegen.errors import LotError, ShapegenError
from shapegen.model.lot import Lot
from shapegen.search.defaults import DEFAULT_MARGIN
from shapegen.statics.statics_options import Reserve

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
    margin: Reserve = Reserve(DEFAULT_MARGIN)

    def builds_as(self, other: Inputs) -> bool:
        """Whether ``other`` builds the same design (the search's settings aside)."""
        return (self.attrs, self.seed, self.lot) == (other.attrs, other.seed, other.lot)


SETTINGS = ("free", "margin", "seed", "lot")


def ranged_numbers(grammar, values: Mapping[str, object]) -> set[str]:
    """The attrs of ``grammar`` a search can vary with the attr values ``values``: numbers
    within a ``@Range`` (none when the ranges cannot be worked out)."""
    try:
        return set(grammar.catalogue.ranges(values))
    except ShapegenError:
        return set()


def free_attrs(grammar, free: list[str] | None, values: Mapping[str, object]) -> list[str]:
    """The attrs the search varies and the stable ranges cover: the ``@Free`` ones (``free``
    None), or those the designer chose that the grammar still has with a ``@Range``."""
    if free is None:
        return list(grammar.catalogue.free)
    ranged = ranged_numbers(grammar, values)
    return [name for name in free if name in ranged]


def with_settings(payload: object, current: Inputs, grammar, ranged: set[str]) -> Inputs:
    """``current`` with the settings a client sends (``POST /api/settings``): ``{"free":
    [names] | null, "margin": 0.1, "seed": 3, "lot": [width, depth] | [[x, z], ...] | null}``,
    any of them, each checked; ``free`` null (and ``lot`` null) give back the file's ``@Free``
    attrs (its ``@Lot``). ``ranged``: the attrs that can be free (:func:`ranged_numbers`)."""
    if not isinstance(payload, dict) or not payload:
        raise RequestError(
            'send a JSON object with any of "free", "margin", "seed", "lot", such as'
            ' {"margin": 0.2}'
        )  # fmt: skip
    unknown = sorted(set(payload) - set(SETTINGS))
    if unknown:
        raise RequestError(f"the settings are free, margin, seed and lot; got {unknown[0]!r}")
    free, margin, seed, lot = current.free, current.margin, current.seed, current.lot
    if "free" in payload:
        free = checked_free(payload["free"], grammar, ranged)
    if "margin" in payload:
        margin = checked_margin(payload["margin"])
    if "seed" in payload:
        seed = checked_seed(payload["seed"])
    if "lot" in payload:
        lot = checked_lot(payload["lot"])
    return Inputs(dict(current.attrs), seed, lot, free, margin)


def valid_attrs(grammar, attrs: Mapping[str, object]) -> dict:
    """The values of ``attrs`` that mean something in ``grammar``: an attr it has, of the
    same type, within its range (a value of the history may predate a reload)."""
    catalogue = grammar.catalogue
    kept = {
        name: value
        for name, value in attrs.items()
        if name in catalogue and type(catalogue[name].default) is type(value)
    }
    try:
        ranges = catalogue.ranges(kept)
    except ShapegenError:
        return {}
    return {
        name: value
        for name, value in kept.items()
        if name not in ranges or ranges[name]["min"] <= value <= ranges[name]["max"]
    }


def checked_free(value: object, grammar, ranged: set[str]) -> list[str] | None:
    if value is None:
        return None
    if not isinstance(value, list) or not all(isinstance(n, str) for n in value):
        raise RequestError('"free" is a list of attr names, such as ["span"], or null')
    for name in value:
        if name not in grammar.catalogue:
            raise RequestError(grammar.catalogue.no_attr(name))
        if name not in ranged:
            raise RequestError(
                f"attr {name!r} cannot be free: the search varies numbers within a @Range"
            )  # fmt: skip
    return list(dict.fromkeys(value))


def checked_margin(value: object) -> Reserve:
    """The margin a client sends, made a :class:`~shapegen.statics.statics_options.Reserve` (its one
    check); its refusal is a 4xx."""
    from shapegen.errors import OptionError

    try:
        return Reserve(value)
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
