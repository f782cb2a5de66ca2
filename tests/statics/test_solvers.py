"""Every back-end on the same small problems: optimality conditions, closed forms, agreement."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import nnls
from statics_cases import assert_solved_within, horizontal_interface

from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.statics.assembly import assemble
from shapegen.statics.interface import GROUND
from shapegen.statics.solvers import BACKENDS, SolveStatus, get_backend

BACKEND_NAMES = list(BACKENDS)
G = 9.81


def box_on_ground():
    model = Model([Block.box((0, 0, 0), (1, 1, 1))])
    return model, [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)]


def hanging_block(x=(0.0, 1.0), z=(0.0, 1.0)):
    """A unit cube glued under a fixed ceiling block; the joint is the rectangle x by z."""
    model = Model(
        [Block.box((0, -1, 0), (1, 0, 1)), Block.box((-1, 0, -1), (2, 1, 2), fixed=True)],
        ground=None,
    )
    return model, [horizontal_interface(0, 1, 0.0, x, z, up=True)]


def block_on_tilted_ground(angle_deg, friction=0.7):
    """A squat block on the ground with gravity tilted by ``angle_deg`` along +x (the same as a
    tilted support); it would tip only past atan(2 / 0.2)."""
    a = math.radians(angle_deg)
    model = Model(
        [Block.box((0, 0, 0), (2, 0.2, 2))],
        gravity=(G * math.sin(a), -G * math.cos(a), 0.0),
        friction=friction,
    )
    return model, [horizontal_interface(0, GROUND, 0.0, (0, 2), (0, 2), up=False)]


def two_stacked(offset):
    """Block 1 on block 0 on the ground, block 1 shifted by ``offset`` along x."""
    model = Model([Block.box((0, 0, 0), (1, 1, 1)), Block.box((offset, 1, 0), (offset + 1, 2, 1))])
    interfaces = [
        horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False),
        horizontal_interface(0, 1, 1.0, (max(0, offset), min(1, 1 + offset)), (0, 1), up=True),
    ]
    return model, interfaces


CASES = {
    "box_on_ground": box_on_ground,
    "hanging_centred": hanging_block,
    "hanging_offset": lambda: hanging_block(x=(0.2, 0.6)),
    "sliding": lambda: block_on_tilted_ground(30.0),
    "holding": lambda: block_on_tilted_ground(20.0),
    "stack_overhang": lambda: two_stacked(0.7),
    "stack_inside": lambda: two_stacked(0.3),
}


def kkt_violation(problem, solution):
    """Largest violation of the optimality conditions of the scaled problem.

    The inequality multipliers are recovered from the equality multipliers: for ``s`` directly,
    for ``(c, u, t)`` by non-negative least squares per vertex against the cone rows.
    """
    m = problem.n_vertices
    x, lam = solution.x, solution.multipliers
    primal = np.abs(problem.residual(x)).max()
    c, s, u, t = x.reshape(4, m)
    cut = np.stack([c, u, t], axis=1)
    slack = -cut @ problem.cone.T  # >= 0
    primal = max(primal, max(0.0, -slack.min()), max(0.0, -s.min()))
    gradient = (problem.quadratic * x + problem.linear + problem.equality.T @ lam).reshape(4, m)
    z_s = gradient[1]  # stationarity in s: grad - z_s = 0
    stationarity = max(0.0, -z_s.min())
    complementarity = np.abs(z_s * s).max()
    for v in range(m):
        target = -np.array([gradient[0, v], gradient[2, v], gradient[3, v]])
        z, residual = nnls(problem.cone.T, target)
        stationarity = max(stationarity, residual)
        complementarity = max(complementarity, np.abs(z * slack[v]).max())
    return primal, stationarity, complementarity


@pytest.mark.parametrize("backend", BACKEND_NAMES)
@pytest.mark.parametrize("case", list(CASES))
def test_optimality_conditions(backend, case):
    model, interfaces = CASES[case]()
    problem = assemble(model, interfaces)
    assert_solved_within(backend, problem, kkt_violation, (1e-7, 1e-5, 1e-7))


def tension_sum_squared(problem, solution):
    m = problem.n_vertices
    return float(np.sum(solution.x[m : 2 * m] ** 2))


@pytest.mark.parametrize("backend", BACKEND_NAMES)
@pytest.mark.parametrize(
    "x_range, expected",
    [
        # centred: four equal tensions W/4 -> y/W^2 = 1/4
        ((0.0, 1.0), 0.25),
        # joint centre at x = 0.4, centroid at 0.5, half width 0.2: the least-norm tensions
        # W (1/4 + a x / sum x^2) give y/W^2 = 1/4 + a^2 / (4 h^2)
        ((0.2, 0.6), 0.25 + 0.1**2 / (4 * 0.2**2)),
    ],
)
def test_hanging_block_closed_form(backend, x_range, expected):
    model, interfaces = hanging_block(x=x_range)
    problem = assemble(model, interfaces)
    solution = get_backend(backend).solve(problem)
    assert solution.status is SolveStatus.OPTIMAL
    assert tension_sum_squared(problem, solution) == pytest.approx(expected, rel=1e-6)


@pytest.mark.parametrize("backend", BACKEND_NAMES)
def test_multipliers_are_the_load_sensitivity(backend):
    # hanging cube: y = W^2 / 4 with W the downward load, so dy/dw_y = -W/2 (w_y = -W);
    # in scaled units d(y/W^2)/d(w_y/W) = -1/2
    model, interfaces = hanging_block()
    problem = assemble(model, interfaces)
    solution = get_backend(backend).solve(problem)
    assert solution.multipliers[1] == pytest.approx(-0.5, rel=1e-5)
    # torque multipliers vanish: a small moment is carried at no first-order cost
    assert np.abs(solution.multipliers[3:]).max() < 1e-5


@pytest.mark.parametrize("backend", BACKEND_NAMES)
def test_no_friction_tangential_load_is_infeasible(backend):
    model, interfaces = block_on_tilted_ground(10.0, friction=0.0)
    solution = get_backend(backend).solve(assemble(model, interfaces))
    assert solution.status is SolveStatus.INFEASIBLE
    assert solution.x is None


@pytest.mark.parametrize("case", list(CASES))
def test_backends_agree(case):
    model, interfaces = CASES[case]()
    values = {}
    for name in BACKEND_NAMES:
        problem = assemble(model, interfaces)
        solution = get_backend(name).solve(problem)
        values[name] = tension_sum_squared(problem, solution)
    reference = values["clarabel"]
    for name, value in values.items():
        assert value == pytest.approx(reference, rel=1e-5, abs=1e-8), name


@pytest.mark.parametrize("backend", BACKEND_NAMES)
def test_point_load_enters_equilibrium(backend):
    # a horizontal push at the top of a unit cube: ground friction must carry it exactly
    model, interfaces = box_on_ground()
    weight = model.total_weight
    model.loads = [PointLoad(model.blocks[0].id, (0.1 * weight, 0, 0), (0.5, 1.0, 0.5))]
    problem = assemble(model, interfaces)
    solution = get_backend(backend).solve(problem)
    m = problem.n_vertices
    c, s, u, t = solution.x.reshape(4, m) * weight
    interface = problem.interfaces[0]
    force_on_ground = (
        (c - s).sum() * interface.normal
        + u.sum() * interface.tangent1
        + t.sum() * interface.tangent2
    )
    np.testing.assert_allclose(force_on_ground, (0.1 * weight, -weight, 0), atol=1e-6 * weight)


@pytest.mark.parametrize("backend", BACKEND_NAMES)
def test_a_loaded_block_without_contacts_is_infeasible(backend):
    problem = assemble(Model([Block.box((0, 1, 0), (1, 2, 1))]), [])
    assert get_backend(backend).solve(problem).status is SolveStatus.INFEASIBLE


@pytest.mark.parametrize("nf", [0, 1, 7])
def test_block_ordering_is_a_permutation(nf):
    from shapegen.statics.solvers.normal_equations import _block_ordering

    # A chain of blocks 0 - 1 - ... - (nf - 1), each also on its own diagonal.
    rows = np.concatenate([np.arange(nf - 1), np.arange(nf)]) if nf else np.zeros(0, int)
    cols = np.concatenate([np.arange(1, nf), np.arange(nf)]) if nf else np.zeros(0, int)
    order = _block_ordering(rows, cols, nf)
    assert order.dtype == np.int64
    assert sorted(order.tolist()) == list(range(nf))
