"""One lot's work, as a worker runs it: derive, judge and (optionally) optimize, place, record.

:func:`run_lot` never raises for a lot's own trouble: a grammar error, a statics error, a work
limit reached or the lot's timeout passed all become a record with ``status`` ``"error"`` or
``"timeout"`` and one line in ``error``, so one bad lot never stops a city. Everything a worker
needs travels in :class:`CitySettings` and :class:`LotTask` (plain, picklable data: the rule's
text, not its path), so a worker on another machine of a Dask cluster needs shapegen installed
and nothing else.

Seeds. A lot's seed is drawn from its id and the run's seed with BLAKE2b (not Python's
``hash``, which changes between processes), so a rerun, on any machine and in any order, gives
the same city.

Placement. The rule derives on the lot's polygon where it lies in the city's frame; the start
shape's scope has x along the lot's first edge and y up, as CityEngine's.
"""

from __future__ import annotations

__all__ = [
    "CitySettings",
    "LotTask",
    "lot_seed",
    "new_record",
    "run_lot",
    "timeout_message",
    "warm_up",
]

import contextlib
import hashlib
import math
import os
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

# A lot whose area falls short of its bounding rectangle's by less than this strip along the
# rectangle's sides (m) is that rectangle.
_RECTANGLE_M = 1e-3


@dataclass(frozen=True)
class CitySettings:
    """What every lot of one run shares.

    Attributes
    ----------
    grammar_text, grammar_name
        The rule's source and how errors name it.
    attrs
        Attr values for every lot (``--set``); a lot's properties override them.
    seed
        The run's seed; each lot's seed is drawn from it and the lot's id.
    search
        A :class:`~shapegen.search.search_options.SearchOptions` to optimize each lot, or None.
    statics
        Block-statics options, or None for the defaults.
    timeout
        Seconds one lot may take, or None.
    analyze
        Judge each building (``stands``, ``measure``); False derives only (a search judges
        anyway).
    limits
        Work limits (:class:`~shapegen.limits.WorkLimits`) of each lot, or None for the
        defaults.
    """

    grammar_text: str
    grammar_name: str
    attrs: dict = field(default_factory=dict)
    seed: int = 0
    search: object | None = None
    statics: object | None = None
    timeout: float | None = None
    limits: object | None = None
    analyze: bool = True


@dataclass(frozen=True)
class LotTask:
    """One lot to build: its id, its corners (east, north about the city's origin, m,
    counter-clockwise seen from above), its properties, the fingerprint of these (``input``,
    kept in its record so a rerun knows whether the lot changed), for a lot that cannot be
    built, why (``problem``: its record is that error), its holes (courtyards: rings of
    corners in the frame of ``ring``, clockwise seen from above) and what reading it changed
    (``warnings``: its record's first warnings)."""

    id: str
    ring: Sequence[Sequence[float]]
    properties: dict = field(default_factory=dict)
    input: str = ""
    problem: str | None = None
    holes: Sequence[Sequence[Sequence[float]]] = ()
    warnings: Sequence[str] = ()


class LotTimeout(Exception):
    """The lot's time ran out (raised inside the lot's work, caught by :func:`run_lot`)."""


def lot_seed(lot_id: str, seed: int = 0) -> int:
    """The seed of lot ``lot_id`` in a run seeded ``seed``: 0 .. 2^31 - 1, the same everywhere."""
    digest = hashlib.blake2b(f"{seed}\x00{lot_id}".encode(), digest_size=4).digest()
    return int.from_bytes(digest, "big") & 0x7FFFFFFF


_GRAMMARS: dict[str, object] = {}  # the rules a worker has compiled, by hash of their text


def _grammar(settings: CitySettings):
    """The run's rule, compiled once per worker. Where the rule file is on this machine with the
    same text, it is loaded from there, so its imports resolve as in the parent (a package's
    ESRI.lib, the rule's own project, SHAPEGEN_RULES_PATH); elsewhere its text is parsed."""
    from shapegen.engine.grammar_api import load_grammar, parse_grammar
    from shapegen.grammar.source_files import read_rule_file

    key = hashlib.sha256(
        (settings.grammar_name + "\x00" + settings.grammar_text).encode()
    ).hexdigest()
    if key not in _GRAMMARS:
        _GRAMMARS.clear()  # one run's rule at a time
        path = Path(settings.grammar_name)
        try:
            here = path.is_file() and read_rule_file(path)[0] == settings.grammar_text
        except (OSError, ValueError):
            here = False
        if here:
            _GRAMMARS[key] = load_grammar(path)
        else:
            _GRAMMARS[key] = parse_grammar(settings.grammar_text, settings.grammar_name)
    return _GRAMMARS[key]


def warm_up(settings: CitySettings) -> None:
    """Compile the run's rule and import the pipeline before the first lot, so that a fresh
    worker's first lot is not charged for them against its timeout. A rule that does not
    compile is left to the lots, whose rows say why."""
    import shapegen.pipeline  # noqa: F401 - imported once, here

    try:
        _grammar(settings)
    except Exception:  # noqa: BLE001 - each lot records it
        pass


