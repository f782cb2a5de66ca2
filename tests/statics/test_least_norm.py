"""The least-norm forces as the first candidate for the feasibility certificate
(shapegen/statics/solvers/least_norm.py): they decide only when the analysis's own certificate
passes them, the interior point method decides otherwise, and a design that does not stand is
never certified."""

from __future__ import annotations

import math

import numpy as np
import pytest
from statics_cases import horizontal_interface, polygon_interface, running_bond_wall
from test_analysis import hanging, overhang

from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.statics import GROUND, analyze, certify, find_interfaces
from shapegen.statics.analysis import DECIDERS
from shapegen.statics.assembly import assemble
from shapegen.statics.solvers.least_norm import least_norm_forces
from shapegen.tolerances import DEFAULT

FEASIBLE_REL = DEFAULT.feasible_rel


def ground_reaction(result) -> np.ndarray:
    """The total force the free blocks put on the ground, N."""
    on_ground = [k for k, face in enumerate(result.interfaces) if face.second == GROUND]
    return result.resultant_forces[on_ground].sum(axis=0)


@pytest.mark.parametrize("pyramid", ["cone", "4"])
def test_a_standing_wall_is_certified_by_its_least_norm_forces(pyramid):
    model = running_bond_wall(courses=10, per_course=8, friction=0.7)
    result = analyze(model, pyramid=pyramid)
    assert result.feasible and result.decided_by == "least_norm"
    assert result.infeasibility == 0.0 and result.to_report()["decided_by"] == "least_norm"
    # the forces reported are the ones certified: compressive, in the friction law, and in
    # equilibrium (the ground carries the wall's weight)
    forces = result.forces
    assert np.all(forces[:, 0] >= 0) and np.all(forces[:, 1] == 0)
    assert np.all(np.hypot(forces[:, 2], forces[:, 3]) <= 0.7 * forces[:, 0] * (1 + 1e-12))
    weight = model.total_weight
    np.testing.assert_allclose(ground_reaction(result), (0, -weight, 0), atol=1e-7 * weight)
    # the back-end that does not build the normal equations judges the same
    other = analyze(model, pyramid=pyramid, solver="clarabel")
    assert other.feasible and other.decided_by == "phase_one"


def test_where_the_certificate_fails_the_interior_point_decides():
    # a push puts the resultant 0.05 from the joint's edge; with the joint's edge midpoints
    # among its vertices the least-norm forces (a linear distribution over the six of them)
    # pull at the far edge, yet the box stands on the near four
    push = 0.225  # the resultant at x = 0.5 + 2 push = 0.95; tips past push = 0.25
    model, _ = tall_box_pushed(push)
    corners = [(x, 0.0, z) for x in (0.0, 0.5, 1.0) for z in (0.0, 1.0)]
    interfaces = [polygon_interface(0, GROUND, (0, -1, 0), corners)]
    problem = assemble(model, interfaces)
    assert certify(problem, least_norm_forces(problem)) > FEASIBLE_REL
    result = analyze(model, interfaces=interfaces, check=False)
    assert result.feasible and result.decided_by == "phase_one"
    assert result.resultant_points[0][0] == pytest.approx(0.5 + 2 * push, abs=1e-6)


def test_a_block_centred_on_its_support_is_certified_at_once():
    # the least-norm forces of a centred block are its weight shared by the four corners
    model, interfaces = overhang(0.0)
    problem = assemble(model, interfaces)
    x = least_norm_forces(problem)
    m = problem.n_vertices
    np.testing.assert_allclose(x[:m], 0.25, rtol=1e-9)  # scaled by the weight
    assert analyze(model, interfaces=interfaces, check=False).decided_by == "least_norm"


def tall_box_pushed(push):
    model = Model([Block.box((0, 0, 0), (1, 2, 1), id="box")], friction=2.0)
    model.loads = [PointLoad("box", (push * model.total_weight, 0, 0), (0.5, 2.0, 0.5))]
    return model, [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)]


def sliding_block(factor):
    angle = math.atan(0.7) * factor
    model = Model(
        [Block.box((0, 0, 0), (2, 0.2, 2))],
        gravity=(9.81 * math.sin(angle), -9.81 * math.cos(angle), 0),
    )
    return model, [horizontal_interface(0, GROUND, 0.0, (0, 2), (0, 2), up=False)]


def sliding_wall():
    model = running_bond_wall(tilt_degrees=12.0, friction=0.2)  # tan 12 deg = 0.21 > 0.2
    return model, find_interfaces(model)


NOT_STANDING = {
    "overhang past the edge": lambda: overhang(0.55),
    "overhang just past the edge": lambda: overhang(0.501),
    "hanging": hanging,
    "tipped by a push": lambda: tall_box_pushed(0.26),
    "sliding block": lambda: sliding_block(1.01),
    "sliding wall": sliding_wall,
}


@pytest.mark.parametrize("case", NOT_STANDING, ids=list(NOT_STANDING))
def test_a_model_that_does_not_stand_is_never_certified(case):
    model, interfaces = NOT_STANDING[case]()
    problem = assemble(model, interfaces)
    x = least_norm_forces(problem)
    assert x is not None and certify(problem, x) > FEASIBLE_REL
    result = analyze(model, interfaces=interfaces, check=False)
    assert not result.feasible and result.infeasibility_normalized > 1e-6
    assert result.decided_by in DECIDERS and result.decided_by != "least_norm"


def test_nothing_to_solve_has_no_least_norm_forces():
    model = Model([Block.box((0, 0, 0), (1, 1, 1), fixed=True)])
    assert least_norm_forces(assemble(model, [])) is None
