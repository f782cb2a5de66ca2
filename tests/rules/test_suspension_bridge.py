"""rules/suspension_bridge.grammar: the bridge builds, its parts are where the documentation puts
them, the cables follow the parabola with the diameter of the cable model, the report's figures
are those of the geometry built, and --optimize searches main span and sag with the cable
structure.

Truth values: the layout rules of docs/bridges.md (towers at the side span plus whole main spans,
round(span / spacing) - 1 suspenders per span and cable), the parabola, the cable primitive's
section (a regular octagon inscribed in the diameter), and the paper's D_direct for the Golden
Gate (0.92 m).
"""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest
from rule_checks import tagged

from shapegen.cli import main
from shapegen.errors import ShapegenError
from shapegen.export.gltf import encode_glb
from shapegen.readers.models import read_model
from shapegen.search import optimize
from shapegen.statics import analyze
from shapegen.structures import Design, make_structure

GRAMMAR = "suspension_bridge.grammar"
SPACING = 15.24  # the grammar's default suspender_spacing, m


@pytest.fixture(scope="module")
def golden_gate(grammar):
    return grammar.build()


def tower_positions(model) -> np.ndarray:
    """x of each tower's axis (m), from the portal beams (two per tower)."""
    return np.unique(np.round([b.centroid[0] for b in tagged(model, "portal beam")], 6))


def cable_section_diameters(model) -> np.ndarray:
    """Diameter of each cable piece measured on its vertices: twice the largest distance of a
    vertex from the piece's axis, the line through the centres of its two end sections (each
    section lies in a plane x = const)."""
    diameters = []
    for block in tagged(model, "cable"):
        vertices = block.vertices
        ends = np.round(vertices[:, 0], 9)
        assert len(np.unique(ends)) == 2, block.id
        first = vertices[ends == ends.min()].mean(axis=0)
        second = vertices[ends == ends.max()].mean(axis=0)
        axis = (second - first) / np.linalg.norm(second - first)
        offsets = vertices - first
        distances = np.linalg.norm(offsets - np.outer(offsets @ axis, axis), axis=1)
        diameters.append(2 * distances.max())
    return np.array(diameters)


def cable_assessment(model):
    """The cable structure's judgement of a built bridge, from the arguments it records."""
    return make_structure(model.metadata["structure"]["name"]).assess(Design.of_model(model))


def test_the_rule_file_is_a_cable_structure(grammar):
    assert grammar.structure == "cable"
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


def test_cable_sections_are_the_assessed_diameter(golden_gate):
    assessment = cable_assessment(golden_gate)
    assert assessment.structure == "cable" and assessment.stands
    diameters = cable_section_diameters(golden_gate)
    # Every piece of every cable, main and side spans, has the governing diameter.
    assert len(diameters) == len(tagged(golden_gate, "cable")) > 0
    np.testing.assert_allclose(diameters, assessment.section["cable_diameter"], rtol=1e-9)
    assert diameters[0] == pytest.approx(0.92, abs=0.01)  # Patow 2012, Table 2, D_direct


@pytest.mark.parametrize(
    "attrs",
    [
        {},
        {"length": 5000, "towers": 0},
        {"length": 5000, "towers": 4, "main_span": 1000, "min_span": 1000},
        {"length": 3000.6, "main_span": 1000.2, "towers": 0, "min_span": 100, "sag": 125},
        {"length": 2560, "towers": 1},
    ],
)
def test_reported_towers_are_the_towers_built(grammar, attrs):
    model = grammar.build(attrs=attrs)
    reports = model.metadata["reports"]
    towers = tower_positions(model)
    assert reports["towers"] == len(towers) == reports["main_spans"] + 1
    side = reports["side_span"]
    assert side >= 0
    assert towers[0] == pytest.approx(side)
    np.testing.assert_allclose(np.diff(towers), model.metadata["attrs"]["main_span"], rtol=1e-9)
    assert cable_assessment(model).section["side_span"] == side


def test_cli_build_reports_the_bridge_as_built(tmp_path):
    report_path, model_path = tmp_path / "r.json", tmp_path / "bridge.json"
    code = main(
        [
            "build", GRAMMAR, "--set", "lanes=6", "--set", "main_span=1280", "--set", "sag=152",
            "--analyze", "-o", str(model_path), "--report", str(report_path), "-q",
        ]
    )  # fmt: skip
    assert code == 0
    report = json.loads(report_path.read_text())
    assert "bridge" not in report
    analysis = report["analysis"]
    assert analysis["structure"] == report["structure"] == "cable"
    for key in (
        "main_span", "sag", "side_span", "cable_diameter", "main_span_diameter", "cable_area",
        "max_tension", "load_per_metre", "max_cable_diameter",
    ):  # fmt: skip
        assert key in analysis
    assert analysis["stands"] and analysis["measure"] == 0.0
    assert analysis["main_span_diameter"] == pytest.approx(0.92, abs=0.01)
    assert analysis["load_per_metre"] == pytest.approx(5300 * 6 * 9.81, rel=1e-3)
    assert analysis["side_span"] == pytest.approx(343.0) == report["reports"]["side_span"]
    model = read_model(model_path)
    np.testing.assert_allclose(
        cable_section_diameters(model), analysis["cable_diameter"], rtol=1e-9
    )
    assert report["reports"]["towers"] == len(tower_positions(model)) == 2


