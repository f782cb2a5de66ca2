"""Tension colouring: a standing model is never painted red; round-off is not tension."""

from types import SimpleNamespace

import numpy as np

from shapegen.export.colors import tension_levels
from shapegen.tolerances import FORCE_NOISE_REL


def _analysis(tension, feasible, weight=1e4):
    return SimpleNamespace(
        block_tension=np.array(tension, float), feasible=feasible, total_weight=weight
    )


def test_a_standing_model_has_no_tension_colour():
    levels = tension_levels(_analysis([1e-9, 3e-8, 0.0], feasible=True))
    np.testing.assert_array_equal(levels, [0.0, 0.0, 0.0])


def test_round_off_below_the_noise_floor_is_ignored_and_the_rest_is_relative():
    noise = 0.5 * FORCE_NOISE_REL * 1e4
    levels = tension_levels(_analysis([noise, 20.0, 40.0, float("nan")], feasible=False))
    np.testing.assert_allclose(levels, [0.0, 0.5, 1.0, 0.0])
