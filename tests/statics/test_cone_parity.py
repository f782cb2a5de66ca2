"""The exact friction cone on the reduced interior point method against Clarabel's cone.

Both solve the same second-order cone program, so on every model they must give the same
verdict and the same ``y / W^2`` (to the solvers' tolerances), and each answer must be an
optimum: its forces balance the loads within the cone, and the equilibrium multipliers of the
QP give the load sensitivity. The models are walls (standing and tilted until they slide),
arches (thick, thin, tilted) and the bundled block rules; a block on a slope checks the verdict
against the closed form atan(mu) at three headings.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from statics_cases import running_bond_wall
from test_friction_cone import block_on_slope, cone_kkt_violation

import shapegen
from shapegen.model.model import Model
from shapegen.primitives.arch import semicircular_arch
from shapegen.statics import analyze, assemble, find_interfaces
from shapegen.statics.solvers import get_backend

MU = 0.7


def arch(thickness: float, tilt_degrees: float = 0.0) -> Model:
    a = math.radians(tilt_degrees)
    blocks = semicircular_arch(1.0, thickness, 24, depth=0.5)
    return Model(blocks, friction=MU, gravity=(9.81 * math.sin(a), -9.81 * math.cos(a), 0.0))


MODELS = {
    "wall": lambda: running_bond_wall(),
    "wall_tilted_20": lambda: running_bond_wall(tilt_degrees=20.0),  # stands: 20 < 35 deg
    "wall_tilted_40": lambda: running_bond_wall(tilt_degrees=40.0),  # slides: tension
    "wall_low_friction": lambda: running_bond_wall(tilt_degrees=10.0, friction=0.1),
    "arch_thick": lambda: arch(0.2),
    "arch_thin": lambda: arch(0.08),  # below Milankovitch's 0.1075: needs tension
    "arch_tilted": lambda: arch(0.2, 12.0),
    "arch_tilted_far": lambda: arch(0.2, 20.0),
}
QUICK_RULES = ["arch_columns", "bezier_arches", "wall_windows", "tower", "barrel_vault", "mosque"]
SLOW_RULES = ["sainte_chapelle", "cluny"]


def _verdicts(model):
    interfaces = find_interfaces(model)
    results = {
        solver: analyze(model, interfaces=interfaces, pyramid="cone", solver=solver)
        for solver in ("reduced", "clarabel")
    }
    return results["reduced"], results["clarabel"]


def _assert_same(reduced, clarabel):
    assert reduced.solver == "reduced" and clarabel.solver == "clarabel"
    assert reduced.status.solved and clarabel.status.solved
    assert reduced.feasible == clarabel.feasible
    # y / W^2: the same optimum to the tolerances (a tiny y is certified zero either way)
    assert reduced.infeasibility_normalized == pytest.approx(
        clarabel.infeasibility_normalized, rel=1e-4, abs=1e-9
    )


@pytest.mark.parametrize("case", list(MODELS))
def test_the_reduced_cone_agrees_with_clarabels(case):
    _assert_same(*_verdicts(MODELS[case]()))


@pytest.mark.parametrize("case", list(MODELS))
def test_the_reduced_cone_meets_the_optimality_conditions(case):
    # the QP itself (not phase one), solved to the end, on the problem of the analysis
    model = MODELS[case]()
    problem = assemble(model, find_interfaces(model), pyramid="cone")
    solution = get_backend("reduced").solve(problem)
    assert solution.status.solved
    primal, dual, complementarity = cone_kkt_violation(problem, solution)
    assert primal <= 1e-7 and dual <= 1e-5 and complementarity <= 1e-6
    reference = get_backend("clarabel").solve(problem)
    m = problem.n_vertices
    tension = [float(np.sum(x[m : 2 * m] ** 2)) for x in (solution.x, reference.x)]
    # the reduced method stops at a complementarity gap of 1e-9 (100 times its tolerance)
    assert tension[0] == pytest.approx(tension[1], rel=1e-5, abs=1e-9)


@pytest.mark.parametrize("rule", QUICK_RULES)
def test_the_bundled_rules_get_the_same_verdict_from_both(rule):
    _assert_same(*_verdicts(shapegen.load_grammar(f"{rule}.grammar").build()))


@pytest.mark.slow
@pytest.mark.parametrize("rule", SLOW_RULES)
def test_the_large_bundled_rules_get_the_same_verdict_from_both(rule):
    _assert_same(*_verdicts(shapegen.load_grammar(f"{rule}.grammar").build()))


@pytest.mark.parametrize("heading", [0.0, 22.5, 45.0])
@pytest.mark.parametrize("slope", [33.0, 34.5, 35.5, 37.0])
def test_a_block_on_a_slope_stands_below_atan_mu_at_every_heading(slope, heading):
    # atan(0.7) = 34.99 deg; the default friction model is the cone, on the reduced back-end
    model = block_on_slope(slope, heading, MU)
    stands = slope < math.degrees(math.atan(MU))
    result = analyze(model)
    assert result.solver == "reduced" and result.problem.pyramid == "cone"
    assert result.feasible == stands
    clarabel = analyze(model, solver="clarabel")
    assert clarabel.feasible == stands
    assert np.isfinite(result.infeasibility_normalized)
