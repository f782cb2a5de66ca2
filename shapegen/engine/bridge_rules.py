"""Suspension bridges as a rule set: the glue between a ``.grammar`` file and the cable model.

A grammar whose start rule carries ``@Structure("cable")`` describes a structure sized by its
cables (:mod:`shapegen.statics.cables`), not by the block statics. For such a grammar

- :class:`BridgeDesign` reads the bridge's attrs (``length``, ``lanes``, ``tracks``, ``cables``,
  ``decks``, ``max_cable_diameter``, ``min_span``, ``golden_factor``, ``safety_factor``,
  ``towers``, ``main_span``, ``sag``), checks them and sizes the cables;
- :func:`optimize_bridge` runs the span/sag search of
  :func:`~shapegen.engine.bridge_search.search_span_and_sag` on the cable model alone (a few
  microseconds per evaluation) and builds the model once, at the end;
  :func:`shapegen.engine.search.optimize` hands such grammars to it;
- :func:`bridge_report` gives the ``bridge`` object of a build report.

The geometry (deck, towers, anchorages, cables, suspenders) comes from the primitives of
:mod:`shapegen.primitives.bridge`; the cable primitive sizes its section with
:meth:`BridgeDesign.sizing`, so geometry, search and report use one model. docs/bridges.md
describes the rule file.
"""

from __future__ import annotations

__all__ = [
    "CABLE_STRUCTURE",
    "SEARCHED_ATTRS",
    "BridgeDesign",
    "BridgeOptimizationResult",
    "auto_main_spans",
    "bridge_report",
    "is_cable_structure",
    "model_design",
    "optimize_bridge",
    "structure_of",
]

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from shapegen.engine.bridge_search import BridgeSearchResult, search_span_and_sag
from shapegen.engine.search import OptimizationResult
from shapegen.errors import GeometryError, GrammarError
from shapegen.statics.cables import (
    GOLDEN_FACTOR,
    SAFETY_FACTOR,
    BridgeLoading,
    CableSizing,
    size_cables,
)

CABLE_STRUCTURE = "cable"  # one of shapegen.grammar.names.STRUCTURES
"""The argument of ``@Structure(...)`` that marks a grammar sized by the cable model."""

SEARCHED_ATTRS = ("main_span", "sag")
"""The free attrs of a cable structure: the search varies both together."""

# Most main spans the automatic choice of towers tries (towers = 0): beyond that the towers
# stand closer than any suspension bridge's.
_MAX_AUTO_MAIN_SPANS = 12


def structure_of(grammar) -> str | None:
    """The argument of the start rule's ``@Structure(...)`` annotation, or None without one."""
    start = grammar.ast.start_rule
    if start is None:
        return None
    annotation = start.annotation("Structure")
    if annotation is None:
        return None
    from shapegen.grammar.checks import constant_value

    value = constant_value(annotation.args[0]) if annotation.args else None
    return value if isinstance(value, str) else None


def is_cable_structure(grammar) -> bool:
    """True when ``grammar``'s start rule is marked ``@Structure("cable")``."""
    return structure_of(grammar) == CABLE_STRUCTURE


def auto_main_spans(length: float, main_span: float) -> int:
    """Main spans chosen when ``towers`` is 0: as many spans of ``main_span`` as fit in the length
    (at least one), the rest going to the two side spans."""
    return max(1, math.floor(length / main_span * (1.0 + 1e-12)))


def _whole(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float) or value != int(value):
        raise GeometryError(f"bridge attr {name!r} must be a whole number, got {value!r}")
    if value < minimum:
        raise GeometryError(f"bridge attr {name!r} must be at least {minimum}, got {int(value)}")
    return int(value)