def run_lot(settings: CitySettings, task: LotTask) -> dict:
    """Build, judge (and optimize) one lot; the record of what happened (see module doc).

    The record holds ``id``, ``status`` (``ok``, ``error``, ``timeout``), ``stands``,
    ``measure`` (y/W^2 for block statics), ``structure``, ``blocks``, ``left_out`` (leaves drawn
    but not judged: not convex blocks), ``warnings`` (the derivation's), ``attrs`` (the values of
    the rule's ranged attrs as built, optimized ones included), ``from_properties`` (attrs the
    lot's properties set), ``seed``, ``footprint``, ``lot`` (width, depth, m), ``seconds``,
    ``error``, ``peak_rss_mib`` (the worker's peak so far), ``input`` (the task's) and, for a
    built lot, ``model``: the placed blocks (a :class:`~shapegen.Model`).
    """
    started = time.perf_counter()
    seed = lot_seed(task.id, settings.seed)
    record = new_record(task.id, seed)
    record["input"] = task.input
    record["warnings"] = list(task.warnings)
    if task.problem is not None:
        record.update(error=task.problem, seconds=0.0)
        return record
    try:
        # A warning (an attr outside its @Range...) belongs to its lot's row, not to a terminal
        # that many workers share.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                _run(settings, task, seed, started, record)
            finally:
                record["warnings"] = list(record["warnings"]) + [
                    " ".join(str(w.message).split()) for w in caught
                ]
        record["status"] = "ok"
    except LotTimeout:
        record["status"] = "timeout"
    except Exception as exc:  # noqa: BLE001 - a lot's failure is a row, whatever it is
        from shapegen.errors import ShapegenError

        text = " ".join(str(exc).split()) or type(exc).__name__
        if not isinstance(exc, ShapegenError):
            text = f"internal error: {type(exc).__name__}: {text}"
        record["error"] = text
    seconds = time.perf_counter() - started
    if settings.timeout is not None and seconds > settings.timeout:
        # Past its time, whatever it got to: a timed-out lot reads the same wherever it stopped.
        record.update(status="timeout", stands=None, measure=None, blocks=None, solids=None)
        record.pop("model", None)
    if record["status"] == "timeout":
        record["error"] = timeout_message(settings.timeout)
    record["seconds"] = seconds
    record["peak_rss_mib"] = _peak_rss_mib()
    return record


def new_record(lot_id: str, seed: int) -> dict:
    """A lot's record before anything is known of it (status ``error``, no error yet)."""
    return {
        "id": lot_id,
        "status": "error",
        "stands": None,
        "measure": None,
        "structure": None,
        "blocks": None,
        "solids": None,
        "left_out": None,
        "warnings": [],
        "attrs": {},
        "from_properties": [],
        "seed": seed,
        "footprint": None,
        "lot": None,
        "iterations": None,
        "error": None,
        "seconds": None,
        "peak_rss_mib": None,
        "input": None,
    }


def timeout_message(timeout: float) -> str:
    """The error of a lot stopped by its timeout."""
    return f"took more than {timeout:g} s (--timeout)"


