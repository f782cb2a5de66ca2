"""rules/suspension_bridge.grammar: the bridge builds, its parts are where the documentation puts
them, the cables follow the parabola with the diameter of the cable model, and --optimize runs
the span/sag search instead of the block QP.

Truth values: the layout rules of docs/bridges.md (towers at the side span plus whole main spans,
round(span / spacing) - 1 suspenders per span and cable), the parabola, and the paper's D_direct
for the Golden Gate (0.92 m).
"""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest

import shapegen
from shapegen.cli import main
from shapegen.engine import bridge_rules
from shapegen.engine.search import optimize
from shapegen.errors import GeometryError, GrammarError, ShapegenError
from shapegen.export.gltf import encode_glb

GRAMMAR = "suspension_bridge.grammar"
SPACING = 15.24  # the grammar's default suspender_spacing, m


@pytest.fixture(scope="module")
def grammar():
    return shapegen.load_grammar(GRAMMAR)


@pytest.fixture(scope="module")
def golden_gate(grammar):
    return grammar.build()


def tagged(model, tag):
    return [b for b in model.blocks if tag in b.tags]


def tower_positions(model) -> np.ndarray:
    """x of each tower's axis (m), from the portal beams (two per tower)."""
    return np.unique(np.round([b.centroid[0] for b in tagged(model, "portal beam")], 6))


def test_the_rule_file_is_a_cable_structure(grammar):
    assert bridge_rules.is_cable_structure(grammar)
    assert set(grammar.free_parameters) == {"main_span", "sag"}
    for name in (
        "length", "lanes", "tracks", "cables", "decks", "max_cable_diameter", "min_span",
        "golden_factor", "safety_factor", "towers",
    ):  # fmt: skip
        assert name in grammar.attrs


def test_towers_stand_at_the_ends_of_the_main_span(golden_gate):
    attrs = golden_gate.metadata["attrs"]
    side = (attrs["length"] - attrs["main_span"]) / 2
    assert np.allclose(tower_positions(golden_gate), [side, side + attrs["main_span"]])
    assert len(tagged(golden_gate, "anchorage")) == 2


def expected_suspenders(spans, cables, spacing=SPACING) -> int:
    return cables * sum(max(1, round(span / spacing)) - 1 for span in spans)


def test_suspender_count_and_spacing(golden_gate):
    attrs = golden_gate.metadata["attrs"]
    side = (attrs["length"] - attrs["main_span"]) / 2
    hangers = tagged(golden_gate, "suspender")
    assert len(hangers) == expected_suspenders([side, attrs["main_span"], side], 2)
    towers = tower_positions(golden_gate)
    x = np.unique(np.round([b.centroid[0] for b in hangers], 6))
    in_main = x[(x > towers[0]) & (x < towers[1])]
    gaps = np.diff(in_main)
    panels = round(attrs["main_span"] / SPACING)
    assert np.allclose(gaps, attrs["main_span"] / panels)


def test_main_cable_follows_the_parabola_with_the_paper_diameter(golden_gate):
    attrs = golden_gate.metadata["attrs"]
    span, sag, pieces = attrs["main_span"], attrs["sag"], int(attrs["cable_segments"])
    towers = tower_positions(golden_gate)
    saddle = max(b.vertices[:, 1].max() for b in tagged(golden_gate, "tower"))
    main = [b for b in tagged(golden_gate, "cable") if towers[0] < b.centroid[0] < towers[1]]
    assert len(main) == 2 * pieces
    x = np.array([b.centroid[0] for b in main]) - towers[0]
    y = np.array([b.centroid[1] for b in main])
    curve = saddle - 4 * sag * x * (span - x) / span**2
    # Straight pieces: the centroid is the chord midpoint, f / n^2 above the curve.
    assert np.max(np.abs(y - curve)) == pytest.approx(sag / pieces**2, rel=1e-6)
    assert sag / pieces**2 < 0.1
    diameters = [np.ptp(b.vertices[:, 2]) for b in main]
    assert np.allclose(diameters, diameters[0])
    assert diameters[0] == pytest.approx(0.92, abs=0.01)  # Patow 2012, Table 2, D_direct


def test_tension_members_and_deck_are_left_out_of_a_block_analysis(golden_gate):
    for tag in ("cable", "suspender", "deck"):
        assert tagged(golden_gate, tag) and not any(b.structural for b in tagged(golden_gate, tag))
    for tag in ("tower", "anchorage"):
        assert all(b.structural for b in tagged(golden_gate, tag))