def _positive(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise GeometryError(f"bridge attr {name!r} must be a number, got {value!r}")
    if value <= 0:
        raise GeometryError(f"bridge attr {name!r} must be positive, got {value:g}")
    return float(value)


@dataclass(frozen=True)
class BridgeDesign:
    """The inputs of a suspension bridge and one choice of main span and sag.

    Attributes
    ----------
    length
        Length between the anchorages, m.
    lanes, tracks
        Road lanes over all decks and railway tracks (each track loads like a lane).
    cables
        Main cables sharing the load.
    decks
        Number of decks (1 or 2).
    max_cable_diameter
        Largest acceptable cable diameter, m (the search's target).
    min_span
        Shortest acceptable main span (the distance between the shores), m.
    golden_factor
        Deck mass per metre and lane, kg/m.
    safety_factor
        Strand breaking strength over peak tension.
    towers
        Number of towers (main spans + 1), or 0 to choose them from the length.
    main_span, sag
        Each main span (tower to tower) and its sag, m.
    """

    length: float
    lanes: int
    tracks: int
    cables: int
    decks: int
    max_cable_diameter: float
    min_span: float
    golden_factor: float
    safety_factor: float
    towers: int
    main_span: float
    sag: float

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, object], *, check_span: bool = True) -> BridgeDesign:
        """A checked design from attr values (the grammar's names).

        ``check_span=False`` skips the checks of ``main_span`` and ``sag`` (the search picks them).

        Raises
        ------
        GeometryError
            With one message naming the attr, for impossible inputs.
        """
        missing = [
            name
            for name in ("length", "lanes", "cables", "min_span", "main_span", "sag")
            if name not in attrs
        ]
        if missing:
            raise GeometryError(f"a cable structure needs the attrs {', '.join(missing)}")
        lanes = _whole("lanes", attrs["lanes"], 0)
        tracks = _whole("tracks", attrs.get("tracks", 0), 0)
        if lanes + tracks < 1:
            raise GeometryError(
                f"a bridge needs at least one lane or track, got lanes={lanes}, tracks={tracks}"
            )
        design = cls(
            length=_positive("length", attrs["length"]),
            lanes=lanes,
            tracks=tracks,
            cables=_whole("cables", attrs["cables"], 1),
            decks=_whole("decks", attrs.get("decks", 1), 1),
            max_cable_diameter=_positive(
                "max_cable_diameter", attrs.get("max_cable_diameter", math.inf)
            ),
            min_span=_positive("min_span", attrs["min_span"]),
            golden_factor=_positive("golden_factor", attrs.get("golden_factor", GOLDEN_FACTOR)),
            safety_factor=_positive("safety_factor", attrs.get("safety_factor", SAFETY_FACTOR)),
            towers=_whole("towers", attrs.get("towers", 2), 0),
            main_span=_positive("main_span", attrs["main_span"]),
            sag=_positive("sag", attrs["sag"]),
        )
        design._check(check_span)
        return design

    def _check(self, check_span: bool) -> None:
        if self.decks > 2:
            raise GeometryError(f"bridge attr 'decks' must be 1 or 2, got {self.decks}")
        if self.towers == 1:
            raise GeometryError("bridge attr 'towers' must be 0 (automatic) or at least 2, got 1")
        if self.length < self.min_span:
            raise GeometryError(
                f"the bridge length {self.length:g} m is shorter than min_span "
                f"{self.min_span:g} m (the distance between the shores)"
            )
        if self.towers >= 2 and self.length / (self.towers - 1) < self.min_span:
            raise GeometryError(
                f"{self.towers} towers make {self.towers - 1} main spans of at least min_span "
                f"{self.min_span:g} m, longer than the bridge length {self.length:g} m"
            )
        if not check_span:
            return
        spans = self.main_spans
        if self.main_span < self.min_span * (1.0 - 1e-9):
            raise GeometryError(
                f"main_span {self.main_span:g} m is shorter than min_span {self.min_span:g} m "
                "(the distance between the shores)"
            )
        if spans * self.main_span > self.length * (1.0 + 1e-9):
            raise GeometryError(
                f"{spans} main span(s) of {self.main_span:g} m do not fit in the bridge length "
                f"{self.length:g} m"
            )
        if self.sag >= self.main_span / 2.0:
            raise GeometryError(
                f"sag {self.sag:g} m must be less than half the main span "
                f"({self.main_span / 2.0:g} m)"
            )

    @property
    def main_spans(self) -> int:
        """Number of main spans: ``towers - 1``, or :func:`auto_main_spans` when towers is 0."""
        if self.towers >= 2:
            return self.towers - 1
        return auto_main_spans(self.length, self.main_span)

    @property
    def tower_count(self) -> int:
        """Number of towers actually built."""
        return self.main_spans + 1

    @property
    def side_span(self) -> float:
        """Each of the two side spans, tower to anchorage, m."""
        return max(self.length - self.main_spans * self.main_span, 0.0) / 2.0

    @property
    def loading(self) -> BridgeLoading:
        """The cable model's inputs."""
        return BridgeLoading(
            lanes=self.lanes,
            tracks=self.tracks,
            cables=self.cables,
            golden_factor=self.golden_factor,
            safety_factor=self.safety_factor,
        )

    def sizing(self) -> CableSizing:
        """Cables sized for this design: one main span between the two side spans (every main
        span hangs alike)."""
        return size_cables(
            self.loading,
            self.main_span,
            self.sag,
            length=self.main_span + 2.0 * self.side_span,
        )

    def with_span(self, main_span: float, sag: float, towers: int | None = None) -> BridgeDesign:
        """The same bridge with another main span and sag (and towers)."""
        values = {**self.__dict__, "main_span": main_span, "sag": sag}
        if towers is not None:
            values["towers"] = towers
        return BridgeDesign(**values)


