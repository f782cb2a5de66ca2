"""A search judges mostly designs that need tension: the QP solved first (analyze's
expect_tension) gives the same verdict and measure, and runs phase one only when it cannot prove
the tension itself."""

from __future__ import annotations

import numpy as np
import pytest

import shapegen.statics.analysis as analysis_module
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics import analyze
from shapegen.statics.solvers import Solution, SolveStatus
from shapegen.statics.tension import PHASE_ONE_STOP, QP_PROOF_FACTOR, proves_tension


def overhanging_stack(overhang: float) -> Model:
    """Two 1 m blocks on the ground, the top one shifted by ``overhang`` m along x (it tips
    past 0.5 m)."""
    blocks = [
        Block.box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        Block.box((overhang, 1.0, 0.0), (overhang + 1.0, 2.0, 1.0)),
    ]
    return Model(blocks, friction=0.7)


def solution(tensions: np.ndarray, status=SolveStatus.OPTIMAL, **info) -> Solution:
    m = len(tensions)
    x = np.concatenate([np.ones(m), tensions, np.zeros(2 * m)])
    return Solution(status, x, None, float(np.sum(tensions**2)), info=info)


def test_the_qp_proves_the_tension_above_what_phase_one_stops_at():
    bound = PHASE_ONE_STOP**2
    assert proves_tension(solution(np.array([np.sqrt(QP_PROOF_FACTOR * bound)])))
    assert not proves_tension(solution(np.array([np.sqrt(0.9 * QP_PROOF_FACTOR * bound)])))
    # with the back-end's duality gap: the objective less twice the gap
    assert proves_tension(solution(np.array([np.sqrt(1.1 * bound)]), gap=0.01 * bound))
    assert not proves_tension(solution(np.array([np.sqrt(1.1 * bound)]), gap=0.1 * bound))
    # an inaccurate solution proves nothing, unless the caller trusts it above a level
    inaccurate = solution(np.array([1.0]), SolveStatus.OPTIMAL_INACCURATE)
    assert not proves_tension(inaccurate) and proves_tension(inaccurate, below=0.5)
    assert not proves_tension(Solution(SolveStatus.INFEASIBLE, None, None, np.inf))


@pytest.mark.parametrize("overhang", [0.3, 0.55, 0.7, 0.9])
def test_the_qp_first_gives_the_same_verdict_and_measure(overhang, monkeypatch):
    model = overhanging_stack(overhang)
    usual = analyze(model)
    solves = []
    solve = analysis_module._solve

    def counted(problem, names, phase_one=False, **more):
        solves.append(phase_one)
        return solve(problem, names, phase_one=phase_one, **more)

    monkeypatch.setattr(analysis_module, "_solve", counted)
    first = analyze(model, expect_tension=True)
    assert first.feasible == usual.feasible == (overhang <= 0.5)
    assert first.infeasibility_normalized == pytest.approx(
        usual.infeasibility_normalized, rel=1e-5, abs=1e-12
    )
    if usual.infeasibility_normalized >= QP_PROOF_FACTOR * PHASE_ONE_STOP**2:
        assert solves == [False]  # the QP alone
    else:
        assert solves[0] is False and True in solves  # phase one decided
