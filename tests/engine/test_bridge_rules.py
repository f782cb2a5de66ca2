"""The glue between the bridge rule file and the cable model: design checks and the search with
several main spans.

Truth values: the layout rules of docs/bridges.md, and the closed-form optimum of the search
without early termination: the sag ratio goes to its upper bound and, while the main span
governs, the span to its lower bound, which with ``m`` main spans is where the side spans
``(Lb - m K) / 2`` reach ``K``: ``K* = max(min_span, Lb / (m + 2))``.
"""

from __future__ import annotations

import pytest

import shapegen
from shapegen.engine.bridge_rules import (
    BridgeDesign,
    auto_main_spans,
    is_cable_structure,
    optimize_bridge,
)
from shapegen.engine.bridge_search import MAX_SAG_RATIO, search_span_and_sag
from shapegen.errors import GeometryError
from shapegen.statics.cables import BridgeLoading

GOLDEN_GATE = {
    "length": 1966.0,
    "lanes": 6,
    "tracks": 0,
    "cables": 2,
    "decks": 1,
    "max_cable_diameter": 0.924,
    "min_span": 1280.0,
    "golden_factor": 5300.0,
    "safety_factor": 3.0,
    "towers": 2,
    "main_span": 1280.0,
    "sag": 152.0,
}


def test_design_layout():
    design = BridgeDesign.from_attrs(GOLDEN_GATE)
    assert design.main_spans == 1 and design.tower_count == 2
    assert design.side_span == pytest.approx(343.0)
    assert design.sizing().main_span_diameter == pytest.approx(0.92, abs=0.01)  # D_direct
    three = BridgeDesign.from_attrs({**GOLDEN_GATE, "length": 5000.0, "towers": 0})
    assert three.main_spans == 3 and three.side_span == pytest.approx((5000 - 3 * 1280) / 2)


@pytest.mark.parametrize(
    ("length", "span", "spans"), [(1966, 1280, 1), (2560, 1280, 2), (2559, 1280, 1), (900, 1000, 1)]
)
def test_automatic_main_spans(length, span, spans):
    assert auto_main_spans(length, span) == spans


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"lanes": 0}, "at least one lane or track"),
        ({"lanes": 2.5}, "'lanes' must be a whole number"),
        ({"length": -1.0}, "'length' must be positive"),
        ({"length": 1000.0}, "shorter than min_span"),
        ({"sag": 640.0}, "less than half the main span"),
        ({"main_span": 1966.0, "towers": 3}, "3 towers make 2 main spans"),
        ({"decks": 3}, "'decks' must be 1 or 2"),
        ({"max_cable_diameter": 0.0}, "'max_cable_diameter' must be positive"),
    ],
)
def test_impossible_designs(change, message):
    attrs = {**GOLDEN_GATE, **change}
    if change.get("lanes") == 0:
        attrs["tracks"] = 0
    with pytest.raises(GeometryError, match=message):
        BridgeDesign.from_attrs(attrs)


@pytest.mark.parametrize("main_spans", [1, 2, 3])
def test_search_with_several_main_spans_reaches_the_closed_form_optimum(main_spans):
    length, min_span = 6000.0, 100.0
    found = search_span_and_sag(
        BridgeLoading(lanes=4),
        length=length,
        min_span=min_span,
        max_diameter=1e-3,  # out of reach: Powell runs to convergence
        main_spans=main_spans,
    )
    assert found.converged and not found.stopped_early
    assert found.span == pytest.approx(max(min_span, length / (main_spans + 2)), rel=1e-3)
    assert found.sag / found.span == pytest.approx(MAX_SAG_RATIO, rel=1e-3)


def test_search_bounds_follow_the_main_spans():
    with pytest.raises(GeometryError, match="at most the bridge length"):
        search_span_and_sag(
            BridgeLoading(lanes=4), length=2000.0, min_span=1200.0, max_diameter=1.0, main_spans=2
        )


def test_automatic_towers_add_main_spans_until_the_cable_fits():
    """A long crossing whose single span would need too thick a cable."""
    grammar = shapegen.load_grammar("suspension_bridge.grammar")
    assert is_cable_structure(grammar)
    attrs = {"length": 6000, "min_span": 1000, "main_span": 1000, "towers": 0}
    attrs["max_cable_diameter"] = 0.75
    single = search_span_and_sag(
        BridgeLoading(lanes=6), length=6000.0, min_span=1000.0, max_diameter=0.75
    )
    assert not single.stopped_early  # one main span cannot get under 0.75 m
    result = optimize_bridge(grammar, attrs=attrs, build=False)
    assert result.feasible and result.towers > 2
    assert result.bridge["cable_diameter"] < 0.75
    assert result.values["towers"] == result.towers
