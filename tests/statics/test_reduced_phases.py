"""Phase one's early answers and the QP's warm start (reduced back-end) keep the verdicts and y."""

from __future__ import annotations

import pytest
from statics_cases import running_bond_wall

import shapegen.statics.analysis as analysis
from shapegen.statics import analyze, certify, find_interfaces
from shapegen.statics.assembly import assemble
from shapegen.statics.solvers.reduced import ReducedBackend


def test_phase_one_stops_at_the_first_certified_solution():
    model = running_bond_wall(friction=0.7)
    problem = assemble(model, find_interfaces(model))
    phase_one = problem.with_objective("tension_sum")
    full = ReducedBackend().solve(phase_one)
    early = ReducedBackend(accept=lambda x: certify(problem, x) <= 1e-7).solve(phase_one)
    assert early.status.value == "optimal" and early.info["accepted"]
    assert early.iterations < full.iterations
    assert certify(problem, early.x) <= 1e-7


def test_a_sliding_wall_is_screened_and_the_qp_gives_the_same_y():
    model = running_bond_wall(tilt_degrees=12.0, friction=0.2)
    problem = assemble(model, find_interfaces(model))
    screened = ReducedBackend(stop_above=1e-3, screen_above=0.1).solve(
        problem.with_objective("tension_sum")
    )
    assert screened.info["screened"]
    cold = ReducedBackend().solve(problem)
    warm_backend = ReducedBackend()
    warm_backend.warm_start = screened.x
    warm = warm_backend.solve(problem)
    assert warm.status.value == cold.status.value == "optimal"
    assert warm.objective == pytest.approx(cold.objective, rel=1e-6)
    assert warm.iterations <= cold.iterations
    result = analyze(model, check=False, solver="reduced")
    assert not result.feasible
    assert result.infeasibility_normalized == pytest.approx(cold.objective, rel=1e-6)
    # Clarabel, which neither screens nor warm starts, agrees
    reference = analyze(model, check=False, solver="clarabel")
    assert result.infeasibility_normalized == pytest.approx(
        reference.infeasibility_normalized, rel=1e-5
    )


def test_a_screened_phase_one_is_redone_when_the_qp_finds_little_tension(monkeypatch):
    """Screening guesses; a standing wall screened by force must still be judged to stand."""
    model = running_bond_wall(friction=0.7)
    monkeypatch.setattr(analysis, "PHASE_ONE_SCREEN", -1e9)  # screen at the first chance
    # the wall's least-norm forces would certify it before phase one runs: this is phase one's
    monkeypatch.setattr(analysis, "least_norm_certificate", lambda *args: None)
    calls = []
    original = ReducedBackend.solve

    def recording(self, problem):
        solution = original(self, problem)
        calls.append((problem.objective, solution.info.get("screened")))
        return solution

    monkeypatch.setattr(ReducedBackend, "solve", recording)
    result = analyze(model, check=False, solver="reduced")
    assert calls[0] == ("tension_sum", True)
    assert calls[-1] == ("tension_sum", False)  # redone in full after the QP
    assert result.feasible
    assert result.infeasibility_normalized <= 1e-12


def test_a_nearby_designs_forces_start_the_solves_and_change_nothing(monkeypatch):
    # a search's next design: the same joints, a little more tilt; the QP starts from the
    # last design's forces and finds the same y, in fewer iterations
    last = analyze(running_bond_wall(tilt_degrees=12.0, friction=0.2), check=False)
    model = running_bond_wall(tilt_degrees=12.5, friction=0.2)
    iterations = []
    original = ReducedBackend.solve

    def counting(self, problem):
        solution = original(self, problem)
        iterations.append(solution.iterations)
        return solution

    monkeypatch.setattr(ReducedBackend, "solve", counting)
    cold = analyze(model, check=False, expect_tension=True)
    cold_iterations, iterations[:] = sum(iterations), []
    warm = analyze(model, check=False, expect_tension=True, warm_start=last)
    assert not warm.feasible and not cold.feasible
    assert warm.infeasibility_normalized == pytest.approx(cold.infeasibility_normalized, rel=1e-6)
    assert sum(iterations) < cold_iterations  # 10 against 13
    # other joints (a wall of another size) are not a start
    other = analyze(running_bond_wall(courses=6, tilt_degrees=12.0, friction=0.2), check=False)
    assert analysis.nearby_forces(other, warm.problem) is None
    assert analysis.nearby_forces(last, warm.problem) is not None
