"""Shared tools of the validation tests: bisection on the verdict of an analysis."""

from collections.abc import Callable

import pytest


def bisect_threshold(
    stands: Callable[[float], bool], low: float, high: float, tolerance: float
) -> float:
    """The value where ``stands`` changes verdict, to within ``tolerance``.

    ``stands(low)`` and ``stands(high)`` must differ (checked); the verdict is assumed to change
    once in between. Returns the midpoint of the final bracket.
    """
    low_verdict = stands(low)
    assert stands(high) != low_verdict, f"no change of verdict between {low} and {high}"
    while high - low > tolerance:
        middle = 0.5 * (low + high)
        if stands(middle) == low_verdict:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


@pytest.fixture
def bisect():
    return bisect_threshold