def test_cli_layout_at_a_whole_number_of_spans_has_one_source(tmp_path):
    # 3000.6 / 1000.2 rounds below 3: two main spans and two half-span sides; the report, the
    # cable model and the geometry must all use that one layout.
    report_path, model_path = tmp_path / "r.json", tmp_path / "bridge.json"
    code = main(
        [
            "build", GRAMMAR, "--set", "length=3000.6", "--set", "main_span=1000.2",
            "--set", "towers=0", "--set", "min_span=100", "--set", "sag=125", "--analyze",
            "-o", str(model_path), "--report", str(report_path), "-q",
        ]
    )  # fmt: skip
    assert code == 0
    report = json.loads(report_path.read_text())
    reports = report["reports"]
    model = read_model(model_path)
    towers = tower_positions(model)
    assert reports["towers"] == len(towers) == reports["main_spans"] + 1
    main_spans = reports["main_spans"]
    side = (3000.6 - main_spans * 1000.2) / 2
    assert reports["side_span"] == pytest.approx(side)
    assert report["analysis"]["side_span"] == reports["side_span"]
    assert towers == pytest.approx(side + 1000.2 * np.arange(main_spans + 1))
    pieces_per_cable = len(tagged(model, "cable")) // 2
    side_pieces = 2 * max(4, round(48 * side / 1000.2)) if side > 1 else 0
    assert pieces_per_cable == main_spans * 48 + side_pieces


def test_optimize_golden_gate_finds_a_cable_under_the_maximum(grammar):
    result = optimize(grammar)  # the defaults: Golden Gate, max_cable_diameter 0.924 m
    span, sag = result.values["main_span"], result.values["sag"]
    assert result.feasible and result.structure == "cable" and result.analysis is None
    assert 1280 <= span <= 1966 and 0 < sag < span / 2
    assert result.assessment.section["cable_diameter"] < 0.924
    assert result.evaluations > 0
    assert result.model is not None
    np.testing.assert_allclose(
        cable_section_diameters(result.model), result.assessment.section["cable_diameter"]
    )


def test_cli_optimize_runs_the_span_and_sag_search(tmp_path):
    report_path, model_path = tmp_path / "r.json", tmp_path / "bridge.json"
    code = main(
        ["build", GRAMMAR, "--optimize", "--set", "max_cable_diameter=0.8", "--report",
         str(report_path), "-q", "-o", str(model_path)]
    )  # fmt: skip
    assert code == 0
    report = json.loads(report_path.read_text())
    optimization, analysis = report["optimization"], report["analysis"]
    assert optimization["structure"] == "cable" and optimization["evaluations"] > 0
    assert optimization["method"] == "Powell" and optimization["feasible"]
    assert analysis["stands"] and analysis["cable_diameter"] <= analysis["max_cable_diameter"]
    assert analysis["main_span"] == pytest.approx(optimization["parameters"]["main_span"]["final"])
    assert analysis["sag"] == pytest.approx(optimization["parameters"]["sag"]["final"])
    model = read_model(model_path)
    np.testing.assert_allclose(cable_section_diameters(model), analysis["cable_diameter"])
    assert analyze(model).feasible  # towers and anchorages stand as blocks


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"lanes": 0, "tracks": 0}, "at least one lane or track"),
        ({"lanes": 2.5}, "'lanes' must be a whole number"),
        ({"length": 1000}, "side_span -140 m: the main spans are longer than the bridge"),
        ({"sag": 700}, "sag 700 m must be less than half the main span"),
        ({"towers": 3}, "side_span -297 m: the main spans are longer than the bridge"),
        ({"cables": 0}, "at least one main cable"),
    ],
)
def test_impossible_inputs_are_clear_errors(grammar, attrs, message):
    with pytest.raises(ShapegenError, match=message):
        grammar.build(attrs=attrs)


def test_impossible_inputs_fail_the_command_line():
    code = main(["build", GRAMMAR, "--set", "lanes=0", "--set", "tracks=0", "-q"])
    assert code != 0
