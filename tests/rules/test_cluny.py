"""rules/cluny.grammar: a Romanesque nave after Cluny III (the seed paper's Figure 1, Table 1).

Checked here: the file loads with its two documented free-parameter sets; the model has the size
its attrs prescribe (closed-form extents of the vault crown, the nave's length and the church's
width) and about 1 000 blocks; it is a sound assembly (no interpenetrating blocks, every block
connected to the ground); with the file's values it needs tension; the search over the four
@Free attrs finds a design that stands, within the bounds.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from shapegen.search import optimize
from shapegen.statics import analyze, check_model, find_interfaces

CLUNY = Path(__file__).resolve().parents[2] / "rules" / "cluny.grammar"
GRAMMAR = CLUNY
FOUR = ["wall_thickness", "buttress_thickness", "window_width", "column_size"]
TEN_EXTRA = [
    "aisle_wall_thickness",
    "nave_vault_thickness",
    "aisle_vault_thickness",
    "flyer_thickness",
    "flyer_angle",
    "buttress_depth",
]


@pytest.fixture(scope="module")
def default_model(grammar):
    return grammar.build()


@pytest.fixture(scope="module")
def default_analysis(default_model):
    return analyze(default_model)


def test_the_four_free_attrs_are_the_papers_small_set(grammar):
    assert sorted(grammar.free_parameters) == sorted(FOUR)


def test_the_documented_ten_parameter_set_names_ranged_attrs(grammar):
    lines = re.findall(r"--free (\S+)", CLUNY.read_text())
    assert lines, "the header documents the --free line of the ten-parameter set"
    ten = lines[0].split(",")
    assert sorted(ten) == sorted(FOUR + TEN_EXTRA)
    ranges = grammar.parameter_ranges({})
    for name in ten:
        assert name in ranges, f"{name} needs a @Range to be a free parameter"
        low, value, high = ranges[name]["min"], ranges[name]["value"], ranges[name]["max"]
        assert low <= value <= high and low < high


def test_the_model_has_the_prescribed_size(grammar, default_model):
    a = grammar.attrs
    lows = np.min([b.vertices.min(axis=0) for b in default_model.blocks], axis=0)
    highs = np.max([b.vertices.max(axis=0) for b in default_model.blocks], axis=0)
    side = (
        a["buttress_thickness"]
        + a["aisle_wall_thickness"]
        + a["aisle_span"]
        + a["aisle_vault_thickness"]
        + a["wall_thickness"]
    )
    # Extrados crown of the semicircular nave vault (an even number of voussoirs puts a joint,
    # hence a vertex, at the crown): springing height plus the extrados radius.
    crown = a["nave_height"] + a["nave_span"] / 2 + a["nave_vault_thickness"]
    length = 2 * a["end_length"] + a["bays"] * a["bay_length"] - a["column_size"]
    assert a["nave_vault_segments"] % 2 == 0
    np.testing.assert_allclose(lows, [0.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(highs, [2 * side + a["nave_span"], crown, length], rtol=1e-9)
    # Cluny III's proportions: a nave about 11 m wide, bays of 5-6 m, a vault 20-30 m high.
    assert 10 <= a["nave_span"] <= 12 and 5 <= a["bay_length"] <= 6 and 20 <= crown <= 30


def test_about_a_thousand_blocks(default_model):
    assert 800 <= len(default_model.blocks) <= 1300
    labels = {tag for block in default_model.blocks for tag in block.tags}
    for part in ("nave vault", "aisle vault", "pier", "arcade arch", "window arch"):
        assert part in labels
    assert "flyer" in labels


def test_the_assembly_is_sound(default_model):
    # raises on interpenetrating blocks or blocks with no chain of contacts to the ground
    check_model(default_model, find_interfaces(default_model))


def test_the_default_design_needs_tension(default_analysis):
    assert not default_analysis.feasible
    assert default_analysis.infeasibility_normalized > 1e-6
    assert default_analysis.max_tension > 0


@pytest.mark.slow
@pytest.mark.parametrize("free", [None, FOUR + TEN_EXTRA], ids=["four @Free", "ten --free"])
def test_the_search_finds_a_standing_nave(grammar, free):
    result = optimize(grammar, free=free)
    assert result.feasible
    assert len(result.values) == (10 if free else 4)
    ranges = grammar.parameter_ranges({})
    for name, value in result.values.items():
        assert ranges[name]["min"] <= value <= ranges[name]["max"]
    # thicker clerestory walls or buttresses: thinner ones than the start cannot carry the vault
    start = grammar.attrs
    assert (
        result.values["wall_thickness"] > start["wall_thickness"]
        or result.values["buttress_thickness"] > start["buttress_thickness"]
    )
    # an independent check of the optimized model, rebuilt from the values alone
    model = grammar.build(attrs=result.values)
    check_model(model, find_interfaces(model))
    assert analyze(model).feasible


def test_a_small_step_keeps_every_contact_for_the_adjoint_gradient(grammar, default_analysis):
    # The adjoint gradient follows each interface vertex through a small change of a parameter.
    # Course joints share corners (up to four joints meet at a block's corner), so a vertex must
    # be matched within its own interface: the match must exist, be one to one, and move no
    # vertex by more than twice the step (the right half moves by both walls' widening).
    from shapegen.statics import assemble
    from shapegen.statics.sensitivity import _match_vertices

    step = 1e-6
    model = grammar.build(attrs={"wall_thickness": grammar.attrs["wall_thickness"] + step})
    problem = default_analysis.problem
    moved = assemble(model, find_interfaces(model))
    order = _match_vertices(problem, moved)
    assert order is not None
    assert len(np.unique(order)) == problem.n_vertices
    shift = np.linalg.norm(moved.vertex_points - problem.vertex_points[order], axis=1)
    assert shift.max() <= 2 * step * (1 + 1e-6)
