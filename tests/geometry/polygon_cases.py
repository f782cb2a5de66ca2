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


def footprint(rng: np.random.Generator) -> np.ndarray:
    """``(n, 2)`` corners (east, north, m) of a building footprint as lot files give them:
    counter-clockwise seen from above, in a city's frame (near its origin or a few km away),
    turned any way; an L, a star, or a polygon whose edges carry extra corners nearly in line
    (surveyed points, jittered by 1 um to 1 cm). It may cross itself or be convex: callers
    keep the ones they need."""
    kind = int(rng.integers(3))
    if kind == 0:  # an L, its corners jittered
        width, depth = rng.uniform(8, 40, 2)
        a, b = rng.uniform(0.2, 0.8, 2)
        ring = np.array(
            [[0, 0], [width, 0], [width, depth * a], [width * b, depth * a],
             [width * b, depth], [0, depth]]
        )  # fmt: skip
        ring = ring + rng.normal(scale=rng.choice([0, 1e-4, 1e-2, 0.3]), size=ring.shape)
    elif kind == 1:
        ring = star_polygon(rng, 4, 20)
    else:  # corners on the edges of a star, nearly in line with them
        corners = star_polygon(rng, 5, 20)
        points = []
        for start, end in zip(corners, np.roll(corners, -1, axis=0), strict=True):
            for t in np.linspace(0, 1, int(rng.integers(1, 4)), endpoint=False):
                points.append(start + t * (end - start))
        ring = np.array(points)
        ring = ring + rng.normal(scale=rng.choice([1e-6, 1e-4, 1e-2]), size=ring.shape)
    angle = rng.uniform(0, 2 * np.pi)
    turn = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    return ring @ turn.T + rng.uniform(-3000, 3000, 2) * rng.integers(2)
