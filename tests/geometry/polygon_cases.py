"""Random polygons shared by the geometry tests."""

from __future__ import annotations

import numpy as np


def star_polygon(rng: np.random.Generator, low: float, high: float) -> np.ndarray:
    """``(n, 2)`` corners of a star-shaped polygon, 3 to 11 of them at sorted angles around the
    origin (counter-clockwise in x, y), at radii drawn from ``[low, high)``; it may cross
    itself where the angles are close."""
    n = int(rng.integers(3, 12))
    angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    radii = rng.uniform(low, high, n)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
