"""The exact Coulomb cone (``pyramid="cone"``): verdicts that do not turn with the model.

A block rests on a fixed slab; both are tilted by the slope angle about z and then turned by a
heading about the vertical. The 4-sided pyramid's sides follow the contact's tangent frame, which
is fixed to the normal, not to the downhill direction: with mu = 0.7 the block slides at
atan(0.7 / sqrt 2) = 26.33 deg at heading 0, where a side faces downhill, and at 32.88 deg at
heading 45 (there the frame stands at 40 deg to the downhill direction on that slope, and
tan(alpha) = mu / (sqrt 2 cos 40 deg)). The cone allows friction mu c in every direction, so the
block slides at atan(mu) whatever the heading.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from statics_cases import assert_solved_within, horizontal_interface

from shapegen.errors import OptionError, StaticsError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics import GROUND, StaticsOptions, analyze, certify
from shapegen.statics.assembly import assemble, friction_cone
from shapegen.statics.sensitivity import infeasibility_change
from shapegen.statics.solvers import BACKENDS, SolveStatus, get_backend

CONE_BACKENDS = [name for name, backend in BACKENDS.items() if backend.second_order_cones]
G = 9.81


def _turn(axis: int, degrees: float) -> np.ndarray:
    """Rotation by ``degrees`` about coordinate axis ``axis`` (right-handed)."""
    a = math.radians(degrees)
    i, j = [k for k in range(3) if k != axis]
    rotation = np.eye(3)
    rotation[i, i] = rotation[j, j] = math.cos(a)
    rotation[j, i], rotation[i, j] = math.sin(a), -math.sin(a)
    return rotation


def block_on_slope(slope: float, heading: float, friction: float, height: float = 0.25) -> Model:
    """A 1 x ``height`` x 0.5 m block on a fixed slab tilted by ``slope`` (deg) about z, the two
    turned by ``heading`` (deg) about the vertical. Squat by default: it would tip only past
    atan(1 / 0.25) = 76 deg."""
    slab = Block.box((-1.5, -0.5, -1.0), (1.5, 0.0, 1.0), fixed=True)
    block = Block.box((-0.5, 0.0, -0.25), (0.5, height, 0.25))
    rotation = _turn(1, heading) @ _turn(2, slope)
    lift = np.array([0.0, 2.0, 0.0])
    return Model(
        [b.transformed(rotation, lift) for b in (slab, block)], ground=None, friction=friction
    )


def stands(slope: float, heading: float, friction: float, pyramid: str) -> bool:
    return analyze(block_on_slope(slope, heading, friction), pyramid=pyramid).feasible


MU_30 = math.tan(math.radians(30.0))


@pytest.mark.parametrize("heading", [0.0, 15.0, 30.0, 45.0, 60.0])
def test_with_the_cone_the_verdict_does_not_turn_with_the_model(heading):
    assert stands(29.0, heading, MU_30, "cone")
    assert not stands(31.0, heading, MU_30, "cone")


@pytest.mark.parametrize("heading", [0.0, 45.0])
@pytest.mark.parametrize("pyramid", ["4", "cone"])
def test_the_cone_limit_is_atan_mu_to_a_tenth_of_a_degree(heading, pyramid):
    # mu = 0.7: atan(mu) = 34.99 deg; the 4-sided pyramid slides long before at either heading
    limit = math.degrees(math.atan(0.7))
    assert stands(limit - 0.1, heading, 0.7, "cone")
    assert not stands(limit + 0.1, heading, 0.7, "cone")
    if pyramid == "4":
        assert not stands(limit - 0.1, heading, 0.7, "4")


@pytest.mark.parametrize(
    "heading, limit",
    [
        (0.0, math.degrees(math.atan(0.7 / math.sqrt(2)))),  # 26.33 deg: a side faces downhill
        (45.0, 32.88),  # the limit the default pyramid gives when the model is turned
    ],
)
def test_the_4_sided_pyramid_turns_with_the_model(heading, limit):
    assert stands(limit - 0.05, heading, 0.7, "4")
    assert not stands(limit + 0.05, heading, 0.7, "4")


def test_the_turned_pyramid_limit_follows_from_its_frame():
    # the 32.88 deg above, from the frame: at heading 45 and slope alpha the downhill direction
    # makes an angle phi with tangent1 (cos phi = sin 45 / sqrt(sin^2 a sin^2 45 + cos^2 a)),
    # and the square |u|, |t| <= mu / sqrt 2 c holds tan(a) <= mu / (sqrt 2 max(|cos|, |sin|))
    mu = 0.7

    def excess(a):
        s45 = math.sin(math.radians(45.0))
        cos_phi = s45 / math.hypot(math.sin(a) * s45, math.cos(a))
        worst = max(cos_phi, math.sqrt(1 - cos_phi**2))
        return math.tan(a) - mu / (math.sqrt(2) * worst)

    low, high = math.radians(20.0), math.radians(40.0)
    for _ in range(60):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if excess(middle) < 0 else (low, middle)
    assert math.degrees(low) == pytest.approx(32.88, abs=0.01)


# ------------------------------------------------------------------ options and back-ends
def test_a_back_end_without_cones_refuses_the_cone_in_one_line(monkeypatch):
    # every bundled back-end takes cones; one that did not (a plug-in of linear rows only) is
    # refused by the options, and by itself on an assembled cone problem, rather than drop
    # friction's limit
    from shapegen.statics.solvers.reduced import ReducedBackend

    monkeypatch.setattr(ReducedBackend, "second_order_cones", False)  # as it would declare
    with pytest.raises(OptionError) as caught:
        StaticsOptions(pyramid="cone", solver="reduced")
    message = str(caught.value)
    assert "\n" not in message
    assert "pyramid 'cone' needs solver auto, clarabel or cvxpy" in message
    assert StaticsOptions(pyramid="cone").backends() == ("clarabel",)
    model = block_on_slope(20.0, 0.0, 0.7)
    problem = assemble(model, find_interfaces_of(model), pyramid="cone")
    with pytest.raises(StaticsError, match="takes only the friction pyramids"):
        ReducedBackend().refuse_unsupported(problem)


def find_interfaces_of(model):
    from shapegen.statics import find_interfaces

    return find_interfaces(model)


def test_auto_picks_the_reduced_back_end_for_the_cone_too():
    assert StaticsOptions(pyramid="cone").backends() == ("reduced", "clarabel")
    assert StaticsOptions(pyramid="4").backends() == ("reduced", "clarabel")
    result = analyze(block_on_slope(20.0, 0.0, 0.7), pyramid="cone")
    assert result.solver == "reduced"
    report = result.to_report()
    assert report["pyramid"] == "cone" and report["friction"] == pytest.approx(0.7)


def test_the_cone_has_no_linear_friction_rows():
    np.testing.assert_array_equal(friction_cone("cone", 0.7), [[-1.0, 0.0, 0.0]])


# ------------------------------------------------------------------ optimality conditions
def tilted_block(angle: float, friction: float, height: float = 0.2):
    """A block 2 x ``height`` x 2 m on the ground with gravity tilted by ``angle`` along +x."""
    a = math.radians(angle)
    model = Model(
        [Block.box((0, 0, 0), (2, height, 2))],
        gravity=(G * math.sin(a), -G * math.cos(a), 0.0),
        friction=friction,
    )
    return model, [horizontal_interface(0, GROUND, 0.0, (0, 2), (0, 2), up=False)]


def cone_kkt_violation(problem, solution):
    """Largest violation of the optimality conditions of the scaled second-order cone program.

    Constraints per vertex: ``(mu c, u, t)`` in the cone Q = {z0 >= ||(z1, z2)||}, ``c >= 0``,
    ``s >= 0``. With ``g`` the gradient of ``objective + lam . (A x + w)``, stationarity asks
    ``g_(c, u, t) = (mu z0 + y, z1, z2)`` for a cone dual ``z`` in Q (Q is self-dual) and
    ``y >= 0``, and ``g_s = y_s >= 0``; complementarity ``z . (mu c, u, t) = 0``, ``y c = 0``,
    ``y_s s = 0``. Where ``c > 0``, ``y = 0`` and ``z0 = g_c / mu``.
    """
    m = problem.n_vertices
    mu = problem.friction
    x, lam = solution.x, solution.multipliers
    c, s, u, t = x.reshape(4, m)
    primal = max(
        float(np.abs(problem.residual(x)).max()),
        float(np.max(np.hypot(u, t) - mu * c)),
        float(max(0.0, -c.min(), -s.min())),
    )
    g = (problem.quadratic * x + problem.linear + problem.equality.T @ lam).reshape(4, m)
    z0, z1, z2 = g[0] / mu, g[2], g[3]
    dual = max(float(np.max(np.hypot(z1, z2) - z0)), float(max(0.0, -g[1].min())))
    complementarity = max(
        float(np.abs(z0 * mu * c + z1 * u + z2 * t).max()), float(np.abs(g[1] * s).max())
    )
    return primal, dual, complementarity


CONE_CASES = {
    "holding": lambda: tilted_block(20.0, 0.7),  # tan 20 deg < 0.7: stands
    "sliding": lambda: tilted_block(40.0, 0.7),  # tan 40 deg > 0.7: needs tension
    "sliding_tall": lambda: tilted_block(40.0, 0.7, height=1.0),
}


@pytest.mark.parametrize("backend", CONE_BACKENDS)
@pytest.mark.parametrize("case", list(CONE_CASES))
def test_cone_optimality_conditions(backend, case):
    model, interfaces = CONE_CASES[case]()
    problem = assemble(model, interfaces, pyramid="cone")
    assert_solved_within(backend, problem, cone_kkt_violation, (1e-7, 1e-5, 1e-6))


@pytest.mark.parametrize("backend", CONE_BACKENDS)
def test_a_cone_without_friction_holds_no_tangential_load(backend):
    # mu = 0 closes the cone to the normal: no friction at all, so a tilted weight has no
    # equilibrium even with tension, while the upright block still stands on c >= 0
    model, interfaces = tilted_block(10.0, 0.0)
    solution = get_backend(backend).solve(assemble(model, interfaces, pyramid="cone"))
    assert solution.status is SolveStatus.INFEASIBLE
    model, interfaces = tilted_block(0.0, 0.0)
    upright = analyze(model, interfaces=interfaces, check=False, pyramid="cone", solver=backend)
    assert upright.feasible


@pytest.mark.parametrize("case", list(CONE_CASES))
def test_cone_back_ends_agree(case):
    model, interfaces = CONE_CASES[case]()
    values = []
    for name in CONE_BACKENDS:
        problem = assemble(model, interfaces, pyramid="cone")
        solution = get_backend(name).solve(problem)
        m = problem.n_vertices
        values.append(float(np.sum(solution.x[m : 2 * m] ** 2)))
    assert values == pytest.approx([values[0]] * len(values), rel=1e-5, abs=1e-9)


@pytest.mark.parametrize("height", [0.2, 1.0])
@pytest.mark.parametrize(
    "pyramid, capacity",
    [("cone", 1.0), ("4r", 1.0), ("4", 1 / math.sqrt(2)), ("8", math.cos(math.pi / 8))],
)
def test_sliding_block_closed_form(pyramid, capacity, height):
    # Weight W on a slope alpha steeper than the friction allows: normal part N = W cos(alpha),
    # tangential part T = W sin(alpha). With friction capacity mu' c along the slope per vertex,
    # the compressions must total T / mu', so the tensions total S = T / mu' - N; four equal
    # tensions are the least sum of squares for that total, and the compressions alone balance
    # the moment: y / W^2 = (sin(alpha) / mu' - cos(alpha))^2 / 4. Along a tangent axis the cone
    # and the turned square both give mu' = mu; the square with a side facing the slope
    # mu / sqrt 2, the octagon mu cos(pi / 8).
    model, interfaces = tilted_block(40.0, 0.7, height)
    a = math.radians(40.0)
    expected = (math.sin(a) / (0.7 * capacity) - math.cos(a)) ** 2 / 4
    result = analyze(model, interfaces=interfaces, check=False, pyramid=pyramid)
    assert not result.feasible
    assert result.infeasibility_normalized == pytest.approx(expected, rel=1e-6)


# ------------------------------------------------------------------ certificate and adjoint
def test_the_certificate_projects_friction_into_the_circle_not_a_pyramid():
    # at 33 deg on the slab (mu 0.7, heading 0) only the cone holds the block; its phase-one
    # forces certify under the cone and fail once projected into the 4-sided pyramid
    model = block_on_slope(33.0, 0.0, 0.7)
    interfaces = find_interfaces_of(model)
    result = analyze(model, interfaces=interfaces, pyramid="cone")
    assert result.feasible
    x = (result.forces / result.problem.weight).T.ravel()
    assert certify(result.problem, x) <= 1e-7
    pyramid = assemble(model, interfaces, pyramid="4")
    assert certify(pyramid, x) > 1e-3


@pytest.mark.parametrize("pyramid", ["cone", "4"])
def test_the_adjoint_holds_with_the_cone(pyramid):
    # a tall block (tips past atan(1 / 1) = 45 deg) sliding at 38 deg: y changes with the slope
    options = StaticsOptions(pyramid=pyramid, friction=0.7)
    slope, step = 38.0, 1e-3

    def model(angle):
        return block_on_slope(angle, 20.0, 0.7, height=1.0)

    base = analyze(model(slope), options)
    assert not base.feasible and base.multipliers is not None
    change = infeasibility_change(base, model(slope + step), options)
    assert change is not None
    above = analyze(model(slope + step), options).infeasibility_normalized
    below = analyze(model(slope - step), options).infeasibility_normalized
    central = (above - below) / 2
    assert change == pytest.approx(central, rel=2e-3)


# ------------------------------------------------------------------ the command line
@pytest.mark.parametrize("heading", [0.0, 45.0])
def test_the_command_line_takes_the_cone_and_reports_it(tmp_path, capsys, heading):
    from shapegen.cli import main
    from shapegen.export.blocks_json import write_blocks_json

    model_path, report_path = tmp_path / "slope.json", tmp_path / "report.json"
    write_blocks_json(block_on_slope(33.0, heading, 0.7), model_path)
    assert (
        main(["analyze", str(model_path), "--pyramid", "cone", "--report", str(report_path)]) == 0
    )
    report = json.loads(report_path.read_text())
    assert report["stands"] is True and report["pyramid"] == "cone"
    assert report["solver"] == "reduced"
    for solver in ("reduced", "clarabel"):
        args = ["analyze", str(model_path), "--pyramid", "cone", "--solver", solver]
        assert main([*args, "--report", str(report_path)]) == 0
        report = json.loads(report_path.read_text())
        assert report["stands"] is True and report["solver"] == solver
