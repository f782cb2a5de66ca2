"""The grid broad phase finds exactly the box pairs that overlap or touch."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.statics.broad_phase import _grid_pairs, candidate_pairs

RNG = np.random.default_rng(11)


def _brute_force(lower, upper, padding):
    n = len(lower)
    a, b = np.triu_indices(n, 1)
    keep = np.all((lower[a] <= upper[b] + padding) & (lower[b] <= upper[a] + padding), axis=1)
    return np.stack([a[keep], b[keep]], axis=1)


def _random(n, power=1.0):
    lower = RNG.uniform(0, 10, (n, 3))
    return lower, lower + RNG.uniform(0, 1, (n, 3)) ** power


def _with_slabs():
    lower, upper = _random(400)
    upper[:3] = lower[:3] + 50.0  # three boxes over everything
    return lower, upper


def _touching_cubes():
    lower = RNG.integers(0, 6, (300, 3)).astype(float)
    return lower, lower + 1.0


def _bricks():
    rows = [(x + 0.5 * (y % 2), y) for y in range(20) for x in range(30)]
    lower = np.array([[0.24 * x, 0.07 * y, 0.0] for x, y in rows])
    return lower, lower + [0.24, 0.07, 0.115]


def _flat():
    lower = RNG.uniform(0, 5, (200, 3))
    upper = lower.copy()
    upper[:, [0, 2]] += 0.7
    return lower, upper


CASES = {
    "random": lambda: _random(500),
    "random, unequal sizes": lambda: _random(500, power=4.0),
    "slabs over everything": _with_slabs,
    "touching cubes": _touching_cubes,
    "running bond": _bricks,
    "flat boxes": _flat,
    "all the same box": lambda: (np.zeros((40, 3)), np.ones((40, 3))),
    "two boxes": lambda: _random(2),
}


@pytest.mark.parametrize("padding", [0.0, 0.01])
@pytest.mark.parametrize("name", list(CASES))
def test_candidate_pairs_are_the_overlapping_pairs(name, padding):
    lower, upper = CASES[name]()
    expected = _brute_force(lower, upper, padding)
    found = candidate_pairs(lower, upper, padding)
    assert found.dtype == np.int64
    assert np.array_equal(found, expected)


def test_the_grid_takes_a_wall_and_leaves_crowded_boxes_to_the_sweep():
    lower, upper = _bricks()
    assert _grid_pairs(lower, upper, 0.0) is not None
    lower, upper = _random(500, power=12.0)  # a few large boxes among many specks
    upper[:300] = lower[:300] + 20.0
    assert _grid_pairs(lower, upper, 0.0) is None
    assert np.array_equal(candidate_pairs(lower, upper), _brute_force(lower, upper, 0.0))
