"""analyze(): verdicts against mechanics (closed forms), report, options, scale independence."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from analysis_report import ANALYSIS_REPORT_KEYS
from statics_cases import horizontal_interface, polygon_interface

from shapegen.errors import OptionError
from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad
from shapegen.statics import GROUND, SolveStatus, analyze

SOLVERS = ["auto", "reduced", "clarabel", "cvxpy"]
G = 9.81


def overhang(offset, scale=1.0):
    """A unit block on a fixed unit support, shifted by ``offset`` along x (lengths * scale)."""
    s = scale
    model = Model(
        [
            Block.box((0, 0, 0), (s, s, s), fixed=True),
            Block.box((offset * s, s, 0), ((offset + 1) * s, 2 * s, s)),
        ]
    )
    contact = horizontal_interface(0, 1, s, (offset * s, s), (0, s), up=True)
    return model, [contact]


def hanging(scale=1.0):
    s = scale
    model = Model(
        [Block.box((0, -s, 0), (s, 0, s)), Block.box((-s, 0, -s), (2 * s, s, 2 * s), fixed=True)],
        ground=None,
    )
    return model, [horizontal_interface(0, 1, 0.0, (0, s), (0, s), up=True)]


def run(model, interfaces, **options):
    return analyze(model, interfaces=interfaces, check=False, **options)


@pytest.mark.parametrize("solver", SOLVERS)
def test_box_on_the_ground_stands_on_its_centroid(solver):
    model = Model([Block.box((0, 0, 0), (1, 1, 2))])
    interfaces = [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 2), up=False)]
    result = run(model, interfaces, solver=solver)
    weight = model.blocks[0].mass * G
    assert result.status is SolveStatus.OPTIMAL
    assert result.feasible
    assert result.infeasibility_normalized < 1e-9
    assert result.total_weight == pytest.approx(weight)
    # the force on the ground (second) is the weight, through the centroid's projection
    np.testing.assert_allclose(result.resultant_forces[0], (0, -weight, 0), atol=1e-6 * weight)
    np.testing.assert_allclose(result.resultant_points[0], (0.5, 0, 1), atol=1e-6)


def test_box_on_the_ground_through_the_contact_search():
    model = Model([Block.box((0, 0, 0), (1, 1, 2)), Block.box((0, 1, 0), (1, 2, 2))])
    result = analyze(model)
    assert result.feasible
    assert len(result.interfaces) == 2


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize(
    "offset, kern, stands",
    [
        (0.45, 1.0, True),  # centroid at 0.95 over the support [0, 1]
        (0.55, 1.0, False),  # centroid at 1.05 beyond the edge
        (0.24, 1 / 3, True),  # middle third of [0.24, 1] ends at 0.7467 > centroid 0.74
        (0.26, 1 / 3, False),  # middle third of [0.26, 1] ends at 0.7533 < centroid 0.76
    ],
)
def test_overhang_stands_iff_centroid_over_the_contact(solver, offset, kern, stands):
    model, interfaces = overhang(offset)
    result = run(model, interfaces, solver=solver, kern=kern)
    assert result.status is SolveStatus.OPTIMAL
    assert result.feasible is stands
    assert (result.infeasibility_normalized > 1e-6) is not stands


@pytest.mark.parametrize("solver", SOLVERS)
def test_hanging_block_needs_its_weight_in_tension(solver):
    model, interfaces = hanging()
    result = run(model, interfaces, solver=solver)
    weight = model.total_weight
    # four vertices share the weight equally: y = 4 (W/4)^2 = W^2 / 4
    assert not result.feasible
    assert result.infeasibility == pytest.approx(weight**2 / 4, rel=1e-6)
    assert result.infeasibility_normalized == pytest.approx(0.25, rel=1e-6)
    assert result.max_tension == pytest.approx(weight / 4, rel=1e-5)
    assert result.interface_tension[0] == pytest.approx(weight, rel=1e-5)
    np.testing.assert_allclose(result.block_tension, (weight, 0.0), rtol=1e-5)


@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_scale_independence(scale):
    model, interfaces = hanging(scale)
    assert run(model, interfaces).infeasibility_normalized == pytest.approx(0.25, rel=1e-6)
    for offset, stands in ((0.45, True), (0.55, False), (0.499, True), (0.501, False)):
        model, interfaces = overhang(offset, scale)
        result = run(model, interfaces)
        assert result.feasible is stands, (scale, offset)


@pytest.mark.parametrize(
    "pyramid, limit", [("4", 0.7 / math.sqrt(2)), ("4r", 0.7), ("8", 0.7 * math.cos(math.pi / 8))]
)
@pytest.mark.parametrize("factor, stands", [(0.99, True), (1.01, False)])
def test_sliding_past_the_pyramid_limit(pyramid, limit, factor, stands):
    # gravity tilted along +x is a tilted support; x is a tangent direction of the ground joint,
    # so the limit is the pyramid's capacity along an axis. A squat block cannot tip first.
    angle = math.atan(limit) * factor
    model = Model(
        [Block.box((0, 0, 0), (2, 0.2, 2))],
        gravity=(G * math.sin(angle), -G * math.cos(angle), 0),
    )
    interfaces = [horizontal_interface(0, GROUND, 0.0, (0, 2), (0, 2), up=False)]
    result = run(model, interfaces, pyramid=pyramid)
    # sliding costs tension (compression paired with tension buys friction): optimal, y > 0
    assert result.status is SolveStatus.OPTIMAL
    assert result.feasible is stands


def test_no_friction_and_a_tangential_load_has_no_equilibrium():
    model = Model([Block.box((0, 0, 0), (1, 1, 1))], gravity=(1.0, -G, 0), friction=0.0)
    interfaces = [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)]
    result = run(model, interfaces)
    assert result.status is SolveStatus.INFEASIBLE
    assert not result.feasible
    assert result.infeasibility == math.inf
    assert result.to_report()["infeasibility"] is None


@pytest.mark.parametrize("solver", SOLVERS)
@pytest.mark.parametrize("push, stands", [(0.24, True), (0.26, False)])
def test_point_load_tips_a_tall_box(solver, push, stands):
    # unit-wide box 2 high; a horizontal push P at the top tips it about the far edge when
    # 2 P > W / 2, i.e. P > W / 4 (friction 2 so that it cannot slide first)
    model = Model([Block.box((0, 0, 0), (1, 2, 1), id="box")], friction=2.0)
    weight = model.total_weight
    model.loads = [PointLoad("box", (push * weight, 0, 0), (0.5, 2.0, 0.5))]
    interfaces = [horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False)]
    result = run(model, interfaces, solver=solver)
    assert result.feasible is stands
    if stands:
        # moment balance about the centroid's foot: x = 0.5 + 2 P / W
        assert result.resultant_points[0][0] == pytest.approx(0.5 + 2 * push, abs=1e-6)


def test_report_is_json_ready_with_the_required_keys():
    model, interfaces = overhang(0.2)
    report = run(model, interfaces).to_report()
    json.dumps(report)
    assert ANALYSIS_REPORT_KEYS <= set(report), ANALYSIS_REPORT_KEYS - set(report)
    assert report["blocks"] == 2 and report["interfaces"] == 1 and report["feasible"] is True
    assert set(report["timings"]) == {"interfaces", "assembly", "solve", "certify"}


@pytest.mark.parametrize(
    "options, message",
    [
        ({"pyramid": "3"}, "pyramid must be one of cone, 4, 4r, 8"),
        ({"solver": "gurobi"}, "solver must be one of auto, reduced, clarabel, cvxpy"),
        ({"kern": 2.0}, "kern must be a number in"),
        ({"kern": "a"}, "kern must be a number in"),
        ({"friction": float("nan")}, "friction must be a finite number"),
    ],
)
def test_bad_options_raise_option_error(options, message):
    model, interfaces = overhang(0.2)
    with pytest.raises(OptionError, match=message):
        run(model, interfaces, **options)


def test_non_structural_blocks_are_left_out():
    model = Model(
        [Block.box((0, 0, 0), (1, 1, 1)), Block.box((0.9, 1, 0), (1.9, 2, 1), structural=False)]
    )
    interfaces = [
        horizontal_interface(0, GROUND, 0.0, (0, 1), (0, 1), up=False),
        horizontal_interface(0, 1, 1.0, (0.9, 1), (0, 1), up=True),
    ]
    result = run(model, interfaces)
    assert result.feasible
    assert result.total_weight == pytest.approx(model.blocks[0].mass * G)
    assert len(result.interfaces) == 1


def arch(n, ratio):
    """Semicircular arch of ``n`` voussoirs with radial joints, centreline radius 1, on the
    ground; returned with hand-built joints."""
    inner, outer = 1 - ratio / 2, 1 + ratio / 2
    angles = np.linspace(np.pi, 0, n + 1)
    blocks, interfaces = [], []
    for k in range(n):
        ring = [
            (r * math.cos(a), r * math.sin(a)) for a in angles[k : k + 2] for r in (inner, outer)
        ]
        blocks.append(Block.from_hull([(x, y, z) for x, y in ring for z in (0.0, ratio)]))
    for k in range(n + 1):
        a = angles[k]
        corners = [
            (r * math.cos(a), r * math.sin(a), z) for r in (inner, outer) for z in (0, ratio)
        ]
        normal = (math.sin(a), -math.cos(a), 0.0)  # from voussoir k-1 towards voussoir k
        if k == 0:
            interfaces.append(polygon_interface(0, GROUND, (0, -1, 0), corners))
        elif k == n:
            interfaces.append(polygon_interface(n - 1, GROUND, (0, -1, 0), corners))
        else:
            interfaces.append(polygon_interface(k - 1, k, normal, corners))
    return Model(blocks, friction=2.0), interfaces


@pytest.mark.parametrize("ratio, stands", [(0.1075 * 0.995, False), (0.1075 * 1.005, True)])
def test_arch_minimum_thickness_is_resolved(ratio, stands):
    # Milankovitch: a semicircular arch needs t/R >= 0.1075 (100 voussoirs: 0.10746)
    model, interfaces = arch(100, ratio)
    assert run(model, interfaces).feasible is stands


def test_a_block_without_contacts_has_no_equilibrium():
    model = Model([Block.box((0, 1, 0), (1, 2, 1))])
    result = run(model, [])
    assert result.status is SolveStatus.INFEASIBLE
    assert not result.feasible and result.infeasibility == math.inf


def test_an_empty_model_stands():
    result = run(Model([]), [])
    assert result.feasible and result.infeasibility == 0.0 and result.total_weight == 0.0


@pytest.mark.parametrize("solver", SOLVERS)
def test_block_wedged_between_fixed_supports_hangs_by_friction(solver):
    # only vertical joints: friction carries the weight, and any squeeze is a self-stress (the
    # optimal set is unbounded without the solver's tiny regularisation); the two friction
    # resultants must each carry half the weight
    model = Model(
        [
            Block.box((-1, 0, 0), (0, 2, 1), fixed=True),
            Block.box((0, 0.5, 0), (1, 1.5, 1)),
            Block.box((1, 0, 0), (2, 2, 1), fixed=True),
        ],
        ground=None,
    )
    joints = [
        polygon_interface(
            1, side, (normal, 0, 0), [(x, 0.5, 0), (x, 1.5, 0), (x, 1.5, 1), (x, 0.5, 1)]
        )
        for side, normal, x in ((0, -1, 0.0), (2, 1, 1.0))
    ]
    result = run(model, joints, solver=solver)
    weight = model.total_weight
    assert result.feasible
    np.testing.assert_allclose(result.resultant_forces[:, 1], -weight / 2, rtol=1e-6)
    np.testing.assert_allclose(
        result.resultant_forces.sum(axis=0), (0, -weight, 0), atol=1e-6 * weight
    )
