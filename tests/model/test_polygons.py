"""The shared polygon routines."""

import numpy as np
import pytest

from shapegen.model.polygons import cross


@pytest.mark.parametrize("rows", [1, 3, 40, 1000])
def test_cross_gives_numpys_bits(rows):
    rng = np.random.default_rng(rows)
    a = rng.normal(size=(rows, 3)) * rng.uniform(1e-3, 1e6, size=(rows, 1))
    b = rng.normal(size=(rows, 3)) * 1e3
    assert np.array_equal(cross(a, b), np.cross(a, b))
