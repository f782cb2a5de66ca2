"""The Inspector's view of a grammar's attrs, and the checks on values a client sends.

Every attr is listed with its kind (number, bool, string, color, file, directory, array), its
current value and the rule's default, its ``@Range`` (a slider) when it has one, whether it is
``@Free``, and what its other annotations ask of the Inspector (step, choices, group, order,
description, hidden: the grammar's attribute catalogue, :mod:`shapegen.engine.attr_catalogue`),
and whether it is a whole number (a count: :mod:`shapegen.editor.counts`), whose slider steps
by 1.
A value sent to the editor is checked here before any work: an unknown name, a value of the wrong
kind, a number that is not finite, a value not among its ``@Enum``'s, a fraction for a count is
a :class:`RequestError` naming it. A number outside its ``@Range`` or off its stepsize is taken,
with a warning the page shows (:func:`range_warnings`): the command line's rule, since a range
is a hint, as in CityEngine.
"""

from __future__ import annotations

__all__ = [
    "AttrSpec",
    "RequestError",
    "attr_specs",
    "checked_values",
    "plain_value",
    "range_warnings",
]

import math
import re
import weakref
from collections.abc import Collection, Mapping
from dataclasses import asdict, dataclass

from shapegen.editor.annotations import asset_choices
from shapegen.editor.counts import count_attrs, is_whole
from shapegen.engine.attr_catalogue import UNIT_RANGES, AttrEntry
from shapegen.errors import ShapegenError

_COLOUR = re.compile(r"#[0-9a-fA-F]{6}")
_ASSETS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # grammar -> {attr: files}


class RequestError(ShapegenError):
    """A request the editor refuses, with the HTTP status it answers with (4xx)."""

    def __init__(self, message: str, status: int = 400):
        super().__init__(message)
        self.status = status


@dataclass(frozen=True)
class AttrSpec:
    """One row of the Inspector.

    ``minimum``, ``maximum`` are the slider's bounds: the ``@Range``'s, or without one the
    default range of an ``@Angle`` or ``@Percent`` (unrestricted), else None; ``ranged``
    says they are a ``@Range``'s, which the search may vary within (``free``). ``step`` is the
    slider's step: the ``@Range`` stepsize, 1 for a ``whole`` number (a count), else about
    1/500 of the range rounded down to a power of ten; ``grid`` is the stepsize a value must
    keep to (from ``minimum``). ``restricted`` False lets a value lie outside the range (or
    the ``choices``); ``user`` says the value is the designer's (set on
    the page, by ``--set`` or by a search) rather than the rule's ``default``. ``unit`` is
    ``angle`` (degrees), ``percent`` (the value 0.1 shown as 10 %) or ``distance`` (metres)
    for an ``@Angle``, ``@Percent`` or ``@Distance`` number, else None.
    """

    name: str
    kind: str  # number, bool, string, color, file, directory or array
    value: object
    minimum: float | None
    maximum: float | None
    step: float | None
    free: bool
    description: str
    whole: bool = False
    default: object = None
    user: bool = False
    restricted: bool = True
    choices: list | None = None
    group: list[str] | None = None
    order: float | None = None
    hidden: bool = False
    display_name: str = ""
    grid: float | None = None  # a restricted @Range's stepsize: values lie on minimum + k grid
    ranged: bool = False
    unit: str | None = None

    def to_json(self) -> dict:
        return asdict(self)


def _step(low: float, high: float) -> float:
    span = high - low
    if not span > 0 or not math.isfinite(span):
        return 1.0
    return 10.0 ** math.floor(math.log10(span / 500.0))


def plain_value(value: object) -> object:
    """A CGA array as a list of its values, anything else as it is."""
    values = getattr(value, "values", None)
    return list(values) if isinstance(values, tuple) else value


def choices_of(grammar, name: str, entry: AttrEntry, values: Mapping[str, object]) -> list | None:
    """The values a drop-down offers for attr ``name``: its ``@Enum`` or ``@Range`` of strings,
    the array its ``@Enum(valuesAttr=...)`` names (at its current value), or the asset files
    (folders) of a ``@File`` (``@Directory``) attr; None for none."""
    if entry.choices is not None:
        return list(entry.choices)
    if entry.values_attr is not None:
        array = grammar.catalogue.get(entry.values_attr)
        default = array.default if array is not None else None
        source = plain_value(values.get(entry.values_attr, default))
        if isinstance(source, list):
            return [float(v) if isinstance(v, int | float) and not isinstance(v, bool) else v
                    for v in source]  # fmt: skip
        return None
    if entry.kind in ("file", "directory"):
        listed = _ASSETS.setdefault(grammar, {})
        if name not in listed:
            listed[name] = asset_choices(
                grammar.path, entry.extensions, directories=entry.kind == "directory"
            )
        return listed[name]
    return None


