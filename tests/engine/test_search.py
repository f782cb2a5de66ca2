"""Parameter search on designs whose feasible region is known in closed form.

The two-block stack: a bottom block of width 0.5 + base under a unit top block shifted right by
0.3 - shift. The top block's centroid is at x = 0.8 - shift and the stack stands iff that lies over
the bottom block: base + shift >= 0.3.
"""

import math

import numpy as np
import pytest

from shapegen import load_grammar
from shapegen.engine.search import Evaluator, optimize, select_parameters
from shapegen.errors import GrammarError, StaticsError

STACK = """
attr overhang = 0.3
@Free @Range(0.0, 0.6)
attr base = 0.1
@Range(0.0, 0.6)
attr shift = 0.0
@StartRule @Lot(1, 1)
Lot --> extrude(2) split(y) { 1 : Bottom | 1 : Top }
Bottom --> s(base + 0.5, '1, '1) Stone
Top --> t(overhang - shift, 0, 0) Stone
"""


@pytest.fixture(scope="module")
def stack():
    return load_grammar(STACK)


@pytest.mark.parametrize("base", [0.05, 0.15, 0.25])
def test_adjoint_gradient_matches_central_differences(stack, base):
    parameters, attrs = select_parameters(stack, free=["base", "shift"])
    evaluator = Evaluator(stack, parameters, attrs)
    theta = np.array([base, 0.02])
    adjoint = evaluator.gradient(theta, "adjoint")
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
    assert np.all(adjoint < 0)  # widening the base or shifting the top back both help


@pytest.mark.parametrize("gradient", ["adjoint", "forward"])
def test_energy_search_reaches_a_feasible_design_within_bounds(stack, gradient):
    result = optimize(stack, gradient=gradient)
    assert result.feasible and result.converged
    base = result.values["base"]
    assert 0.3 - 1e-6 <= base <= 0.6
    assert result.initial_infeasibility > 0 and result.final_infeasibility <= 1e-4
    assert result.model is not None and result.analysis.feasible
    report = result.to_report()
    for key in (
        "converged",
        "feasible",
        "iterations",
        "qp_solves",
        "seconds",
        "seconds_per_iteration",
        "initial_infeasibility",
        "final_infeasibility",
    ):
        assert key in report
    assert report["parameters"]["base"] == {"initial": 0.1, "final": base, "min": 0.0, "max": 0.6}


def test_closest_objective_finds_the_projection_onto_the_feasible_boundary(stack):
    # From (0.1, 0) the nearest point of base + shift >= 0.3 (equal ranges) is (0.2, 0.1).
    result = optimize(stack, free=["base", "shift"], objective="closest")
    assert result.feasible
    assert result.values["base"] == pytest.approx(0.2, abs=0.01)
    assert result.values["shift"] == pytest.approx(0.1, abs=0.01)


def test_a_feasible_start_needs_no_iteration(stack):
    result = optimize(stack, attrs={"base": 0.5})
    assert result.feasible and result.iterations == 0
    assert result.values["base"] == 0.5


def test_fix_pins_an_attr_and_free_chooses_parameters(stack):
    result = optimize(stack, free=["shift"], fix={"base": 0.0})
    assert result.feasible
    assert list(result.parameters) == ["shift"]
    assert result.values["shift"] >= 0.3 - 1e-6


@pytest.mark.parametrize(
    ("free", "message"),
    [(["bsae"], "did you mean 'base'"), (["overhang"], "has no @Range")],
)
def test_bad_parameter_choices_are_reported(stack, free, message):
    with pytest.raises(GrammarError, match=message):
        optimize(stack, free=free)


def test_failing_builds_are_stepped_around():
    # Beyond base = 0.45 the design cannot be built (the arch is thicker than its radius).
    grammar = load_grammar(STACK.replace(
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
    assert a.values == b.values and a.qp_solves == b.qp_solves
    assert all(math.isfinite(v) for v in a.values.values())


def test_arch_columns_example_needs_tension_and_optimizes_to_a_standing_design():
    grammar = load_grammar("arch_columns.grammar")  # the bundled rule file
    from shapegen.statics import analyze

    initial = analyze(grammar.build())
    assert not initial.feasible and initial.infeasibility > 0
    result = optimize(grammar)
    assert result.feasible
    again = analyze(grammar.build(attrs=result.values))  # the reported values really stand
    assert again.feasible
    for name, spec in result.parameters.items():
        assert spec["min"] <= spec["final"] <= spec["max"], name


def test_landscape_marks_the_feasible_region(stack):
    from shapegen.engine.landscape import energy_landscape

    landscape = energy_landscape(stack, "base", "shift", grid=5)
    base, shift = np.meshgrid(landscape.first, landscape.second)
    expected = base + shift >= 0.3 + 1e-9
    clearly = np.abs(base + shift - 0.3) > 1e-6  # leave points exactly on the boundary alone
    np.testing.assert_array_equal(landscape.feasible[clearly], expected[clearly])
    assert np.all(landscape.infeasibility[~expected] > 0)


def test_margin_finds_the_boundary_of_the_shrunk_joints(stack):
    # The joint spans x in [0.3, 0.5 + base]; shrunk about its middle to k of its length, it
    # still reaches the top block's centroid (x = 0.8) iff base >= (0.8 - 0.2 k) / (1 + k).
    k = 0.9
    result = optimize(stack, objective="closest", margin=1 - k)
    assert result.feasible and result.analysis.feasible
    assert result.values["base"] == pytest.approx((0.8 - 0.2 * k) / (1 + k), abs=2e-3)
    plain = optimize(stack, objective="closest")
    assert plain.values["base"] == pytest.approx(0.3, abs=2e-3)
    with pytest.raises(StaticsError, match="margin"):
        optimize(stack, margin=1.0)
