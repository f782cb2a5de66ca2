"""The cable structure (Patow 2012): a suspension bridge stands when its governing main-cable
diameter d is at most the allowed diameter d_allowed = (1 - margin) max_cable_diameter.

Truth values: the verdict and measure of the structure's definition (measure 0 exactly when the
bridge stands, (d / d_allowed - 1)^2 otherwise), the sizing of
:func:`shapegen.statics.cables.bridge_cables` (checked against the paper in
tests/statics/test_cables.py), the paper's D_direct for the Golden Gate (0.92 m) and the layout
rules of rules/suspension_bridge.grammar (side spans (length - main_spans main_span) / 2, and
with towers = 0 as many main spans as fit in the length).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import shapegen
from shapegen.errors import GeometryError, OptionError, ShapegenError, StaticsError
from shapegen.statics import StaticsOptions
from shapegen.statics.cables import GOLDEN_FACTOR, SAFETY_FACTOR, CableSizing, bridge_cables
from shapegen.structures import Assessment, Design, make_structure
from shapegen.structures.cable import CableModel

# Patow 2012, Table 1: the Golden Gate, as the bundled rule file lays it out by default.
GOLDEN_GATE = {
    "main_span": 1280.0,
    "sag": 152.0,
    "side_span": 343.0,
    "lanes": 6.0,
    "tracks": 0.0,
    "cables": 2.0,
    "golden_factor": 5300.0,
    "safety_factor": 3.0,
    "max_cable_diameter": 0.924,
}

SECTION_KEYS = {
    "main_span",
    "sag",
    "side_span",
    "cable_diameter",
    "main_span_diameter",
    "side_span_diameter",
    "governing",
    "cable_area",
    "max_tension",
    "horizontal_tension",
    "load_per_metre",
    "max_cable_diameter",
    "allowed_diameter",
}


def never_built():
    pytest.fail("the cable model judges a design from its arguments: it must not build the model")


def assess(margin: float = 0.0, **change) -> Assessment:
    arguments = {**GOLDEN_GATE, **change}
    return CableModel().assess(Design(arguments, build=never_built), margin=margin)


def sizing(**change) -> CableSizing:
    arguments = {**GOLDEN_GATE, **change}
    arguments.pop("max_cable_diameter")
    return bridge_cables(**arguments)


GOLDEN_GATE_DIAMETER = sizing().diameter  # 0.917 m


@pytest.fixture(scope="module")
def grammar():
    return shapegen.load_grammar("suspension_bridge.grammar")


# ---------------------------------------------------------------------- the structure
def test_the_cable_structure_is_registered_and_judges_without_a_model():
    structure = make_structure("cable")
    assert isinstance(structure, CableModel) and structure.name == "cable"
    assert structure.needs_model is False and structure.has_gradient is False
    assert structure.measure_name == "(d/d_max - 1)²"
    assert structure.options is None
    assert structure.measure_change(assess(), Design(GOLDEN_GATE, build=never_built)) is None


@pytest.mark.parametrize("make", [lambda o: make_structure("cable", o), CableModel])
def test_block_statics_options_do_not_apply_to_cables(make):
    # by name or by class, the same refusal
    with pytest.raises(OptionError, match="does not apply to the structure 'cable'"):
        make(StaticsOptions(friction=0.5))


def test_golden_gate_stands_with_the_paper_diameter():
    assessment = assess()
    assert assessment.structure == "cable" and assessment.status == "optimal"
    assert assessment.stands and assessment.measure == 0.0 and assessment.ok
    assert set(assessment.section) == SECTION_KEYS
    section = assessment.section
    assert section["main_span_diameter"] == pytest.approx(0.92, abs=0.01)  # Table 2, D_direct
    assert section["governing"] == "main"
    assert section["cable_diameter"] == section["main_span_diameter"]
    assert section["side_span_diameter"] < section["main_span_diameter"]
    assert section["load_per_metre"] == pytest.approx(5300 * 6 * 9.81, rel=1e-3)
    assert section["max_cable_diameter"] == section["allowed_diameter"] == 0.924
    assert (section["main_span"], section["sag"], section["side_span"]) == (1280.0, 152.0, 343.0)


def test_section_and_detail_are_the_cable_sizing():
    assessment = assess()
    expected = sizing()
    assert isinstance(assessment.detail, CableSizing)
    section = assessment.section
    assert section["cable_diameter"] == expected.diameter
    assert section["main_span_diameter"] == expected.main_span_diameter
    assert section["side_span_diameter"] == expected.side_span_diameter
    assert section["cable_area"] == expected.area
    assert section["max_tension"] == expected.max_tension
    assert section["horizontal_tension"] == expected.horizontal_tension
    assert section["load_per_metre"] == expected.load_per_metre
    assert math.pi * section["cable_diameter"] ** 2 / 4 == pytest.approx(section["cable_area"])


def test_report_puts_the_verdict_before_the_section():
    report = assess(max_cable_diameter=0.8).to_report()
    assert list(report)[:5] == ["structure", "stands", "measure", "status", "margin"]
    assert report["structure"] == "cable" and report["stands"] is False
    assert report["measure"] > 0 and report["margin"] == 0.0
    assert set(report) - {"structure", "stands", "measure", "status", "margin"} == SECTION_KEYS


@pytest.mark.parametrize(
    "limit",
    [0.3, 0.8, GOLDEN_GATE_DIAMETER * (1 - 1e-12), GOLDEN_GATE_DIAMETER, 0.924, 2.0, 3],
)
def test_stands_iff_the_diameter_is_at_most_the_maximum(limit):
    d = GOLDEN_GATE_DIAMETER
    assessment = assess(max_cable_diameter=limit)
    assert assessment.stands == (d <= limit)
    assert assessment.section["cable_diameter"] == d  # the limit does not size the cable
    if assessment.stands:
        assert assessment.measure == 0.0
    else:
        assert assessment.measure > 0
        assert assessment.measure == pytest.approx((d / limit - 1) ** 2, rel=1e-12)


def test_measure_grows_with_the_excess():
    measures = [assess(max_cable_diameter=limit).measure for limit in (0.9, 0.8, 0.6, 0.3, 0.05)]
    assert 0 < measures[0] and all(np.diff(measures) > 0)


@pytest.mark.parametrize("margin", [0.01, 0.1, 0.5])
def test_margin_lowers_the_allowed_diameter(margin):
    d = GOLDEN_GATE_DIAMETER
    # A maximum between d and d / (1 - margin): stands without the margin, not with it.
    limit = d / (1 - margin / 2)
    plain = assess(max_cable_diameter=limit)
    reserved = assess(margin, max_cable_diameter=limit)
    assert plain.stands and plain.measure == 0.0 and plain.margin == 0.0
    assert not reserved.stands and reserved.margin == margin
    allowed = (1 - margin) * limit
    assert reserved.section["allowed_diameter"] == pytest.approx(allowed, rel=1e-15)
    assert reserved.section["max_cable_diameter"] == limit
    assert reserved.measure == pytest.approx((d / allowed - 1) ** 2, rel=1e-12)
    assert reserved.to_report()["margin"] == margin
    # With room for the margin, the design stands with and without it.
    roomy = assess(margin, max_cable_diameter=d / (1 - margin) * (1 + 1e-9))
    assert roomy.stands and roomy.measure == 0.0


@pytest.mark.parametrize("margin", [-0.5, 1.0, 2.0])
def test_a_margin_outside_0_1_is_refused(margin):
    with pytest.raises(ShapegenError, match="margin"):
        assess(margin)


def test_defaults_of_the_optional_arguments():
    required = {key: GOLDEN_GATE[key] for key in ("main_span", "sag", "lanes")}
    required["max_cable_diameter"] = 1.0
    by_default = CableModel().assess(Design(required, build=never_built))
    explicit = CableModel().assess(
        Design(
            {
                **required,
                "side_span": 0.0,
                "tracks": 0,
                "cables": 2,
                "golden_factor": GOLDEN_FACTOR,
                "safety_factor": SAFETY_FACTOR,
            },
            build=never_built,
        )
    )
    assert by_default.section == explicit.section
    assert by_default.section["side_span"] == 0.0 and by_default.section["side_span_diameter"] == 0


@pytest.mark.parametrize(
    ("change", "error", "words"),
    [
        ({"main_span": None}, OptionError, r"needs the argument\(s\) main_span"),
        ({"lanes": None, "sag": None}, OptionError, r"needs the argument\(s\) sag, lanes"),
        ({"max_cable_diameter": None}, OptionError, r"needs the argument\(s\) max_cable_"),
        ({"span": 1280.0}, OptionError, "has no argument 'span'; its arguments: main_span"),
        ({"max_cable_diameter": 0.0}, OptionError, "max_cable_diameter must be a positive"),
        ({"max_cable_diameter": -1}, OptionError, "max_cable_diameter must be a positive"),
        ({"max_cable_diameter": True}, OptionError, "max_cable_diameter must be a positive"),
        ({"max_cable_diameter": "1 m"}, OptionError, "max_cable_diameter must be a positive"),
        ({"lanes": "six"}, OptionError, "argument 'lanes' must be a number"),
        ({"sag": False}, OptionError, "argument 'sag' must be a number"),
        ({"main_span": 0.0}, GeometryError, "main_span"),
        ({"sag": 640.0}, GeometryError, "less than half the main span"),
        ({"sag": float("nan")}, GeometryError, "sag"),
        ({"side_span": -10.0}, GeometryError, "side_span"),
        ({"lanes": 0, "tracks": 0}, StaticsError, "at least one lane or track"),
        ({"lanes": 2.5}, StaticsError, "lanes must be a whole number"),
        ({"cables": 0}, StaticsError, "at least one main cable"),
        ({"golden_factor": -1.0}, StaticsError, "golden_factor"),
    ],
)
def test_bad_arguments_raise_one_clear_error(change, error, words):
    arguments = {**GOLDEN_GATE, **change}
    arguments = {k: v for k, v in arguments.items() if v is not None}
    with pytest.raises(error, match=words) as caught:
        CableModel().assess(Design(arguments, build=never_built))
    assert isinstance(caught.value, ShapegenError)


# ---------------------------------------------------------------------- the bridge's arguments
def test_the_bridge_grammar_hands_the_cable_model_its_layout(grammar):
    assert grammar.structure == "cable"
    assert grammar.structure_arguments() == {**GOLDEN_GATE, "min_span": 1280.0}
    three = grammar.structure_arguments({"length": 5000.0, "towers": 0})
    assert three["main_span"] == 1280.0
    assert three["side_span"] == pytest.approx((5000 - 3 * 1280) / 2)  # three main spans


@pytest.mark.parametrize(
    ("length", "span", "spans"),
    [(1966, 1280, 1), (2560, 1280, 2), (2559, 1280, 1), (5000, 1000, 5), (900, 1000, 1)],
)
def test_automatic_main_spans_fit_in_the_length(grammar, length, span, spans):
    attrs = {"length": length, "main_span": span, "min_span": 100, "towers": 0}
    arguments = grammar.structure_arguments(attrs)
    assert arguments["side_span"] == pytest.approx((length - spans * span) / 2)
    if length < span:  # one main span longer than the bridge cannot be sized
        with pytest.raises(GeometryError, match="side_span"):
            CableModel().assess(Design(arguments, build=never_built))


def test_towers_set_the_main_spans(grammar):
    arguments = grammar.structure_arguments({"length": 5000.0, "towers": 3})
    assert arguments["side_span"] == pytest.approx((5000 - 2 * 1280) / 2)
    overrun = grammar.structure_arguments({"main_span": 1966.0, "towers": 3})
    assert overrun["side_span"] == pytest.approx((1966 - 2 * 1966) / 2)
    with pytest.raises(GeometryError, match="side_span"):
        CableModel().assess(Design(overrun, build=never_built))


def test_a_built_bridge_is_judged_from_the_arguments_it_records(grammar):
    model = grammar.build(attrs={"max_cable_diameter": 0.9})
    recorded = model.metadata["structure"]
    assert recorded == {
        "name": "cable",
        "arguments": {**GOLDEN_GATE, "max_cable_diameter": 0.9, "min_span": 1280.0},
    }
    from_model = CableModel().assess(Design.of_model(model))
    assert not from_model.stands
    assert from_model.section == assess(max_cable_diameter=0.9).section


def test_a_main_span_shorter_than_min_span_is_refused():
    """The shortest acceptable main span is the distance between the shores: a design that does
    not cross them is an error naming both, never a verdict."""
    assert assess(min_span=GOLDEN_GATE["main_span"]).stands
    with pytest.raises(GeometryError, match="shorter than min_span 1300 m"):
        assess(min_span=1300.0)
