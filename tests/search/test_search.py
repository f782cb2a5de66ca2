"""The search over free attrs, for block statics and for the cable model of the bridge.

Block statics: designs whose standing region is known in closed form. The two-block stack is a
bottom block of width 0.5 + base under a unit top block shifted right by 0.3 - shift. The top
block's centroid is at x = 0.8 - shift and the stack stands iff that lies over the bottom block:
base + shift >= 0.3.

Cables: rules/suspension_bridge.grammar, whose free attrs main_span and sag are judged by the
cable model from the start rule's @Structure("cable", ...) arguments; a design stands iff its
governing cable diameter is at most (1 - margin) max_cable_diameter.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.errors import GrammarError, OptionError
from shapegen.search import (
    DEFAULT_MARGIN,
    GRADIENTS,
    DesignSession,
    Evaluator,
    RangeWarning,
    energy_landscape,
    optimize,
    select_parameters,
)
from shapegen.statics import StaticsOptions, analyze
from shapegen.structures import Design, make_structure
from shapegen.structures.cable import CableModel

STACK = (Path(__file__).parents[1] / "data" / "rules" / "stack.grammar").read_text()

REPORT_KEYS = {
    "structure",
    "measure",
    "converged",
    "feasible",
    "iterations",
    "evaluations",
    "seconds",
    "seconds_per_iteration",
    "initial_infeasibility",
    "final_infeasibility",
    "objective",
    "method",
    "gradient",
    "message",
    "margin",
    "parameters",
    "fixed",
}

# Block statics solved by clarabel: the back-end plays no part in what a search finds, and on
# two blocks clarabel is the quickest, which keeps the long searches (closest) short.
CLARABEL = StaticsOptions(solver="clarabel")

# The Golden Gate defaults with a thinner cable: the default design (main span 1280 m, sag 152 m,
# 0.917 m) does not stand and the search has something to do.
THIN = {"max_cable_diameter": 0.8}


@pytest.fixture(scope="module")
def stack():
    return parse_grammar(STACK)


@pytest.fixture(scope="module")
def bridge():
    return load_grammar("suspension_bridge.grammar")


def cable_diameter(result) -> float:
    return result.assessment.section["cable_diameter"]


def assert_same_blocks(first, second):
    assert len(first.blocks) == len(second.blocks)
    for a, b in zip(first.blocks, second.blocks, strict=True):
        assert a.tags == b.tags
        np.testing.assert_allclose(a.vertices, b.vertices, rtol=0, atol=1e-9)


# ---------------------------------------------------------------------- block statics
@pytest.mark.parametrize("base", [0.05, 0.15, 0.25])
def test_adjoint_gradient_matches_central_differences(stack, base):
    parameters, attrs = select_parameters(stack, free=["base", "shift"])
    evaluator = Evaluator(stack, make_structure("blocks"), parameters, attrs)
    theta = np.array([base, 0.02])
    adjoint = evaluator.gradient(theta, "adjoint")
    # The adjoint judged one design; no parameter fell back to a whole evaluation.
    assert evaluator.evaluations == 1
    forward = evaluator.gradient(theta, "forward")
    assert evaluator.evaluations == 1 + 2  # one more design per parameter
    h = 1e-5
    central = []
    for j in range(2):
        step = np.zeros(2)
        step[j] = h
        central.append(
            (evaluator.evaluate(theta + step).infeasibility
             - evaluator.evaluate(theta - step).infeasibility) / (2 * h)
        )  # fmt: skip
    np.testing.assert_allclose(adjoint, central, rtol=1e-3)
    np.testing.assert_allclose(forward, central, rtol=1e-2)
    assert np.all(adjoint < 0)  # widening the base or shifting the top back both help


def test_the_default_gradient_is_the_structures_best(stack, bridge):
    assert optimize(stack).gradient == "adjoint"
    assert optimize(bridge, attrs=THIN, build=False).gradient == "none"


@pytest.mark.parametrize("gradient", GRADIENTS)
def test_energy_search_reaches_a_feasible_design_within_bounds(stack, gradient):
    result = optimize(stack, gradient=gradient)
    assert result.feasible and result.converged
    assert result.gradient == gradient
    assert result.method == ("Powell" if gradient == "none" else "SLSQP")
    assert result.structure == "blocks" and result.measure == "y/W²"
    # By default the design stands with a reserve: with its joint shrunk to k = 0.9 of its size,
    # which needs base >= (0.8 - 0.2 k) / (1 + k) (see the margin test below), not only 0.3.
    assert result.margin == DEFAULT_MARGIN == 0.1
    k = 1 - DEFAULT_MARGIN
    base = result.values["base"]
    assert (0.8 - 0.2 * k) / (1 + k) - 1e-4 <= base <= 0.6
    assert result.initial_infeasibility > 0 and result.final_infeasibility <= 1e-4
    assert result.evaluations > 0
    assert result.model is not None and result.analysis.feasible
    assert result.assessment.stands and result.assessment.margin == 0.0  # judged without it
    report = result.to_report()
    assert set(report) == REPORT_KEYS
    assert report["evaluations"] == result.evaluations
    assert report["parameters"]["base"] == {"initial": 0.1, "final": base, "min": 0.0, "max": 0.6}


def test_statics_options_reach_the_search_through_the_structure(stack):
    # The options the block structure is made with judge every design of the search: joints
    # shrunk to k of their size (see the margin test below for the boundary), solved by the
    # back-end asked for.
    k = 0.9
    shrunk = make_structure("blocks", StaticsOptions(kern=k, solver="clarabel"))
    result = optimize(stack, structure=shrunk, objective="closest", margin=0)
    assert result.feasible and result.margin == 0.0
    assert result.values["base"] == pytest.approx((0.8 - 0.2 * k) / (1 + k), abs=2e-3)
    assert result.analysis.to_report()["solver"] == "clarabel"


def test_closest_objective_finds_the_projection_onto_the_feasible_boundary(stack):
    # From (0.1, 0) the nearest point of base + shift >= 0.3 (equal ranges) is (0.2, 0.1).
    structure = make_structure("blocks", CLARABEL)
    result = optimize(
        stack, structure=structure, free=["base", "shift"], objective="closest", margin=0
    )
    assert result.feasible
    assert result.values["base"] == pytest.approx(0.2, abs=0.01)
    assert result.values["shift"] == pytest.approx(0.1, abs=0.01)


def test_a_feasible_start_needs_no_iteration(stack):
    result = optimize(stack, attrs={"base": 0.5})
    assert result.feasible and result.iterations == 0
    assert result.values["base"] == 0.5
    assert result.evaluations == 1


def test_fix_pins_an_attr_and_free_chooses_parameters(stack):
    result = optimize(stack, free=["shift"], fix={"base": 0.0})
    assert result.feasible
    assert list(result.parameters) == ["shift"]
    assert result.values["shift"] >= 0.3 - 1e-6
    assert result.fixed == {"base": 0.0}


def test_result_attrs_rebuild_the_result_model(stack):
    result = optimize(stack, free=["shift"], fix={"base": 0.0}, attrs={"overhang": 0.35})
    assert result.attrs == {"overhang": 0.35, "base": 0.0, "shift": result.values["shift"]}
    assert_same_blocks(stack.build(attrs=result.attrs), result.model)


@pytest.mark.parametrize(
    ("free", "message"),
    [(["bsae"], "did you mean 'base'"), (["overhang"], "has no @Range")],
)
def test_bad_parameter_choices_are_reported(stack, free, message):
    with pytest.raises(GrammarError, match=message):
        optimize(stack, free=free)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"objective": "nearest"}, "objective must be one of energy, closest"),
        ({"gradient": "backward"}, "gradient must be one of adjoint, forward, none"),
        ({"max_iter": 0}, "max_iter must be at least 1"),
        ({"multistart": -1}, "multistart must be at least 0"),
        ({"margin": 1.0}, "margin must be at least 0 and below 1"),
        ({"margin": -0.1}, "margin must be at least 0 and below 1"),
    ],
)
def test_bad_options_are_option_errors(stack, options, message):
    with pytest.raises(OptionError, match=message):
        optimize(stack, **options)


def test_failing_builds_are_stepped_around():
    # Beyond base = 0.45 the design cannot be built (the arch is thicker than its radius).
    grammar = parse_grammar(STACK.replace(
        "Bottom --> s(base + 0.5, '1, '1) Stone",
        'Bottom --> s(base + 0.5, \'1, \'1) Piece\n'
        'Piece --> case base > 0.45 : i("arch", thickness=100) else : Stone',
    ))  # fmt: skip
    result = optimize(grammar)
    assert result.feasible
    assert 0.3 - 1e-6 <= result.values["base"] <= 0.45


def test_multistart_is_deterministic_per_seed(stack):
    a = optimize(stack, free=["base", "shift"], multistart=2, seed=7, max_iter=1)
    b = optimize(stack, free=["base", "shift"], multistart=2, seed=7, max_iter=1)
    assert a.values == b.values and a.evaluations == b.evaluations
    assert all(math.isfinite(v) for v in a.values.values())


def test_arch_columns_example_needs_tension_and_optimizes_to_a_standing_design():
    grammar = load_grammar("arch_columns.grammar")  # the bundled rule file
    initial = analyze(grammar.build())
    assert not initial.feasible and initial.infeasibility > 0
    result = optimize(grammar)
    assert result.feasible
    again = analyze(grammar.build(attrs=result.attrs))  # the reported values really stand
    assert again.feasible
    for name, spec in result.parameters.items():
        assert spec["min"] <= spec["final"] <= spec["max"], name


def test_landscape_marks_the_feasible_region(stack):
    landscape = energy_landscape(stack, "base", "shift", grid=5)
    assert landscape.measure == "y/W²"
    base, shift = np.meshgrid(landscape.first, landscape.second)
    expected = base + shift >= 0.3 + 1e-9
    clearly = np.abs(base + shift - 0.3) > 1e-6  # leave points exactly on the boundary alone
    np.testing.assert_array_equal(landscape.feasible[clearly], expected[clearly])
    # on the boundary y is 0 (up to the solver's noise): only the points clearly outside need
    # tension
    assert np.all(landscape.infeasibility[~expected & clearly] > 0)
    assert landscape.evaluations == 25


def test_margin_finds_the_boundary_of_the_shrunk_joints(stack):
    # The joint spans x in [0.3, 0.5 + base]; shrunk about its middle to k of its length, it
    # still reaches the top block's centroid (x = 0.8) iff base >= (0.8 - 0.2 k) / (1 + k).
    k = 0.9
    structure = make_structure("blocks", CLARABEL)
    result = optimize(stack, structure=structure, objective="closest", margin=1 - k)
    assert result.feasible and result.analysis.feasible
    assert result.margin == pytest.approx(1 - k)
    assert result.assessment.margin == 0.0  # the returned verdict is without margin
    assert result.values["base"] == pytest.approx((0.8 - 0.2 * k) / (1 + k), abs=2e-3)
    plain = optimize(stack, structure=structure, objective="closest", margin=0)
    assert plain.values["base"] == pytest.approx(0.3, abs=2e-3)
    assert "(margin 0: no reserve)" in plain.message
    default = optimize(stack, structure=structure, objective="closest")  # a 10% reserve
    assert default.margin == 0.1 and default.values == pytest.approx(result.values, abs=1e-6)
    assert "with a 10% margin" in default.message


def test_design_session_warm_starts_from_the_last_solution(stack):
    session = DesignSession(stack, free=["base"])
    first = session.optimize()
    assert first.feasible and first.structure == "blocks"
    session.set(overhang=0.35)  # the top block moves out: the last solution no longer stands
    second = session.optimize()
    assert second.parameters["base"]["initial"] == first.values["base"]
    assert second.feasible and second.values["base"] >= 0.35 - 1e-6
    assert session.last is second and session.solution == second.values


# ---------------------------------------------------------------------- the cable structure
def test_the_adjoint_gradient_is_refused_for_the_cable_structure(bridge):
    with pytest.raises(OptionError, match="gives no gradient"):
        optimize(bridge, gradient="adjoint")
    with pytest.raises(OptionError, match="gives no gradient"):
        DesignSession(bridge, gradient="adjoint").optimize()


@pytest.mark.parametrize(("gradient", "method"), [("forward", "SLSQP"), ("none", "Powell")])
def test_cable_search_with_and_without_a_gradient(bridge, gradient, method):
    result = optimize(bridge, attrs=THIN, gradient=gradient)
    assert result.feasible and result.converged
    assert (result.method, result.gradient, result.structure) == (method, gradient, "cable")
    assert result.measure == CableModel.measure_name
    assert result.initial_infeasibility > 0 and result.final_infeasibility == 0.0
    assert result.analysis is None  # no block analysis for a cable design
    assert result.assessment.structure == "cable" and result.assessment.stands
    assert cable_diameter(result) <= 0.8
    span, sag = result.values["main_span"], result.values["sag"]
    assert 1280 <= span <= 1966 and 0 < sag < span / 2
    assert set(result.to_report()) == REPORT_KEYS


@pytest.mark.parametrize("gradient", ["forward", "none"])
def test_cable_margin_lowers_the_diameter_limit(bridge, gradient):
    margin = 0.1
    result = optimize(bridge, attrs=THIN, gradient=gradient, margin=margin, build=False)
    assert result.feasible and result.margin == margin
    assert cable_diameter(result) <= (1 - margin) * 0.8
    # The assessment returned is judged without margin: against the whole limit.
    assessment = result.assessment
    assert assessment.margin == 0.0 and assessment.stands and assessment.measure == 0.0
    assert assessment.section["allowed_diameter"] == assessment.section["max_cable_diameter"]
    assert assessment.section["max_cable_diameter"] == 0.8


def test_closest_objective_for_the_bridge(bridge):
    # With the span at its lower bound already, the nearest standing design deepens the sag
    # only as far as the cable needs: it ends on the boundary d = max_cable_diameter.
    result = optimize(bridge, attrs=THIN, objective="closest", build=False, margin=0)
    assert result.feasible and result.objective == "closest"
    assert result.values["main_span"] == pytest.approx(1280.0, abs=1.0)
    assert 152 < result.values["sag"] < 1280 / 2
    assert cable_diameter(result) == pytest.approx(0.8, rel=1e-3)
    assert cable_diameter(result) <= 0.8
    energy = optimize(bridge, attrs=THIN, build=False, margin=0)
    start = np.array([1280.0, 152.0])
    span = np.array([1966.0 - 1280.0, 983.0 - 1.0])

    def distance(values):
        return np.linalg.norm((np.array([values["main_span"], values["sag"]]) - start) / span)

    assert distance(result.values) <= distance(energy.values) + 1e-9


def test_cable_landscape_values_are_the_cable_measure(bridge):
    landscape = energy_landscape(bridge, "main_span", "sag", grid=4, attrs=THIN)
    assert landscape.measure == CableModel.measure_name
    np.testing.assert_allclose(landscape.first, np.linspace(1280, 1966, 4))
    np.testing.assert_allclose(landscape.second, np.linspace(1, 983, 4))
    judged = np.isfinite(landscape.infeasibility)
    assert landscape.evaluations == judged.sum()
    # sag >= main_span / 2 cannot be sized: not judged.
    spans, sags = np.meshgrid(landscape.first, landscape.second)
    np.testing.assert_array_equal(judged, sags < spans / 2)
    np.testing.assert_array_equal(
        landscape.feasible, judged & (np.nan_to_num(landscape.infeasibility, nan=1) == 0)
    )
    assert landscape.feasible.any() and (judged & ~landscape.feasible).any()
    i, j = 1, 2  # sag 328.3 m, main span 1737.3 m: too thick a cable, a positive measure
    arguments = bridge.structure_arguments(
        {**THIN, "main_span": landscape.first[j], "sag": landscape.second[i]}
    )
    expected = CableModel().assess(Design(arguments, build=lambda: pytest.fail("built")))
    assert not expected.stands and expected.measure > 0
    assert landscape.infeasibility[i, j] == expected.measure
    d = expected.section["cable_diameter"]
    assert expected.measure == pytest.approx((d / 0.8 - 1) ** 2, rel=1e-12)


def test_design_session_on_the_bridge(bridge):
    session = DesignSession(bridge, margin=0)  # 0.7 m cannot be met with a 10% reserve
    assert session.structure.name == "cable"
    session.set(**THIN)
    first = session.optimize()
    assert first.feasible and first.method == "Powell"
    assert cable_diameter(first) <= 0.8
    session.set(max_cable_diameter=0.7)
    second = session.optimize()
    for name in ("main_span", "sag"):
        assert second.parameters[name]["initial"] == first.values[name]
    assert second.feasible and cable_diameter(second) <= 0.7
    assert second.attrs["max_cable_diameter"] == 0.7


def test_bridge_result_attrs_hold_the_fixed_attrs_and_rebuild_the_model(bridge):
    result = optimize(bridge, attrs=THIN, fix={"lanes": 4.0})
    assert result.fixed == {"lanes": 4.0}
    assert result.attrs == {**THIN, "lanes": 4.0, **result.values}
    assert result.model.metadata["attrs"]["lanes"] == 4.0
    assert_same_blocks(bridge.build(attrs=result.attrs), result.model)
    # The model carries the arguments the cable model judged.
    recorded = result.model.metadata["structure"]
    assert recorded["name"] == "cable"
    assert recorded["arguments"] == bridge.structure_arguments(result.attrs)
    again = CableModel().assess(Design.of_model(result.model))
    assert again.section == result.assessment.section


def test_a_start_outside_its_range_is_warned_about_and_a_build_is_never_clamped(stack):
    with pytest.warns(RangeWarning, match=r"base = 0.8 is outside its @Range \[0, 0.6\]: the"):
        result = optimize(stack, attrs={"base": 0.8}, margin=0)
    assert result.parameters["base"]["initial"] == 0.6  # a search stays within the ranges
    assert stack.build(attrs={"base": 0.8}).metadata["attrs"]["base"] == 0.8  # a build does not


def test_every_search_entry_point_defaults_to_the_same_reserve(stack):
    from shapegen.search.search_options import SearchOptions
    from shapegen.simulation.settings import SIMULATION_MARGIN

    assert DEFAULT_MARGIN == 0.1
    assert SearchOptions().margin == DEFAULT_MARGIN == SIMULATION_MARGIN
    assert DesignSession(stack).options.margin == DEFAULT_MARGIN
    assert DesignSession(stack, margin=0).options == SearchOptions(margin=0)
