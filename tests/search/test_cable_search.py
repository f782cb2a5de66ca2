"""The search on the suspension bridge: main_span and sag searched with the cable model.

Truth values: Patow 2012's search, Powell's method on the cable diameter that stops at the first
design whose diameter is under the maximum; the bridges of the paper's Table 1 with their
published cable diameters; and, when the maximum is out of reach, the thinnest cable of the
parabola: the peak tension (w K / 8) sqrt(1 / n^2 + 16) falls as the sag ratio n grows to its
bound 1/2 (tests/statics/test_cables.py), and while the main span governs it falls with the
span, so the span goes to its lower bound min_span, until the side spans (length - K) / 2
outgrow it at K = length / 3: K* = max(min_span, length / 3).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from suspension_bridges import BRIDGES, Bridge

import shapegen
from shapegen.cli import main
from shapegen.engine.grammar_api import Grammar
from shapegen.errors import GeometryError, GrammarError, OptionError
from shapegen.search import optimize
from shapegen.statics.cables import bridge_cables
from shapegen.structures import Assessment, Design
from shapegen.structures.cable import CableModel

GRAMMAR = "suspension_bridge.grammar"


class RecordingCable(CableModel):
    """The cable model, keeping every design it judged, in order."""

    def __init__(self):
        super().__init__()
        self.judged: list[tuple[dict, Assessment]] = []

    def assess(self, design: Design, *, margin: float = 0.0) -> Assessment:
        assert not design.built, "the search built a model to judge a cable design"
        assessment = super().assess(design, margin=margin)
        self.judged.append((dict(design.arguments), assessment))
        return assessment


@pytest.fixture(scope="module")
def grammar():
    return shapegen.load_grammar(GRAMMAR)


def bridge_attrs(bridge: Bridge) -> dict:
    """The bridge at the shortest span allowed, with a shallow start (sag span / 10) whose cable
    is too thick, and the diameter of the bridge as built for the maximum, so that the search
    has to move."""
    return {
        "length": bridge.length,
        "min_span": bridge.main_span,
        "main_span": bridge.main_span,
        "sag": bridge.main_span / 10,
        "lanes": bridge.lanes,
        "tracks": bridge.tracks,
        "cables": bridge.cables,
        "max_cable_diameter": bridge.built_diameter,
    }


def thinnest_cable(length: float, min_span: float, lanes: int = 6) -> tuple[float, float]:
    """K* of one main span and the diameter there with the sag ratio at its bound 1/2."""
    span = max(min_span, length / 3)
    sizing = bridge_cables(
        main_span=span, sag=span / 2 * (1 - 1e-9), side_span=(length - span) / 2, lanes=lanes
    )
    return span, sizing.diameter


@pytest.mark.parametrize("bridge", BRIDGES, ids=[bridge.name for bridge in BRIDGES])
def test_search_stops_at_the_first_design_under_the_maximum(grammar, bridge):
    name, span = bridge.name, bridge.main_span
    structure = RecordingCable()
    attrs = bridge_attrs(bridge)
    # Margin 0: the paper's rule, the first design whose cable is under the maximum itself.
    result = optimize(grammar, attrs=attrs, structure=structure, build=False, margin=0)
    assert result.feasible and result.converged, name
    assert (result.method, result.gradient, result.structure) == ("Powell", "none", "cable")
    assert result.model is None  # build=False: nothing was built
    judged = structure.judged
    assert result.evaluations == len(judged) > 1
    # Every design before the last was too thick; the last one is the design found.
    assert all(not assessment.stands for _, assessment in judged[:-1]), name
    last_arguments, last = judged[-1]
    assert last.stands and last.section["cable_diameter"] <= bridge.built_diameter
    assert last_arguments == grammar.structure_arguments(result.attrs)
    assert result.assessment.section == last.section
    assert result.initial_infeasibility == judged[0][1].measure > 0
    # The path ends at the design found, within the bounds.
    assert result.path[0] == {"main_span": span, "sag": span / 10}
    assert result.path[-1] == result.values
    found_span, found_sag = result.values["main_span"], result.values["sag"]
    assert span <= found_span <= bridge.length
    assert 0 < found_sag < found_span / 2
    assert result.iterations >= 1


def test_search_with_a_forward_gradient_also_stops_at_the_first_standing_design(grammar):
    structure = RecordingCable()
    attrs = bridge_attrs(BRIDGES[0])
    result = optimize(grammar, attrs=attrs, structure=structure, gradient="forward", margin=0)
    assert result.feasible and result.method == "SLSQP"
    assert all(not assessment.stands for _, assessment in structure.judged[:-1])
    assert structure.judged[-1][1].stands
    assert result.evaluations == len(structure.judged)


def test_an_acceptable_start_stops_at_the_first_evaluation(grammar):
    structure = RecordingCable()
    attrs = {"length": 1500.0, "min_span": 1000.0, "main_span": 1500.0, "sag": 150.0}
    attrs["max_cable_diameter"] = 5.0
    result = optimize(grammar, attrs=attrs, structure=structure, build=False, margin=0)
    assert result.feasible and result.converged
    assert (result.evaluations, result.iterations) == (1, 0)
    assert len(structure.judged) == 1
    assert result.values == {"main_span": 1500.0, "sag": 150.0}
    assert result.path == [result.values]


@pytest.mark.parametrize(("length", "min_span"), [(1966.0, 1280.0), (1200.0, 600.0)])
def test_an_unreachable_maximum_converges_to_the_thinnest_cable(grammar, length, min_span):
    # min_span above length / 3: the main span governs and goes to its lower bound.
    structure = RecordingCable()
    attrs = {"length": length, "min_span": min_span, "main_span": min_span, "sag": min_span / 10}
    attrs["max_cable_diameter"] = 0.05  # out of reach: no early stop
    result = optimize(grammar, attrs=attrs, structure=structure, build=False)
    assert result.converged and not result.feasible
    assert "local minimum" in result.message
    assert not any(assessment.stands for _, assessment in structure.judged)
    span, sag = result.values["main_span"], result.values["sag"]
    assert span == pytest.approx(min_span, rel=1e-3)  # the lower bound of main_span
    assert sag < span / 2 and sag / span == pytest.approx(0.5, abs=1e-3)
    best_span, best_diameter = thinnest_cable(length, min_span)
    assert best_span == min_span
    assert result.assessment.section["cable_diameter"] == pytest.approx(best_diameter, rel=1e-3)
    assert result.assessment.section["cable_diameter"] > 0.05


@pytest.mark.parametrize(
    ("length", "min_span", "towers"), [(3000.0, 500.0, 2), (1200.0, 100.0, 2), (6000.0, 100.0, 3)]
)
def test_an_unreachable_maximum_balances_main_and_side_spans(grammar, length, min_span, towers):
    # min_span below length / (m + 2) for m = towers - 1 main spans: the side spans govern below
    # K = length / (m + 2), the main spans above (tests/statics/test_cables.py).
    attrs = {"length": length, "min_span": min_span, "main_span": min_span, "sag": min_span / 10}
    attrs.update(towers=towers, max_cable_diameter=0.05)
    result = optimize(grammar, attrs=attrs, build=False)
    assert result.converged and not result.feasible
    best_span = length / (towers + 1)
    assert best_span > min_span
    assert result.values["main_span"] == pytest.approx(best_span, rel=1e-3)
    assert result.values["sag"] / result.values["main_span"] == pytest.approx(0.5, abs=1e-3)


def test_automatic_towers_add_main_spans_until_the_cable_fits(grammar):
    """A long crossing whose single main span would need too thick a cable."""
    attrs = {"length": 6000.0, "min_span": 1000.0, "main_span": 6000.0, "sag": 600.0}
    attrs["max_cable_diameter"] = 0.75
    # With one main span the thinnest cable (K* = 2000 m, n = 1/2) is still too thick.
    assert thinnest_cable(6000.0, 1000.0)[1] > 0.75
    single = optimize(grammar, attrs={**attrs, "main_span": 2000.0, "towers": 2}, build=False)
    assert not single.feasible
    # With towers = 0 the layout follows main_span: shorter spans, more of them.
    result = optimize(grammar, attrs={**attrs, "towers": 0})
    assert result.feasible
    assert result.assessment.section["cable_diameter"] <= 0.75
    reports = result.model.metadata["reports"]
    assert reports["towers"] > 2 and reports["towers"] == reports["main_spans"] + 1
    span = result.values["main_span"]
    assert reports["main_spans"] == np.floor(6000.0 / span)
    assert result.assessment.section["side_span"] == pytest.approx(
        (6000.0 - reports["main_spans"] * span) / 2
    )


def test_fixing_the_sag_searches_the_main_span_alone(grammar):
    structure = RecordingCable()
    attrs = {"main_span": 1900.0, "max_cable_diameter": 0.924}
    result = optimize(grammar, attrs=attrs, fix={"sag": 152.0}, structure=structure, margin=0)
    assert list(result.parameters) == ["main_span"]
    assert result.feasible and result.attrs["sag"] == 152.0
    assert all(arguments["sag"] == 152.0 for arguments, _ in structure.judged)
    assert result.values["main_span"] < 1900.0
    assert result.model.metadata["attrs"]["sag"] == 152.0


def test_a_bridge_optimize_builds_the_model_exactly_once(grammar, monkeypatch, tmp_path):
    builds = []
    build = Grammar.build

    def counting_build(self, *args, **kwargs):
        builds.append(kwargs.get("attrs"))
        return build(self, *args, **kwargs)

    monkeypatch.setattr(Grammar, "build", counting_build)
    attrs = {"max_cable_diameter": 0.8}
    result = optimize(grammar, attrs=attrs, build=False)
    assert result.evaluations > 1 and builds == []  # judged from the arguments alone
    result = optimize(grammar, attrs=attrs)
    assert len(builds) == 1 and builds[0] == result.attrs
    assert result.model.metadata["attrs"]["sag"] == result.values["sag"]

    builds.clear()
    report_path = tmp_path / "r.json"
    code = main(
        ["build", GRAMMAR, "--optimize", "--set", "max_cable_diameter=0.8", "-q",
         "--report", str(report_path), "-o", str(tmp_path / "bridge.json")]
    )  # fmt: skip
    assert code == 0
    assert len(builds) == 1
    report = json.loads(report_path.read_text())
    assert report["optimization"]["evaluations"] > 1
    assert report["analysis"]["stands"] and report["analysis"]["cable_diameter"] <= 0.8
    assert report["attrs"]["sag"] == report["optimization"]["parameters"]["sag"]["final"]


@pytest.mark.parametrize(
    ("attrs", "error", "words"),
    [
        ({"length": 1000.0}, GrammarError, "attr 'main_span' has an empty @Range"),
        ({"sag": 700.0}, GeometryError, "starting design cannot be judged: .*half the main span"),
        ({"max_cable_diameter": 0.0}, OptionError, "max_cable_diameter must be a positive"),
        (
            {"length": 2000.0, "min_span": 1200.0, "main_span": 1200.0, "towers": 3},
            GeometryError,
            "starting design cannot be judged: .*side_span",
        ),
        ({"lanes": 0, "tracks": 0}, GeometryError, "starting design cannot be judged"),
    ],
)
def test_impossible_search_inputs_are_clear_errors(grammar, attrs, error, words):
    with pytest.raises(error, match=words):
        optimize(grammar, attrs=attrs, build=False)