def bridge_report(design: BridgeDesign) -> dict:
    """The ``bridge`` object of a build report (plain JSON types, SI units).

    ``cable_diameter`` is the governing diameter (main or side spans), ``main_span_diameter`` the
    main span alone (the paper's ``D_direct``); area and tension are per cable.
    """
    sizing = design.sizing()
    return {
        "main_span": design.main_span,
        "sag": design.sag,
        "side_spans": [design.side_span, design.side_span],
        "main_spans": design.main_spans,
        "towers": design.tower_count,
        "cable_diameter": sizing.diameter,
        "main_span_diameter": sizing.main_span_diameter,
        "side_span_diameter": sizing.side_span_diameter,
        "governing": sizing.governing,
        "cable_area": sizing.area,
        "max_tension": sizing.max_tension,
        "horizontal_tension": sizing.horizontal_tension,
        "load_per_metre": sizing.load_per_metre,
        "max_cable_diameter": (
            design.max_cable_diameter if math.isfinite(design.max_cable_diameter) else None
        ),
    }


def model_design(model) -> BridgeDesign:
    """The design a built bridge model was made with (from its ``metadata["attrs"]``)."""
    return BridgeDesign.from_attrs(model.metadata.get("attrs", {}))


@dataclass
class BridgeOptimizationResult(OptimizationResult):
    """:class:`~shapegen.engine.search.OptimizationResult` of a cable structure.

    ``feasible`` means a design whose cables are no thicker than ``max_cable_diameter`` was
    found; ``qp_solves`` is 0 (no block statics). Extra fields: ``evaluations`` (cable sizings),
    ``stopped_early`` (the paper's early termination), ``search_seconds`` (the search alone),
    ``build_seconds`` (the one build at the end), ``towers`` and ``bridge`` (the report of
    :func:`bridge_report` at the design found).
    """

    evaluations: int = 0
    stopped_early: bool = False
    search_seconds: float = 0.0
    build_seconds: float = 0.0
    towers: int = 2
    bridge: dict | None = None

    @property
    def values(self) -> dict[str, float]:
        """Final ``main_span`` and ``sag``, and the number of towers they were sized for."""
        return {**super().values, "towers": self.towers}

    @property
    def seconds_per_evaluation(self) -> float:
        """Mean time of one cable-model evaluation during the search, s."""
        return self.search_seconds / self.evaluations if self.evaluations else 0.0

    def to_report(self) -> dict:
        report = super().to_report()
        report.update(
            {
                "structure": CABLE_STRUCTURE,
                "evaluations": self.evaluations,
                "stopped_early": self.stopped_early,
                "search_seconds": self.search_seconds,
                "seconds_per_evaluation": self.seconds_per_evaluation,
                "build_seconds": self.build_seconds,
                "towers": self.towers,
            }
        )
        return report


def _design_attrs(grammar, attrs: Mapping[str, object] | None, seed: int, lot) -> dict:
    """Attr values (defaults with ``attrs`` over them, converted to the attrs' types)."""
    from shapegen.engine.shape import lot_scope

    return grammar.program.initial_values(attrs, seed, lot_scope(*(lot or grammar.lot)))


