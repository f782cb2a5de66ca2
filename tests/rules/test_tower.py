"""rules/tower.grammar: a leaning tower of 16 levels of 6 blocks, 32 free level offsets.

Truth values from the rule's layout and from statics by hand. The joint under level j carries
everything above it; its contacts are horizontal and compression-only, so the tower can stand
only if the centre of mass of levels j..16 lies over the footprint of level j - 1 (all levels
have the same weight). With every level shifted by the same ``d`` along x from the one below,
levels j..16 sit ``d, 2d, ..., (17 - j) d`` from level j - 1, their centre of mass
``d (18 - j) / 2`` from it; the worst joint is the one under level 2, at ``8 d``. Half the tower's
width is 0.75 m, so a lean of ``d > 0.75 / 8 = 0.094 m`` cannot stand, and one well inside it
stands (the condition is necessary, not sufficient: single blocks can still tip near the
limit, so the test that stands keeps a wide margin).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from shapegen.search import optimize
from shapegen.statics import analyze

RULES = Path(__file__).resolve().parents[2] / "rules"
GRAMMAR = RULES / "tower.grammar"
LEVELS = 16
HALF_WIDTH = 0.75  # m, half the lot's 1.5 m
LEVEL_HEIGHT = 0.5  # m, the file's level_height


def lean(d_x: float, d_z: float = 0.0) -> dict[str, float]:
    """Attrs shifting every level by the same offsets (m)."""
    return {f"dx{k}": d_x for k in range(1, LEVELS + 1)} | {
        f"dz{k}": d_z for k in range(1, LEVELS + 1)
    }


def test_96_blocks_in_16_levels_of_6(grammar):
    model = grammar.build()
    assert len(model.blocks) == 96
    heights = np.array([b.centroid[1] for b in model.blocks])
    levels = np.floor(heights / LEVEL_HEIGHT).astype(int)
    assert np.array_equal(np.bincount(levels), np.full(LEVELS, 6))
    volume = sum(b.volume for b in model.blocks)
    assert volume == pytest.approx(LEVELS * LEVEL_HEIGHT * (2 * HALF_WIDTH) ** 2, rel=1e-9)


def test_32_free_offsets_with_ranges(grammar):
    free = grammar.free_parameters
    assert sorted(free) == sorted(f"d{a}{k}" for a in "xz" for k in range(1, LEVELS + 1))
    ranges = grammar.parameter_ranges()
    assert all(ranges[name]["min"] < 0 < ranges[name]["max"] for name in free)


def test_offsets_add_up_level_by_level(grammar):
    model = grammar.build(attrs=lean(0.05, -0.02))
    top = [b for b in model.blocks if b.centroid[1] > (LEVELS - 1) * LEVEL_HEIGHT]
    lo = np.min(np.vstack([b.vertices for b in top]), axis=0)
    assert lo[0] == pytest.approx(LEVELS * 0.05, abs=1e-9)
    assert lo[2] == pytest.approx(LEVELS * -0.02, abs=1e-9)


@pytest.mark.parametrize(
    ("d", "stands"),
    [
        (0.0, True),  # a plumb stack
        (0.05, True),  # 8 d = 0.4 m < 0.75 m
        (0.10, False),  # 8 d = 0.80 m > 0.75 m: just past the limit, the upper part tips over
        (0.12, False),  # 8 d = 0.96 m
        (-0.12, False),  # the same leaning the other way
    ],
)
def test_uniform_lean_against_the_centre_of_mass_limit(grammar, d, stands):
    assert analyze(grammar.build(attrs=lean(d))).feasible is stands


def test_mirrored_lean_needs_the_same_tension(grammar):
    attrs = grammar.attrs
    mirrored = {name: -value for name, value in attrs.items() if name.startswith("dx")}
    y = analyze(grammar.build()).infeasibility_normalized
    y_mirror = analyze(grammar.build(attrs=mirrored)).infeasibility_normalized
    assert y > 0
    assert y_mirror == pytest.approx(y, rel=1e-3)


def test_default_leans_too_far(grammar):
    dx = np.array([grammar.attrs[f"dx{k}"] for k in range(1, LEVELS + 1)])
    # Centre of mass of levels 2..16 over level 1, from the file's offsets: past the edge.
    cumulative = np.cumsum(dx[1:])
    assert cumulative.mean() > HALF_WIDTH
    assert not analyze(grammar.build()).feasible


@pytest.mark.slow
def test_optimize_makes_it_stand_within_bounds(grammar):
    result = optimize(grammar)
    assert result.feasible
    assert analyze(grammar.build(attrs=result.values)).feasible
    for name, p in result.parameters.items():
        assert p["min"] <= p["final"] <= p["max"], name