def attr_specs(
    grammar,
    values: Mapping[str, object],
    user: Collection[str] = (),
    free: Collection[str] | None = None,
) -> list[AttrSpec]:
    """The Inspector rows of ``grammar`` in file order, with the attrs' current ``values`` (the
    built model's final values) and the ranges evaluated for them; ``user`` names the attrs
    whose values are the designer's, ``free`` the attrs the search may change (the ``@Free``
    ones by default)."""
    catalogue = grammar.catalogue
    ranges = catalogue.ranges(values)
    counts = count_attrs(grammar)
    rows = []
    for name, entry in catalogue.items():
        default = entry.default
        value = values.get(name, default)
        spec = ranges.get(name)
        whole = name in counts
        low = high = step = None
        is_free = entry.free if free is None else name in free
        restricted = entry.restricted or is_free
        ranged = spec is not None
        if ranged:
            low, high = float(spec["min"]), float(spec["max"])
        elif (
            entry.kind == "number"
            and entry.unit in UNIT_RANGES
            and not (entry.choices or entry.values_attr)
        ):
            low, high = UNIT_RANGES[entry.unit]  # CityEngine's slider, no bound on the value
            restricted = False
        if low is not None:
            step = entry.step or (1.0 if whole else _step(low, high))
        rows.append(
            AttrSpec(
                name,
                entry.kind,
                plain_value(value),
                low,
                high,
                step,
                is_free,
                entry.description,
                whole,
                default=plain_value(default),
                user=name in user,
                restricted=restricted,
                choices=choices_of(grammar, name, entry, values),
                group=list(entry.group),
                order=entry.order,
                hidden=entry.hidden,
                display_name=entry.display_name,
                grid=entry.step if entry.step and ranged and restricted else None,
                ranged=ranged,
                unit=entry.unit,
            )
        )
    return rows


def checked_values(
    grammar,
    current: Mapping[str, object],
    payload: object,
    free: Collection[str] = (),
) -> dict[str, object]:
    """The attr values of a request body, checked: ``{"name": value, ...}``.

    Numbers must be finite JSON numbers, and whole for a count (one outside its ``@Range``
    or off its stepsize is taken: :func:`range_warnings` says so); booleans ``true``/``false``;
    strings strings, a ``@Color`` ``"#rrggbb"``, one of the ``@Enum``'s values when restricted.
    Raises :class:`RequestError` naming the first problem: 400 for a request the page cannot
    mean, 422 for a fraction given to a count.
    """
    if not isinstance(payload, dict):
        raise RequestError('send a JSON object of attr values, such as {"span": 7.5}')
    if not payload:
        raise RequestError("no attr values given")
    catalogue = grammar.catalogue
    counts = count_attrs(grammar)
    values: dict[str, object] = {}
    for name, value in payload.items():
        if name not in catalogue:
            raise RequestError(catalogue.no_attr(name))
        kind = catalogue[name].kind
        if kind == "number":
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise RequestError(f"attr {name!r} takes a number; got {_shown(value)}")
            try:
                number = float(value)
            except OverflowError:  # an integer beyond a float's range
                number = math.inf
            if not math.isfinite(number):
                raise RequestError(f"attr {name!r} takes a finite number; got {_shown(value)}")
            if name in counts and not is_whole(number):
                raise RequestError(
                    f"attr {name!r} is a count: it takes a whole number; got {number:g}", 422
                )
            value = number
        elif kind == "bool" and not isinstance(value, bool):
            raise RequestError(f"attr {name!r} takes true or false; got {_shown(value)}")
        elif kind == "array":
            raise RequestError(f"attr {name!r} is an array: the editor shows it but cannot set it")
        elif kind not in ("number", "bool") and not isinstance(value, str):
            raise RequestError(f"attr {name!r} takes a string; got {_shown(value)}")
        elif kind == "color" and not _COLOUR.fullmatch(value):
            raise RequestError(
                f'attr {name!r} is a @Color: it takes "#rrggbb"; got {_shown(value)}'
            )
        values[name] = value
    given = {**current, **values}
    for name, value in values.items():
        entry = catalogue[name]
        restricted = entry.restricted or entry.free or name in free
        # an asset not listed may still be found by the asset search: a path is not refused
        choices = None if entry.kind in ("file", "directory") else entry.choices
        if entry.values_attr is not None:
            choices = choices_of(grammar, name, entry, given)
        if restricted and choices is not None:
            if value not in choices:
                listed = ", ".join(_choice(c) for c in choices[:8])
                more = ", ..." if len(choices) > 8 else ""
                raise RequestError(
                    f"attr {name!r} takes one of {listed}{more}; got {_choice(value)}"
                )
    return values


def range_warnings(
    grammar, attrs: Mapping[str, object], values: Mapping[str, object], free: Collection[str] = ()
) -> list[str]:
    """The warnings of the designer's ``attrs`` outside their ``@Range`` or off its stepsize
    (``values``: every attr's value, which a bound may depend on), one line each as the page
    shows them: the command line's ``--set`` rule
    (:meth:`~shapegen.engine.attr_catalogue.AttrCatalogue.range_warnings`)."""
    if not attrs:
        return []
    found = grammar.catalogue.range_warnings(attrs, values, free=free)
    return [f"attr {warning}" for warning in found.values()]


def _choice(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else _shown(value)


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
