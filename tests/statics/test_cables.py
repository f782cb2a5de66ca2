"""The cable model against the seed paper's Table 2 and against closed forms of statics."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq
from suspension_bridges import BRIDGES

from shapegen.errors import GeometryError, ShapegenError, StaticsError
from shapegen.statics.cables import (
    STRAND_BREAKING_STRESS,
    BridgeLoading,
    SpanCable,
    cable_area,
    catenary_parameter,
    round_cable_diameter,
    size_cables,
)


@pytest.mark.parametrize("bridge", BRIDGES, ids=[bridge.name for bridge in BRIDGES])
def test_main_span_diameter_reproduces_paper_table_2(bridge):
    loading = BridgeLoading(bridge.lanes, bridge.tracks, bridge.cables)
    sizing = size_cables(loading, bridge.main_span, bridge.sag)
    assert sizing.main_span_diameter == pytest.approx(bridge.table_2_diameter, abs=0.01)
    # Without side spans the governing diameter is the main span's.
    assert sizing.diameter == sizing.main_span_diameter


def test_strand_strength_matches_psi_conversion():
    # 76.669 short tons-force per square inch = 153 338 psi; 1 psi = 6894.757293168 Pa.
    assert STRAND_BREAKING_STRESS == pytest.approx(76.669 * 2000 * 6894.757293168, rel=1e-12)


@pytest.mark.parametrize("tension", [1.0, 2.5e8])
def test_cable_area_breaks_at_safety_factor_times_tension(tension):
    area = cable_area(tension, safety_factor=3.0)
    square_inches = area / 0.0254**2
    breaking_short_tons = 76.669 * square_inches
    assert breaking_short_tons * 2000 * 0.45359237 * 9.80665 == pytest.approx(3 * tension)


@pytest.mark.parametrize("diameter", [0.01, 0.924, 2.0])
def test_round_cable_diameter_inverts_circle_area(diameter):
    assert round_cable_diameter(math.pi * diameter**2 / 4) == pytest.approx(diameter)


@pytest.mark.parametrize(("lanes", "tracks"), [(6, 0), (7, 4), (0, 2)])
def test_load_is_golden_factor_times_effective_lanes(lanes, tracks):
    loading = BridgeLoading(lanes, tracks, cables=4)
    assert loading.load_per_metre == pytest.approx(5300 * 9.81 * (lanes + tracks))
    assert loading.load_per_cable == pytest.approx(loading.load_per_metre / 4)


@pytest.mark.parametrize("cables", [1, 2, 4])
def test_cables_share_the_load(cables):
    one = size_cables(BridgeLoading(6, cables=1), 1000.0, 100.0)
    shared = size_cables(BridgeLoading(6, cables=cables), 1000.0, 100.0)
    assert shared.area * cables == pytest.approx(one.area)


@pytest.mark.parametrize("ratio", [0.005, 0.01, 0.03, 0.06])
def test_parabola_length_series_agrees_with_arc_length(ratio):
    span = 800.0
    cable = SpanCable(span, ratio * span, 1.0)
    arc, _ = quad(lambda x: math.hypot(1.0, float(cable.slope(x))), -span / 2, span / 2)
    assert cable.exact_length == pytest.approx(arc, rel=1e-12)
    # The first neglected term of the series is -32/5 n^4 K.
    assert abs(cable.length - arc) <= 7.0 * ratio**4 * span
    assert abs(cable.length - arc) >= 5.0 * ratio**4 * span


@pytest.mark.parametrize(("span", "sag"), [(1280.0, 152.0), (100.0, 40.0), (500.0, 5.0)])
def test_parabola_shape_and_slope(span, sag):
    cable = SpanCable(span, sag, 1.0e5)
    assert cable.height(span / 2) == pytest.approx(sag)
    assert cable.height(-span / 2) == pytest.approx(sag)
    x = np.linspace(-span / 2, span / 2, 7)
    assert np.allclose(cable.slope(x), 8 * sag * x / span**2)
    step = 1e-4 * span
    central = (cable.height(x + step) - cable.height(x - step)) / (2 * step)
    assert np.allclose(cable.slope(x), central)


@pytest.mark.parametrize("shape", ["parabola", "catenary"])
@pytest.mark.parametrize(("span", "sag"), [(1280.0, 152.0), (100.0, 45.0)])
def test_peak_tension_from_support_equilibrium(shape, span, sag):
    load = 1.5e5
    cable = SpanCable(span, sag, load, shape)
    horizontal = cable.horizontal_tension
    support_slope = float(cable.slope(span / 2))
    assert cable.max_tension == pytest.approx(horizontal * math.hypot(1.0, support_slope))
    # Each support holds up half the cable's load: w K / 2 horizontally spread (parabola), or
    # w times half the cable length (catenary).
    carried = span if shape == "parabola" else cable.exact_length
    assert cable.max_tension == pytest.approx(math.hypot(horizontal, load * carried / 2))
    if shape == "parabola":
        assert horizontal == pytest.approx(load * span**2 / (8 * sag))


@pytest.mark.parametrize(("span", "sag"), [(1000.0, 1e-3), (1000.0, 10.0), (50.0, 20.0)])
def test_catenary_parameter_reproduces_sag(span, sag):
    a = catenary_parameter(span, sag)
    # cosh(u) - 1 written as 2 sinh(u/2)^2, which keeps its digits for a nearly flat cable.
    assert 2 * a * math.sinh(span / (4 * a)) ** 2 == pytest.approx(sag, rel=1e-9)
    assert a * (math.cosh(span / (2 * a)) - 1) == pytest.approx(sag, rel=1e-5)
    assert SpanCable(span, sag, 1.0, "catenary").height(span / 2) == pytest.approx(sag)


@pytest.mark.parametrize("ratio", [0.002, 0.01, 0.05])
def test_catenary_approaches_parabola_for_small_sag(ratio):
    span = 1000.0
    parabola = SpanCable(span, ratio * span, 1.0e5)
    catenary = SpanCable(span, ratio * span, 1.0e5, "catenary")
    for quantity in ("horizontal_tension", "max_tension", "exact_length"):
        para, cat = getattr(parabola, quantity), getattr(catenary, quantity)
        assert abs(cat - para) / para <= 4 * ratio**2, quantity


def test_catenary_differs_from_parabola_for_deep_sag():
    parabola = SpanCable(1000.0, 300.0, 1.0e5)
    catenary = SpanCable(1000.0, 300.0, 1.0e5, "catenary")
    assert catenary.max_tension > 1.05 * parabola.max_tension


@pytest.mark.parametrize("shape", ["parabola", "catenary"])
def test_side_spans_share_horizontal_tension_and_curve(shape):
    loading = BridgeLoading(4, cables=2, shape=shape)
    sizing = size_cables(loading, 1000.0, 100.0, length=1600.0)
    assert sizing.side_span == pytest.approx(300.0)
    side = SpanCable(sizing.side_span, sizing.side_sag, loading.load_per_cable, shape)
    assert side.horizontal_tension == pytest.approx(sizing.horizontal_tension, rel=1e-9)
    if shape == "parabola":
        assert sizing.side_sag == pytest.approx(100.0 * (300.0 / 1000.0) ** 2)
    assert sizing.governing == "main"
    assert sizing.side_span_diameter < sizing.main_span_diameter


@pytest.mark.parametrize("shape", ["parabola", "catenary"])
def test_side_span_as_long_as_main_span_needs_the_same_cable(shape):
    sizing = size_cables(BridgeLoading(4, shape=shape), 500.0, 60.0, length=1500.0)
    assert sizing.side_span == pytest.approx(500.0)
    assert sizing.side_sag == pytest.approx(60.0)
    assert sizing.side_span_diameter == pytest.approx(sizing.main_span_diameter)


def test_long_side_spans_govern():
    sizing = size_cables(BridgeLoading(4), 400.0, 50.0, length=2000.0)
    assert sizing.governing == "side"
    assert sizing.diameter == sizing.side_span_diameter > sizing.main_span_diameter
    assert sizing.area == sizing.side_span_area
    assert sizing.max_tension == sizing.side_span_tension


@pytest.mark.parametrize(
    ("build", "error", "words"),
    [
        (lambda: BridgeLoading(0, 0), StaticsError, "lane or track"),
        (lambda: BridgeLoading(-1, 3), StaticsError, "lane or track"),
        (lambda: BridgeLoading(6, cables=0), StaticsError, "main cable"),
        (lambda: BridgeLoading(6, golden_factor=-1.0), StaticsError, "golden_factor"),
        (lambda: BridgeLoading(6, shape="chain"), StaticsError, "parabola, catenary"),
        (lambda: SpanCable(0.0, 10.0, 1.0), GeometryError, "span"),
        (lambda: SpanCable(100.0, -1.0, 1.0), GeometryError, "sag"),
        (lambda: SpanCable(100.0, float("nan"), 1.0), GeometryError, "sag"),
        (lambda: size_cables(BridgeLoading(6), 1000.0, 100.0, 900.0), GeometryError, "shorter"),
    ],
)
def test_bad_inputs_raise_one_clear_error(build, error, words):
    with pytest.raises(error, match=words) as caught:
        build()
    assert isinstance(caught.value, ShapegenError)


def test_catenary_minimum_tension_sag_ratio_matches_closed_form():
    # For a fixed span, the catenary's peak tension w (a + f) is least where u tanh u = 1,
    # u = K / (2a); the sag ratio there is (cosh u - 1) / (2 u), about 0.3377.
    u = brentq(lambda u: u * math.tanh(u) - 1.0, 0.5, 2.0)
    best_ratio = (math.cosh(u) - 1) / (2 * u)
    ratios = np.linspace(0.2, 0.45, 251)
    tensions = [SpanCable(100.0, r * 100.0, 1.0, "catenary").max_tension for r in ratios]
    assert ratios[int(np.argmin(tensions))] == pytest.approx(best_ratio, abs=1e-3)


def test_parabola_diameter_falls_as_the_sag_ratio_grows_to_one_half():
    # The parabola's peak tension (w K / 8) sqrt(1 / n^2 + 16) falls with the sag ratio n over
    # the whole range n < 1/2: the thinnest parabolic cable of a span is at the bound n = 1/2
    # (unlike the catenary's, at about 0.3377, above).
    span, load = 1000.0, 1.0e5
    ratios = np.linspace(0.01, 0.4999, 200)
    tensions = np.array([SpanCable(span, r * span, load).max_tension for r in ratios])
    closed_form = load * span / 8 * np.sqrt(1 / ratios**2 + 16)
    np.testing.assert_allclose(tensions, closed_form, rtol=1e-12)
    assert np.all(np.diff(tensions) < 0)
    diameters = [size_cables(BridgeLoading(6), span, r * span).diameter for r in ratios]
    assert np.all(np.diff(diameters) < 0)


@pytest.mark.parametrize(
    ("length", "min_span", "main_spans"),
    [
        (1200.0, 100.0, 1),
        (3000.0, 500.0, 1),
        (1200.0, 600.0, 1),
        (1966.0, 1280.0, 1),
        (6000.0, 100.0, 2),
        (6000.0, 100.0, 3),
        (6000.0, 1400.0, 3),
    ],
)
def test_thinnest_cable_has_side_spans_as_long_as_the_main_spans_or_shorter(
    length, min_span, main_spans
):
    # At the sag ratio 1/2 a main span needs more tension the longer it is; the side spans
    # (length - m K) / 2 of m main spans hang on the same curve and govern once they outgrow K,
    # below K = length / (m + 2). The thinnest cable over K >= min_span is at
    # K* = max(min_span, length / (m + 2)).
    def sized(span):
        side = (length - main_spans * span) / 2
        return size_cables(BridgeLoading(6), span, 0.4999 * span, length=span + 2 * side)

    spans = np.linspace(min_span, length / main_spans, 2001)
    diameters = np.array([sized(k).diameter for k in spans])
    best = spans[int(np.argmin(diameters))]
    assert best == pytest.approx(max(min_span, length / (main_spans + 2)), abs=length / 1000)
    balanced = sized(length / (main_spans + 2))
    assert balanced.side_span == pytest.approx(length / (main_spans + 2))
    assert balanced.side_span_diameter == pytest.approx(balanced.main_span_diameter)
