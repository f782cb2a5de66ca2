"""A `.grammar` rule's blocks are convex and disjoint: each is its own body, and the statics on
bodies give the verdicts and figures of the statics on blocks.

The analysis takes the blocks' own path when every body is one block; here the body path is
forced on the same models (every block a body of one part) and compared with it.
"""

from __future__ import annotations

import pytest

from shapegen.pipeline import load
from shapegen.statics import analyze, lateral_capacity
from shapegen.statics.bodies import Bodies

QUICK = ["arch_columns", "bezier_arches", "wall_windows", "tower", "barrel_vault", "mosque"]
SLOW = ["sainte_chapelle", "cluny"]


def _both(model, monkeypatch):
    blocks = analyze(model)
    assert blocks.bodies.trivial and blocks.problem.bodies is None
    with monkeypatch.context() as patch:
        patch.setattr(Bodies, "trivial", property(lambda self: False))
        bodies = analyze(model)
    assert bodies.problem.bodies is not None
    assert bodies.bodies.count == blocks.problem.n_free
    return blocks, bodies


def _same(blocks, bodies):
    assert bodies.feasible is blocks.feasible
    assert bodies.total_weight == blocks.total_weight
    assert bodies.infeasibility_normalized == pytest.approx(
        blocks.infeasibility_normalized, rel=1e-9, abs=1e-15
    )
    assert (bodies.problem.equality != blocks.problem.equality).nnz == 0
    assert (bodies.problem.load == blocks.problem.load).all()


@pytest.mark.parametrize("name", QUICK + [pytest.param(n, marks=pytest.mark.slow) for n in SLOW])
def test_every_bundled_block_rule_gives_the_same_verdict_on_bodies(name, monkeypatch):
    model = load(f"{name}.grammar").build()
    _same(*_both(model, monkeypatch))


def test_the_capacity_on_bodies_is_that_on_blocks(monkeypatch):
    model = load("wall_windows.grammar").build()
    blocks = lateral_capacity(model, azimuths=[0, 90])
    with monkeypatch.context() as patch:
        patch.setattr(Bodies, "trivial", property(lambda self: False))
        bodies = lateral_capacity(model, azimuths=[0, 90])
    for a, b in zip(blocks.directions, bodies.directions, strict=True):
        assert (a.status, a.tilt) == (b.status, b.tilt)
