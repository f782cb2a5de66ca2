"""Connected components in numpy (shapegen/geometry/graphs.py) against scipy's csgraph."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components as scipy_components

from shapegen.geometry.graphs import connected_components


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("n, edges", [(1, 0), (10, 4), (300, 200), (2000, 1900), (500, 2000)])
def test_components_and_their_numbering_are_scipys(seed, n, edges):
    rng = np.random.default_rng(seed)
    first, second = rng.integers(n, size=edges), rng.integers(n, size=edges)
    count, label = connected_components(n, first, second)
    graph = coo_matrix((np.ones(edges), (first, second)), shape=(n, n))
    expected_count, expected = scipy_components(graph, directed=False)
    assert count == expected_count
    np.testing.assert_array_equal(label, expected)


def test_a_long_path_numbered_backwards_is_one_component():
    n = 10_000
    order = np.arange(n)[::-1]
    count, label = connected_components(n, order[:-1], order[1:])
    assert count == 1 and not label.any()


def test_no_edges_leave_every_node_alone():
    count, label = connected_components(4, [], [])
    assert count == 4 and label.tolist() == [0, 1, 2, 3]
