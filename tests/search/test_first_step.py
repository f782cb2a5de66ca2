"""The SQP's first step goes to where the linearised sqrt(measure) vanishes, moving a parameter
by at least FIRST_STEP and at most MAX_FIRST_STEP of its range.

A one-parameter measure ``y = (target - theta)^2`` (zero from ``target`` up) has a linear
``sqrt(y)``, so that step lands on the standing region's edge exactly when it is within reach.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from shapegen.search.evaluator import Evaluation
from shapegen.search.methods import FIRST_STEP, MAX_FIRST_STEP, Search


class Parabola:
    """Stands in for an Evaluator: ``y = max(target - theta, 0)^2`` on [0, 1]."""

    def __init__(self, target: float):
        self.target = target
        self.lower, self.upper = np.zeros(1), np.ones(1)
        self.evaluations = 0
        self.seen: list[float] = []

    def named(self, theta):
        return {"x": float(theta[0])}

    def evaluate(self, theta):
        theta = np.clip(np.asarray(theta, float), 0.0, 1.0)
        if not self.seen or theta[0] != self.seen[-1]:
            self.evaluations += 1
            self.seen.append(float(theta[0]))
        y = max(self.target - theta[0], 0.0) ** 2
        return Evaluation(theta, None, None, y, y <= 1e-20)

    def gradient(self, theta, method):
        return np.array([-2.0 * max(self.target - float(theta[0]), 0.0)])


def search(target: float) -> tuple[Parabola, Evaluation]:
    parabola = Parabola(target)
    best, converged, _ = Search(parabola, "adjoint", 50, None, time.perf_counter()).energy(
        [np.zeros(1)]
    )
    assert converged and best.feasible
    return parabola, best


@pytest.mark.parametrize("target", [0.2, 0.35, 0.45])
def test_a_linear_root_within_reach_is_reached_in_one_step(target):
    parabola, best = search(target)
    assert parabola.seen[:2] == [0.0, pytest.approx(target, abs=1e-12)]
    assert parabola.evaluations == 2
    assert best.theta[0] == pytest.approx(target, abs=1e-12)


def test_the_first_step_is_at_most_max_first_step():
    parabola, best = search(0.9)
    assert parabola.seen[1] == pytest.approx(MAX_FIRST_STEP, abs=1e-12)
    assert best.theta[0] >= 0.9 - 1e-9


def test_the_first_step_is_at_least_first_step():
    parabola, best = search(0.03)
    assert parabola.seen[1] == pytest.approx(FIRST_STEP, abs=1e-12)
    assert math.isclose(best.infeasibility, 0.0, abs_tol=1e-20)
