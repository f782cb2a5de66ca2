"""scatter (op_scatter): point shapes on a surface, in a volume or in the scope; a uniform
or gaussian draw around a side of the scope; each point a zero-size scope with one vertex, y along
the surface normal on a surface; the same points for the same seed."""

from __future__ import annotations

import math

import numpy as np
import pytest

import shapegen
from shapegen.errors import GrammarError


def _build(text, seed=0):
    return shapegen.parse_grammar("@StartRule\n" + text, "scatter.cga").build(
        lot=(12, 8), seed=seed
    )


CUBE = "Leaf --> primitiveCube() s(0.2, 0.2, 0.2) center(xz)\n"


def _leaves(model):
    """The inserted cubes: blocks, and those cut at the roof's trim planes (drawn open)."""
    return [*model.blocks, *model.surfaces]


def _centres(model):
    return np.array([b.vertices.mean(axis=0) for b in _leaves(model)])


def test_points_on_a_surface_stand_on_it_along_its_normal():
    model = _build(
        "Lot --> extrude(2) comp(f) { top : scatter(surface, 50, uniform) { Leaf } }\n" + CUBE,
    )
    centres = _centres(model)
    assert len(centres) == 50
    # a 0.2 m cube standing on the roof at y = 2 (cut by the roof's trim planes near its edges)
    assert np.allclose([b.vertices[:, 1].min() for b in _leaves(model)], 2.0)
    assert np.allclose([b.vertices[:, 1].max() for b in _leaves(model)], 2.2)
    assert centres[:, 0].min() > -0.2 and centres[:, 0].max() < 12.2
    assert centres[:, 2].min() > -0.2 and centres[:, 2].max() < 8.2


def test_points_in_a_volume_and_in_the_scope_lie_inside():
    for domain in ("volume", "scope"):
        model = _build(f"Lot --> extrude(3) scatter({domain}, 200, uniform) {{ P }}\n"
                                 "P --> primitiveCube() s(0.01, 0.01, 0.01)\n")  # fmt: skip
        c = _centres(model)
        assert len(c) == 200
        assert (c >= -0.01).all() and (c <= [12.01, 3.01, 8.01]).all()
        # uniform: the mean is near the middle (standard error of 200 draws: 0.29 m in x)
        assert abs(c[:, 0].mean() - 6) < 1.2 and abs(c[:, 1].mean() - 1.5) < 0.4


def test_a_gaussian_on_the_left_side_is_a_half_normal_on_the_face():
    text = "Lot --> scatter(surface, 400, gaussian, left, '0.1) { Leaf }\n" + CUBE
    x = _centres(_build(text))[:, 0]
    # accepted draws on x >= 0 around x = 0 with sigma 0.1 x 12 m: mean sigma sqrt(2/pi)
    assert x.mean() == pytest.approx(1.2 * math.sqrt(2 / math.pi), abs=0.2)
    assert np.percentile(x, 95) < 3.5


def test_same_seed_same_points_and_points_draw_nothing():
    text = "Lot --> scatter(surface, 20, uniform) { Leaf }\n" + CUBE
    a, b, c = (_centres(_build(text, seed)) for seed in (1, 1, 2))
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    empty = _build("Lot --> scatter(scope, 20, uniform) { X. }\n")
    assert not empty.blocks and not empty.surfaces


@pytest.mark.parametrize(
    "call, message",
    [
        ("scatter(edges, 3, uniform)", "domain is surface, volume or scope"),
        ("scatter(surface, 3, poisson)", "undefined name 'poisson'"),
        ("scatter(surface, 3, uniform, left)", "belong to a gaussian"),
    ],
)
def test_bad_calls_are_load_errors(call, message):
    with pytest.raises(GrammarError, match=message):
        _build(f"Lot --> {call} {{ X }}\n")


@pytest.mark.parametrize(("count", "points"), [("2.5", 2), ("2.99", 2), ("-1", 0)])
def test_a_count_that_is_not_whole_places_its_whole_part_with_a_warning(count, points):
    # op_scatter: nPoints is a float; the derivation goes on with the count's whole part
    model = _build(f"Lot --> scatter(surface, {count}, uniform) {{ Leaf }}\n" + CUBE)
    assert len(model.blocks) == points
    (warning,) = [w for w in model.metadata["warnings"] if "scatter()" in w]
    assert warning.startswith("scatter.cga" + ":2:9: ")
    assert f"places {points}" in warning