def test_gltf_export_carries_the_labels(golden_gate):
    content = encode_glb(golden_gate)
    chunk_length, chunk_type = struct.unpack_from("<I4s", content, 12)
    assert chunk_type == b"JSON"
    tree = json.loads(content[20 : 20 + chunk_length])
    labels = {label for node in tree["nodes"] for label in node.get("extras", {}).get("labels", [])}
    for label in ("cable", "suspender", "tower", "portal beam", "deck", "anchorage"):
        assert label in labels


def test_double_deck_with_posts_and_several_main_spans(grammar):
    attrs = {"length": 5000, "towers": 0, "decks": 2, "cables": 4, "tracks": 2}
    model = grammar.build(attrs=attrs)
    span = model.metadata["attrs"]["main_span"]
    spans = math.floor(5000 / span)  # towers = 0: as many main spans as fit
    side = (5000 - spans * span) / 2
    assert np.allclose(tower_positions(model), side + span * np.arange(spans + 1))
    assert tagged(model, "deck posts")
    levels = {round(b.vertices[:, 1].min(), 6) for b in tagged(model, "deck panel")}
    assert len(levels) == 2
    hangers = tagged(model, "suspender")
    assert len(hangers) == expected_suspenders([side, *[span] * spans, side], 4)


def test_cli_build_reports_the_bridge(tmp_path):
    report_path = tmp_path / "r.json"
    code = main(
        [
            "build", GRAMMAR, "--set", "lanes=6", "--set", "main_span=1280", "--set", "sag=152",
            "-o", str(tmp_path / "bridge.glb"), "--report", str(report_path), "-q",
        ]
    )  # fmt: skip
    assert code == 0
    bridge = json.loads(report_path.read_text())["bridge"]
    for key in (
        "main_span", "sag", "side_spans", "cable_diameter", "main_span_diameter", "cable_area",
        "max_tension", "load_per_metre",
    ):  # fmt: skip
        assert key in bridge
    assert bridge["main_span_diameter"] == pytest.approx(0.92, abs=0.01)
    assert bridge["load_per_metre"] == pytest.approx(5300 * 6 * 9.81)
    assert bridge["side_spans"] == pytest.approx([343.0, 343.0])
    assert (tmp_path / "bridge.glb").stat().st_size > 0


def test_optimize_golden_gate_finds_a_cable_under_the_maximum(grammar):
    result = optimize(grammar)  # the defaults: Golden Gate, max_cable_diameter 0.924 m
    span, sag = result.values["main_span"], result.values["sag"]
    assert result.feasible and result.qp_solves == 0
    assert 1280 <= span <= 1966 and 0 < sag < span / 2
    assert result.bridge["cable_diameter"] < 0.924
    assert result.evaluations > 0 and result.stopped_early
    assert result.model is not None
    cable = tagged(result.model, "cable")[0]
    assert np.ptp(cable.vertices[:, 2]) == pytest.approx(result.bridge["cable_diameter"])


def test_cli_optimize_runs_the_span_and_sag_search(tmp_path):
    report_path = tmp_path / "r.json"
    code = main(
        ["build", GRAMMAR, "--optimize", "--report", str(report_path), "-q",
         "-o", str(tmp_path / "bridge.json")]
    )  # fmt: skip
    assert code == 0
    report = json.loads(report_path.read_text())
    optimization, bridge = report["optimization"], report["bridge"]
    assert optimization["structure"] == "cable" and optimization["evaluations"] > 0
    assert bridge["cable_diameter"] < bridge["max_cable_diameter"]
    assert bridge["main_span"] == pytest.approx(optimization["parameters"]["main_span"]["final"])
    assert report["analysis"]["feasible"]  # towers and anchorages stand as blocks


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"lanes": 0, "tracks": 0}, "at least one lane or track"),
        ({"length": 1000}, "length 1000 m is shorter than min_span 1280 m"),
        ({"main_span": 1000}, "main_span 1000 m is shorter than min_span"),
        ({"sag": 700}, "sag 700 m must be less than half the main span"),
        ({"towers": 1}, "'towers' must be 0"),
        ({"towers": 3}, "3 towers make 2 main spans"),
        ({"cables": 0}, "'cables' must be at least 1"),
    ],
)
def test_impossible_inputs_are_clear_errors(grammar, attrs, message):
    with pytest.raises(ShapegenError, match=message):
        grammar.build(attrs=attrs)


def test_impossible_search_inputs_are_clear_errors(grammar):
    with pytest.raises(GeometryError, match="shorter than min_span"):
        optimize(grammar, attrs={"length": 1000})
    with pytest.raises(GrammarError, match="searches main_span and sag together"):
        optimize(grammar, fix={"sag": 100})
    code = main(["build", GRAMMAR, "--set", "lanes=0", "--set", "tracks=0", "-q"])
    assert code != 0