def _run(settings: CitySettings, task: LotTask, seed: int, started: float, record: dict) -> None:
    from shapegen.errors import ShapegenError
    from shapegen.limits import (
        check_clock,
        current_limits,
        remaining_seconds,
        work_clock,
        work_limits,
    )
    from shapegen.pipeline import design

    grammar = _grammar(settings)
    attrs = dict(settings.attrs)
    for name, value in task.properties.items():
        if name in grammar.attrs and value is not None:
            if isinstance(value, list | dict):
                raise _input_error(f"property {name!r} is a {type(value).__name__}; an attr"
                                   " takes a number, boolean or string")  # fmt: skip
            attrs[name] = value
            record["from_properties"].append(name)
    size, footprint = lot_extent(task.ring)
    record["footprint"] = "polygon" if task.holes else footprint
    record["lot"] = [float(size[0]), float(size[1])]
    lot = [(x, z) for x, z in city_lot(task.ring).tolist()]
    if task.holes:  # a courtyard: the start shape has the lot's holes, as CityEngine's has
        from shapegen.model.lot import Lot

        lot = Lot.polygon(lot, [city_lot(hole).tolist() for hole in task.holes])

    # One clock for the lot (--timeout, counted from the lot's start): the derivation, the
    # statics and the search look at it (shapegen.limits.work_clock) besides their own
    # max_seconds; past it, the lot is a timeout row (run_lot), whatever step it stopped in.
    limits = settings.limits or current_limits()
    clock = contextlib.nullcontext()
    if settings.timeout is not None:
        clock = work_clock("the lot", settings.timeout - (time.perf_counter() - started))
    with work_limits(limits), clock:
        try:
            outcome = design(
                grammar,
                attrs=attrs,
                seed=seed,
                lot=lot,
                statics=settings.statics,
                search=settings.search,
                assess=settings.analyze,
            )
            check_clock()
        except ShapegenError:
            if settings.timeout is not None and remaining_seconds() == 0.0:
                raise LotTimeout from None
            raise
    assessment = outcome.assessment
    if assessment is not None:
        record["structure"] = outcome.structure.name
        record["stands"] = bool(assessment.stands)
        record["measure"] = _number(assessment.measure)
        if not assessment.judged:  # no verdict: an empty cell and why, not a plain "no"
            record["stands"] = None
            record["solver_status"] = assessment.status
    record["blocks"] = len(outcome.model.blocks)
    record["solids"] = int(outcome.report.get("solids", 0))  # not convex, kept as derived
    # Leaves drawn but not judged (not convex blocks) and the derivation's warnings: said, so a
    # building judged on part of itself is never taken for the whole.
    record["left_out"] = int((outcome.report.get("left_out") or {}).get("leaves", 0))
    record["warnings"] = list(task.warnings) + list(outcome.report.get("warnings") or [])
    if "solver_status" in record:
        record["warnings"].append(
            f"the solver ended with {record.pop('solver_status')}: no verdict (taken not to stand)"
        )
    built = outcome.model.metadata.get("attrs", {})
    ranged = outcome.report.get("free_parameters") or {}
    names = list(settings.search.free or ranged) if settings.search is not None else list(ranged)
    record["attrs"] = {name: _number(built.get(name)) for name in names if name in built}
    if outcome.optimization is not None:
        record["iterations"] = outcome.optimization.iterations
    record["model"] = outcome.model


def _input_error(message: str):
    from shapegen.errors import InputFormatError

    return InputFormatError(message)


def _number(value):
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        return value
    value = float(value)
    return value if math.isfinite(value) else None


def lot_extent(ring: np.ndarray) -> tuple[tuple[float, float], str]:
    """The size of a lot's scope and whether the lot fills it.

    ``ring`` is ``(k, 2)`` east/north corners, counter-clockwise seen from above. The lot's scope
    has x along the first edge and y up (CityEngine's scope of a lot); it is the lot's bounding
    rectangle in that frame, ``(width, depth)`` m, which is the lot itself when the lot is a
    rectangle (``footprint`` ``"rectangle"``; else ``"polygon"``).
    """
    points = city_lot(ring)
    width, depth, rectangle = lot_extents(points, np.array([0, len(points)]))
    return (float(width[0]), float(depth[0])), "rectangle" if rectangle[0] else "polygon"


def lot_extents(points: np.ndarray, offsets: np.ndarray):
    """:func:`lot_extent` of many lots at once: ``points`` their ``(x, z)`` corners end to end,
    lot ``i`` at ``points[offsets[i]:offsets[i + 1]]``; the widths along each first edge, the
    depths across it, and whether each lot is the rectangle it fills."""
    sizes = np.diff(offsets)
    first = offsets[:-1]
    edge = points[first + 1] - points[first]
    length = np.hypot(edge[:, 0], edge[:, 1])
    length = np.where(length > 0, length, 1.0)
    u = edge / length[:, None]
    w = np.column_stack([-u[:, 1], u[:, 0]])  # (x, z) of u cross +y
    relative = points - np.repeat(points[first], sizes, axis=0)
    along = np.einsum("ij,ij->i", relative, np.repeat(u, sizes, axis=0))
    across = np.einsum("ij,ij->i", relative, np.repeat(w, sizes, axis=0))
    width = np.maximum.reduceat(along, first) - np.minimum.reduceat(along, first)
    depth = np.maximum.reduceat(across, first) - np.minimum.reduceat(across, first)
    nxt = np.arange(1, len(points) + 1)
    nxt[offsets[1:] - 1] = first
    x, z = points[:, 0], points[:, 1]
    area = 0.5 * np.abs(np.add.reduceat(x * z[nxt] - z * x[nxt], first))
    # A polygon fills its bounding rectangle only when it is that rectangle.
    return width, depth, width * depth - area <= _RECTANGLE_M * (width + depth)


def city_lot(ring: np.ndarray) -> np.ndarray:
    """The lot as :meth:`~shapegen.Grammar.build` takes a polygon: ``(k, 2)`` ``(x, z)`` corners
    (m) in shapegen's city frame (east +x, north -z, y up), so that the model is derived where it
    stands in the city."""
    ring = np.asarray(ring, dtype=float)
    return np.column_stack([ring[:, 0], -ring[:, 1]])


def _peak_rss_mib() -> float | None:
    """This process's peak resident memory, MiB (None where the OS does not say)."""
    try:
        import resource
    except ImportError:  # not on Windows
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # Linux reports KiB, macOS bytes.
    return round(peak / (2**20 if os.uname().sysname == "Darwin" else 1024), 1)
