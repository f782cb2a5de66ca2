"""Powell search over main span and sag: early termination, bounds, and the known optimum."""

import math

import pytest
from scipy.optimize import brentq

from shapegen.engine.bridge_search import search_span_and_sag
from shapegen.errors import GeometryError, ShapegenError
from shapegen.statics.cables import BridgeLoading, size_cables

# Real bridges: main span (m), length between anchorages (main + both side spans, m), lanes,
# tracks, cables, published main-cable diameter (m).
REAL_BRIDGES = [
    ("Golden Gate", 1280.0, 1966.0, 6, 0, 2, 0.924),
    ("Akashi Kaikyo", 1991.0, 3911.0, 6, 0, 2, 1.122),
    ("Humber", 1410.0, 2220.0, 4, 0, 2, 0.70),
    ("Manhattan", 448.0, 890.0, 7, 4, 4, 0.53),
    ("Brooklyn", 487.0, 1053.0, 6, 0, 4, 0.40),
]


@pytest.mark.parametrize(
    ("name", "span", "length", "lanes", "tracks", "cables", "diameter"), REAL_BRIDGES
)
def test_search_stops_at_first_design_under_the_maximum(
    name, span, length, lanes, tracks, cables, diameter
):
    loading = BridgeLoading(lanes, tracks, cables)
    found = search_span_and_sag(loading, length=length, min_span=span, max_diameter=diameter)
    assert found.stopped_early and not found.converged, name
    assert found.diameter < diameter
    assert span <= found.span <= length
    assert 0 < found.sag < found.span / 2
    assert found.iterations >= 1
    assert found.evaluations >= 1
    # The design reported is the one that was sized.
    again = size_cables(loading, found.span, found.sag, length=length)
    assert again.diameter == pytest.approx(found.diameter)


def test_acceptable_start_stops_at_first_evaluation():
    found = search_span_and_sag(BridgeLoading(6), length=1500.0, min_span=1000.0, max_diameter=5.0)
    assert found.stopped_early
    assert (found.evaluations, found.iterations) == (1, 1)
    assert found.span == pytest.approx(1500.0)
    assert found.sag == pytest.approx(150.0)


@pytest.mark.parametrize(
    ("length", "min_span", "best_span"),
    [
        (1200.0, 100.0, 400.0),  # side spans govern below length / 3: towers balance there
        (3000.0, 500.0, 1000.0),
        (1200.0, 600.0, 600.0),  # the shores are farther apart than length / 3
    ],
)
def test_unreachable_maximum_converges_to_thinnest_parabolic_cable(length, min_span, best_span):
    # The parabolic peak tension (w K / 8) sqrt(1 / n^2 + 16) falls as the sag ratio n grows,
    # so the thinnest cable has n at its bound 1/2; the main span then needs the least tension
    # at the shortest span allowed, until the side spans (length - K) / 2 outgrow it at
    # K = length / 3 and govern.
    found = search_span_and_sag(
        BridgeLoading(6), length=length, min_span=min_span, max_diameter=0.01
    )
    assert found.converged and not found.stopped_early
    assert found.diameter > 0.01
    assert found.span == pytest.approx(best_span, rel=1e-3)
    assert found.sag / found.span == pytest.approx(0.5, abs=1e-3)
    best = size_cables(BridgeLoading(6), best_span, best_span * 0.5, length=length)
    assert found.diameter == pytest.approx(best.diameter, rel=1e-3)


@pytest.mark.parametrize("max_sag_ratio", [0.125, 0.3])
def test_sag_ratio_bound_is_respected(max_sag_ratio):
    found = search_span_and_sag(
        BridgeLoading(6),
        length=1500.0,
        min_span=1000.0,
        max_diameter=0.01,
        max_sag_ratio=max_sag_ratio,
    )
    assert found.converged
    assert found.sag <= max_sag_ratio * found.span * (1 + 1e-12)
    assert found.sag / found.span == pytest.approx(max_sag_ratio, rel=1e-3)
    assert found.span == pytest.approx(1000.0, rel=1e-3)


def test_unreachable_maximum_finds_catenary_optimal_sag():
    # A catenary's peak tension w (a + f) is least where u tanh u = 1 (u = K / 2a).
    u = brentq(lambda u: u * math.tanh(u) - 1.0, 0.5, 2.0)
    best_ratio = (math.cosh(u) - 1) / (2 * u)
    found = search_span_and_sag(
        BridgeLoading(6, shape="catenary"), length=1200.0, min_span=600.0, max_diameter=0.01
    )
    assert found.converged
    assert found.span == pytest.approx(600.0, rel=1e-6)
    assert found.sag / found.span == pytest.approx(best_ratio, abs=2e-3)


@pytest.mark.parametrize(
    ("settings", "words"),
    [
        ({"length": 1000.0, "min_span": 1200.0, "max_diameter": 1.0}, "minimum main span"),
        ({"length": -5.0, "min_span": 1.0, "max_diameter": 1.0}, "bridge length"),
        ({"length": 1000.0, "min_span": 800.0, "max_diameter": 0.0}, "maximum cable diameter"),
        (
            {"length": 1000.0, "min_span": 800.0, "max_diameter": 1.0, "initial_span": 700.0},
            "initial main span",
        ),
        (
            {"length": 1000.0, "min_span": 800.0, "max_diameter": 1.0, "initial_sag_ratio": 0.5},
            "initial sag ratio",
        ),
        (
            {"length": 1000.0, "min_span": 800.0, "max_diameter": 1.0, "max_sag_ratio": 0.6},
            "maximum sag ratio",
        ),
    ],
)
def test_bad_settings_raise_one_clear_error(settings, words):
    with pytest.raises(GeometryError, match=words) as caught:
        search_span_and_sag(BridgeLoading(6), **settings)
    assert isinstance(caught.value, ShapegenError)