def optimize_bridge(
    grammar,
    *,
    free: Sequence[str] | None = None,
    fix: Mapping[str, object] | None = None,
    attrs: Mapping[str, object] | None = None,
    seed: int = 0,
    lot: tuple[float, float] | None = None,
    build: bool = True,
    **ignored: object,
) -> BridgeOptimizationResult:
    """Search main span and sag of a ``@Structure("cable")`` grammar with the cable model.

    Only the cable model is evaluated during the search (no geometry is built); the model is
    built once at the end with the design found. With ``towers = 0`` the search tries one main
    span, then two, ... and keeps the first count that gets under ``max_cable_diameter`` (or
    the thinnest cable if none does).

    Parameters
    ----------
    grammar
        A loaded grammar whose start rule is marked ``@Structure("cable")``.
    free
        None, or exactly ``main_span`` and ``sag`` (the search moves them together).
    fix
        Attr values to hold; ``main_span`` and ``sag`` cannot be held.
    attrs, seed, lot
        Attr overrides and build settings, as for :meth:`Grammar.build`.
    build
        False skips the final build (``model`` is then None).
    ignored
        Options of the block search (``objective``, ``gradient``, ``max_iter``,
        ``analysis_options``, ``progress``...), which do not apply to the cable model.

    Raises
    ------
    GrammarError
        For a ``free``/``fix`` the search cannot honour.
    GeometryError
        For impossible bridge inputs (length shorter than min_span, no lanes...).
    """
    started = time.perf_counter()
    if free and set(free) != set(SEARCHED_ATTRS):
        raise GrammarError(
            f"{grammar.name}: a cable structure searches main_span and sag together; "
            f"--free {','.join(free)} is not supported"
        )
    fix = dict(fix or {})
    held = [name for name in SEARCHED_ATTRS if name in fix]
    if held:
        raise GrammarError(
            f"{grammar.name}: a cable structure searches main_span and sag together; "
            f"{' and '.join(held)} cannot be fixed (set the other attrs instead)"
        )
    values = _design_attrs(grammar, {**(attrs or {}), **fix}, seed, lot)
    design = BridgeDesign.from_attrs(values, check_span=False)
    if not math.isfinite(design.max_cable_diameter):
        raise GeometryError(f"{grammar.name}: the search needs a max_cable_diameter")
    ranges = grammar.parameter_ranges({**(attrs or {}), **fix})

    search_started = time.perf_counter()
    if design.towers >= 2:
        counts = [design.towers - 1]
    else:
        most = min(_MAX_AUTO_MAIN_SPANS, math.floor(design.length / design.min_span))
        counts = list(range(1, max(most, 1) + 1))
    found: BridgeSearchResult | None = None
    spans_used = counts[0]
    evaluations = iterations = 0
    for count in counts:
        outcome = search_span_and_sag(
            design.loading,
            length=design.length,
            min_span=design.min_span,
            max_diameter=design.max_cable_diameter,
            main_spans=count,
        )
        evaluations += outcome.evaluations
        iterations += outcome.iterations
        if found is None or outcome.diameter < found.diameter or outcome.stopped_early:
            found, spans_used = outcome, count
        if outcome.stopped_early:
            break
    search_seconds = time.perf_counter() - search_started
    assert found is not None

    towers = spans_used + 1
    final = design.with_span(found.span, found.sag, towers)
    initial = {name: values[name] for name in SEARCHED_ATTRS}
    parameters = {
        name: {
            "initial": float(initial[name]),
            "final": float(getattr(final, name)),
            "min": float(ranges.get(name, {}).get("min", math.nan)),
            "max": float(ranges.get(name, {}).get("max", math.nan)),
        }
        for name in SEARCHED_ATTRS
    }
    model = None
    build_seconds = 0.0
    if build:
        build_started = time.perf_counter()
        build_attrs = {**(attrs or {}), **fix, "main_span": final.main_span, "sag": final.sag}
        build_attrs["towers"] = towers
        model = grammar.build(attrs=build_attrs, seed=seed, lot=lot)
        build_seconds = time.perf_counter() - build_started
    message = found.message
    if design.towers == 0:
        message = f"{towers} towers: {message}"
    return BridgeOptimizationResult(
        converged=found.stopped_early or found.converged,
        feasible=found.diameter < design.max_cable_diameter,
        iterations=iterations,
        qp_solves=0,
        seconds=time.perf_counter() - started,
        initial_infeasibility=math.nan,
        final_infeasibility=math.nan,
        parameters=parameters,
        message=message,
        objective="cable_diameter",
        gradient="powell",
        path=[],
        model=model,
        analysis=None,
        evaluations=evaluations,
        stopped_early=found.stopped_early,
        search_seconds=search_seconds,
        build_seconds=build_seconds,
        towers=towers,
        bridge=bridge_report(final),
    )
