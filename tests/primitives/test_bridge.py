"""Bridge parts: the cable follows the parabola, the suspenders stand at the documented spacing.

Truth values are closed forms: the parabola y = chord - 4 f x (K - x) / K^2, the chord midpoint's
offset f / n^2 from the curve, the area of a regular polygon, and the strand sizing formulas
(docs/bridges.md) recomputed here from the published constants.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from shapegen.errors import GeometryError
from shapegen.model.scope import Scope
from shapegen.primitives import insert

GOLDEN_GATE = {
    "side_span": 0.0,
    "lanes": 6,
    "tracks": 0,
    "cables": 2,
    "golden_factor": 5300.0,
    "safety_factor": 3.0,
}


def span_scope(span: float, height: float, depth: float = 2.0, origin=(0.0, 0.0, 0.0)) -> Scope:
    return Scope.axis_aligned(origin=origin, size=(span, height, depth))


def parabola(x, span, sag, top, left_drop=0.0, right_drop=0.0):
    left, right = top - left_drop, top - right_drop
    return left + (right - left) * x / span - 4.0 * sag * x * (span - x) / span**2


def joint_centres(blocks) -> np.ndarray:
    """Centres of the joint sections (the planes x = const shared by neighbouring pieces)."""
    centres = []
    for block in blocks:
        x = block.vertices[:, 0]
        for end in (x.min(), x.max()):
            ring = block.vertices[np.isclose(x, end)]
            centres.append(ring.mean(axis=0))
    return np.unique(np.round(np.array(centres), 9), axis=0)


def test_cable_joints_lie_on_the_parabola_and_centroids_off_by_the_chord_offset():
    span, sag, segments = 1280.0, 152.0, 32
    scope = span_scope(span, sag + 3.0)
    blocks = insert("cable", scope, sag=sag, diameter=0.9, segments=segments)
    assert len(blocks) == segments
    assert all("cable" in b.tags for b in blocks)
    joints = joint_centres(blocks)
    assert len(joints) == segments + 1
    expected = parabola(joints[:, 0], span, sag, scope.sy)
    assert np.max(np.abs(joints[:, 1] - expected)) < 1e-9
    assert np.allclose(joints[:, 2], scope.sz / 2)
    # A straight piece's centroid is its chord's midpoint, above the curve by f / n^2.
    centroids = np.array([b.centroid for b in blocks])
    offset = centroids[:, 1] - parabola(centroids[:, 0], span, sag, scope.sy)
    assert np.allclose(offset, sag / segments**2, rtol=1e-9, atol=1e-9)


def test_cable_volume_is_section_area_times_span():
    span, diameter, sides = 300.0, 0.6, 8
    blocks = insert(
        "cable", span_scope(span, 40.0), sag=30.0, diameter=diameter, segments=10, sides=sides
    )
    radius = diameter / 2
    section = sides / 2 * radius**2 * math.sin(2 * math.pi / sides)
    assert sum(b.volume for b in blocks) == pytest.approx(section * span, rel=1e-9)
    widths = [np.ptp(b.vertices[:, 2]) for b in blocks]
    assert np.allclose(widths, diameter)


def test_side_span_is_an_arc_of_the_main_parabola():
    """Same load and horizontal tension: the same curvature 8 f / K^2 in every span."""
    main_span, sag, side, drop = 1280.0, 152.0, 343.0, 140.0
    scope = span_scope(side, sag + 3.0)
    blocks = insert(
        "cable", scope, sag=sag, main_span=main_span, drop_left=drop, diameter=0.9, segments=20
    )
    joints = joint_centres(blocks)
    second = np.polyfit(joints[:, 0], joints[:, 1], 2)[0]
    assert 2 * second == pytest.approx(8 * sag / main_span**2, rel=1e-9)
    assert joints[0, 1] == pytest.approx(scope.sy - drop)
    assert joints[-1, 1] == pytest.approx(scope.sy)


def test_sized_cable_matches_the_strand_formulas_and_the_paper():
    """Golden Gate (Table 1 inputs): the paper's D_direct is 0.92 m."""
    span, sag = 1280.0, 152.0
    blocks = insert("cable", span_scope(span, sag + 3.0), sag=sag, segments=4, **GOLDEN_GATE)
    diameter = np.ptp(blocks[0].vertices[:, 2])  # section across z: the full diameter
    pound_force, inch = 0.45359237 * 9.80665, 0.0254
    stress = 76.669 * 2000 * pound_force / inch**2
    load = 5300.0 * 6 * 9.81 / 2
    horizontal = load * span**2 / (8 * sag)
    peak = horizontal * math.sqrt(1 + (4 * sag / span) ** 2)
    area = 3.0 * peak / stress
    assert diameter == pytest.approx(math.sqrt(4 * area / math.pi), rel=1e-9)
    assert diameter == pytest.approx(0.92, abs=0.01)


