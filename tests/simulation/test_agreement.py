"""The simulation agrees with limit analysis on assemblies with known limits (issue 8, part 2).

- Semicircular arch of 40 voussoirs: the minimum thickness is t / R = 0.107 (Milankovitch); at
  0.13 it stands (no vertex moves 1 mm in 5 s after settling), at 0.08 it collapses.
- Harmonic stack of 6: each block overhangs the one below by ``factor * L / (2 k)``; at 0.95 of
  the critical offsets it stands, at 1.10 it falls.
Each case also checks the statics verdict, so a disagreement shows which side moved.
"""

import pytest

from shapegen.simulation import simulate
from shapegen.simulation.cases import arch, harmonic_stack, leaning_tower
from shapegen.statics import analyze


@pytest.mark.slow
def test_arch_thick_enough_stands_for_five_seconds():
    model = arch(0.13)
    assert analyze(model).feasible
    result = simulate(model, seconds=5.0)
    assert result.verdict == "stands"
    assert result.max_displacement < 1e-3  # metres, after the 0.5 s settling window
    assert result.settlement < 5e-3


def test_arch_too_thin_collapses():
    model = arch(0.08)
    assert not analyze(model).feasible
    result = simulate(model, seconds=3.0)
    assert result.verdict == "collapses"
    # The crown falls to the ground: far more than any settling.
    assert result.max_displacement > 0.2


@pytest.mark.parametrize("factor, stands", [(0.95, True), (1.10, False)])
def test_harmonic_stack_of_six(factor, stands):
    model = harmonic_stack(factor)
    assert analyze(model).feasible == stands
    result = simulate(model, seconds=3.0)
    assert result.stands == stands
    if not stands:
        top = result.motions[-1]
        assert top.displacement > 0.1  # the top block has toppled, not crept


@pytest.mark.parametrize("factor, stands", [(0.9, True), (1.1, False)])
def test_leaning_tower(factor, stands):
    model = leaning_tower(factor)
    assert analyze(model).feasible == stands
    assert simulate(model, seconds=3.0).stands == stands
