"""The simulation agrees with limit analysis on assemblies with known limits.

- Harmonic stack of 6: each block overhangs the one below by ``factor * L / (2 k)``; it stands
  below the critical offsets (factor 1) and falls above them.
- Semicircular arch of 40 voussoirs, R = 1 m: the least thickness that stands is t / R = 0.1075
  (Milankovitch; Heyman). At 0.12 it stands (about 1 % of a voussoir's width of settling in 5 s),
  at 0.10 it falls.
Each case also checks the statics verdict, so a disagreement shows which side moved. The
simulator judges each block relative to its own smallest width (docs/simulation.md, "Verdict").
"""

import pytest

from shapegen.simulation import simulate
from shapegen.simulation.cases import arch, harmonic_stack, leaning_tower
from shapegen.statics import analyze
from shapegen.tolerances import SIMULATION_FALL_REL

MIN_THICKNESS_RATIO = 0.1075  # semicircular arch, friction high enough that no joint slides


@pytest.mark.parametrize(("factor", "stands"), [(0.95, True), (1.05, False)])
def test_harmonic_stack_of_six(factor, stands):
    model = harmonic_stack(factor)
    assert analyze(model).feasible == stands
    result = simulate(model, seconds=5.0)
    assert result.stands == stands, result.explanation()
    if stands:
        # Settling, not motion: a small fraction of the fall bar.
        assert result.max_relative_displacement < 0.1 * SIMULATION_FALL_REL
    else:
        top = result.motions[-1]
        assert top.fell and top.displacement > 0.1  # the top block has toppled, not crept


@pytest.mark.slow
def test_arch_at_a_ninth_over_its_minimum_thickness_stands_for_five_seconds():
    ratio = 0.12
    assert ratio > MIN_THICKNESS_RATIO
    model = arch(ratio)
    assert analyze(model).feasible
    result = simulate(model, seconds=5.0)
    assert result.verdict == "stands", result.explanation()
    assert result.max_relative_displacement < 0.5 * SIMULATION_FALL_REL
    assert result.moving_blocks == 0


def test_arch_thinner_than_its_minimum_thickness_collapses():
    ratio = 0.10
    assert ratio < MIN_THICKNESS_RATIO
    model = arch(ratio)
    assert not analyze(model).feasible
    result = simulate(model, seconds=2.0)
    assert result.verdict == "collapses"
    # The crown falls to the ground: its voussoirs move many times their own width.
    assert result.max_relative_displacement > 1.0
    assert result.peak_speed > 1.0  # m/s: a fall, not a creep


@pytest.mark.parametrize(("factor", "stands"), [(0.9, True), (1.1, False)])
def test_leaning_tower(factor, stands):
    model = leaning_tower(factor)
    assert analyze(model).feasible == stands
    assert simulate(model, seconds=3.0).stands == stands