def test_cable_in_a_turned_scope_is_turned_with_it():
    turn = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # x along -z
    scope = Scope(np.array([5.0, 0.0, 0.0]), turn, np.array([100.0, 20.0, 1.0]))
    blocks = insert("cable", scope, sag=10.0, diameter=0.5, segments=8)
    assert all(b.volume > 0 for b in blocks)
    lows = min(b.vertices[:, 1].min() for b in blocks)
    assert lows == pytest.approx(20.0 - 10.0 - 0.25, abs=0.2)


@pytest.mark.parametrize("spacing", [15.24, 20.0, 50.0])
def test_suspenders_at_the_spacing_reach_the_cable(spacing):
    span, sag = 400.0, 40.0
    scope = span_scope(span, sag + 3.0, origin=(10.0, 50.0, 0.0))
    hangers = insert("suspenders", scope, sag=sag, spacing=spacing, width=0.2)
    panels = round(span / spacing)
    assert len(hangers) == panels - 1
    x = np.sort([b.centroid[0] - 10.0 for b in hangers])
    assert np.allclose(x, span * np.arange(1, panels) / panels)
    for hanger in hangers:
        xc = hanger.centroid[0] - 10.0
        assert hanger.vertices[:, 1].min() == pytest.approx(50.0)
        top = 50.0 + parabola(xc, span, sag, scope.sy)
        assert hanger.vertices[:, 1].max() == pytest.approx(top)
        assert "suspender" in hanger.tags


def test_suspenders_shorter_than_the_minimum_are_left_out():
    # A cable whose lowest point touches the deck: the middle hanger would have no length.
    hangers = insert("suspenders", span_scope(100.0, 10.0), sag=10.0, spacing=10.0)
    x = np.arange(10.0, 100.0, 10.0)
    heights = parabola(x, 100.0, 10.0, 10.0)  # 0.4 m at x = 40 and 60, 0 at midspan
    assert len(hangers) == np.count_nonzero(heights >= 1.0) == 6


@pytest.mark.parametrize(
    ("name", "params", "message"),
    [
        ("cable", {"sag": 0.0, "diameter": 1.0}, "sag must be positive"),
        ("cable", {"sag": 5.0, "diameter": 1.0, "segments": 1}, "segments 1 must be at least 2"),
        ("cable", {"sag": 5.0, "diameter": 1.0, "drop_left": 50.0}, "drop_left 50 m"),
        ("cable", {"sag": 5.0, "lanes": 0}, "at least one lane or track"),
        ("suspenders", {"sag": 5.0, "spacing": 0.0}, "must be positive"),
        ("cable", {"sag": 5.0, "diamter": 1.0}, "did you mean 'diameter'"),
    ],
)
def test_bad_parameters_are_clear_errors(name, params, message):
    with pytest.raises(GeometryError, match=message):
        insert(name, span_scope(100.0, 20.0), **params)
