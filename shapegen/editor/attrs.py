"""The Inspector's view of a grammar's attrs, and the checks on values a client sends.

Every attr is listed with its kind (number, boolean or string), its current value, its
``@Range`` (a slider) when it has one, whether it is ``@Free`` and its ``@Description``, and
whether it is a whole number (a count: :mod:`shapegen.editor.counts`), whose slider steps by 1.
A value sent to the editor is checked here before any work: an unknown name, a value of the wrong
kind, a number that is not finite or lies outside its ``@Range``, a fraction for a count is a
:class:`RequestError` naming it.
"""

from __future__ import annotations

__all__ = ["AttrSpec", "RequestError", "attr_specs", "checked_values"]

import difflib
import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass

from shapegen.editor.counts import count_attrs, is_whole
from shapegen.errors import ShapegenError
from shapegen.grammar.ast import String


class RequestError(ShapegenError):
    """A request the editor refuses, with the HTTP status it answers with (4xx)."""

    def __init__(self, message: str, status: int = 400):
        super().__init__(message)
        self.status = status


@dataclass(frozen=True)
class AttrSpec:
    """One row of the Inspector.

    ``minimum``, ``maximum`` are the ``@Range`` bounds (None without one); ``step`` is the
    slider's step: 1 for a ``whole`` number (a count), else about 1/500 of the range rounded
    down to a power of ten.
    """

    name: str
    kind: str  # "number", "boolean" or "string"
    value: object
    minimum: float | None
    maximum: float | None
    step: float | None
    free: bool
    description: str
    whole: bool = False

    def to_json(self) -> dict:
        return asdict(self)


def _kind(value: object) -> str:
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int | float):
        return "number"
    return "string"


def _description(node) -> str:
    annotation = node.annotation("Description")
    if annotation is None or not annotation.args:
        return ""
    first = annotation.args[0]
    return first.value if isinstance(first, String) else ""


def _step(low: float, high: float) -> float:
    span = high - low
    if not span > 0 or not math.isfinite(span):
        return 1.0
    return 10.0 ** math.floor(math.log10(span / 500.0))


def attr_specs(grammar, values: Mapping[str, object]) -> list[AttrSpec]:
    """The Inspector rows of ``grammar`` in file order, with the attrs' current ``values`` (the
    built model's final values) and the ranges evaluated for them."""
    ranges = grammar.parameter_ranges(dict(values))
    nodes = grammar.program.attr_nodes
    counts = count_attrs(grammar)
    rows = []
    for name, default in grammar.attrs.items():
        value = values.get(name, default)
        spec = ranges.get(name)
        whole = name in counts
        low = high = step = None
        if spec is not None:
            low, high = float(spec["min"]), float(spec["max"])
            step = 1.0 if whole else _step(low, high)
        node = nodes[name]
        kind, free, description = _kind(default), node.free, _description(node)
        rows.append(AttrSpec(name, kind, value, low, high, step, free, description, whole))
    return rows


def checked_values(grammar, current: Mapping[str, object], payload: object) -> dict[str, object]:
    """The attr values of a request body, checked: ``{"name": value, ...}``.

    Numbers must be finite JSON numbers within the attr's ``@Range`` (evaluated with the new
    values, since a bound may depend on another attr), and whole for a count; booleans
    ``true``/``false``; strings strings. Raises :class:`RequestError` naming the first problem:
    400 for a request the page cannot mean, 422 for a fraction given to a count.
    """
    if not isinstance(payload, dict):
        raise RequestError('send a JSON object of attr values, such as {"span": 7.5}')
    if not payload:
        raise RequestError("no attr values given")
    defaults = grammar.attrs
    counts = count_attrs(grammar)
    values: dict[str, object] = {}
    for name, value in payload.items():
        if name not in defaults:
            close = difflib.get_close_matches(str(name), list(defaults), n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise RequestError(f"the grammar has no attr {name!r}{hint}")
        kind = _kind(defaults[name])
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
        elif kind == "boolean" and not isinstance(value, bool):
            raise RequestError(f"attr {name!r} takes true or false; got {_shown(value)}")
        elif kind == "string" and not isinstance(value, str):
            raise RequestError(f"attr {name!r} takes a string; got {_shown(value)}")
        values[name] = value
    ranges = grammar.parameter_ranges({**current, **values})
    for name, value in values.items():
        spec = ranges.get(name)
        if spec is None or isinstance(value, bool) or not isinstance(value, float):
            continue
        if not spec["min"] <= value <= spec["max"]:
            raise RequestError(
                f"attr {name!r} = {value:g} is outside its @Range [{spec['min']:g}, "
                f"{spec['max']:g}]"
            )
    return values


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
