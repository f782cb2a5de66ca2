"""The bundled sainte_chapelle.grammar: groin-vaulted bays between buttressed piers.

Counts follow from the rule's structure (bays, piers, courses); the geometry is checked
independently of the statics (no interpenetration, every block supported, the vaults springing
from the tops of the piers); the statics verdicts are those the file promises: its defaults need
tension, and the search over the 4-set and over the 10-set documented in its header finds a design
that stands.
"""

import re

import pytest

from shapegen import load_grammar
from shapegen.engine.project.rules_path import find_bundled_rule
from shapegen.search import optimize
from shapegen.statics import StaticsOptions, analyze, find_interfaces
from shapegen.statics.checks import check_model
from shapegen.structures import make_structure

CLARABEL = make_structure("blocks", StaticsOptions(solver="clarabel"))
FOUR = {"column_depth", "corner_width", "corner_depth", "height"}


@pytest.fixture(scope="module")
def chapel():
    return load_grammar("sainte_chapelle.grammar")


@pytest.fixture(scope="module")
def model(chapel):
    return chapel.build()


def ten_set() -> list[str]:
    """The 10-set, as documented in the file's header comment (``--free a,b,...``)."""
    text = find_bundled_rule("sainte_chapelle.grammar").read_text()
    (names,) = re.findall(r"--free ([a-z_,]+)", text)
    return names.split(",")


def defaults(chapel) -> dict:
    return {name: spec["value"] for name, spec in chapel.parameter_ranges().items()}


def labelled(model, label):
    return [i for i, block in enumerate(model.blocks) if label in block.tags]


def test_free_parameter_sets(chapel):
    assert set(chapel.free_parameters) == FOUR
    ten = ten_set()
    assert len(ten) == len(set(ten)) == 10 and FOUR <= set(ten)
    ranges = chapel.parameter_ranges()
    for name in ten:  # every one can be searched: a number with bounds around its default
        assert ranges[name]["min"] < ranges[name]["max"], name
        assert ranges[name]["min"] <= ranges[name]["value"] <= ranges[name]["max"], name


def test_blocks_follow_from_the_rule_structure(chapel, model):
    values = defaults(chapel)
    bays = int(values["bays"])
    courses = max(1, round(values["height"] / values["pier_course"]))
    assert len(labelled(model, "pier")) == 2 * (bays - 1) * courses
    assert len(labelled(model, "corner_pier")) == 4 * courses
    # windows: bays on each long wall and one in each end wall, each with one sill
    assert len(labelled(model, "sill")) == 2 * bays + 2
    assert 400 <= len(model.blocks) <= 600


def test_model_is_sound_geometry(model):
    interfaces = find_interfaces(model)
    check_model(model, interfaces)  # no interpenetration, every block has a path to the ground
    lowest = min(block.vertices[:, 1].min() for block in model.blocks)
    assert lowest == pytest.approx(0.0, abs=1e-9)


def test_vaults_spring_from_the_piers_at_the_wall_height(chapel, model):
    values = defaults(chapel)
    vaults = set(labelled(model, "vault"))
    bottom = min(model.blocks[i].vertices[:, 1].min() for i in vaults)
    assert bottom == pytest.approx(values["height"], abs=1e-9)
    piers = set(labelled(model, "pier")) | set(labelled(model, "corner_pier"))
    carrying = set()
    for interface in find_interfaces(model):
        pair = {interface.first, interface.second}
        if pair & vaults and pair & piers:
            carrying |= pair & piers
    # the top course of every pier and corner pier carries vault corners
    bays = int(values["bays"])
    assert len(carrying) == 2 * (bays - 1) + 4
    assert all(
        model.blocks[i].vertices[:, 1].max() == pytest.approx(values["height"]) for i in carrying
    )


def test_defaults_need_tension(model):
    analysis = analyze(model, solver="clarabel")
    assert not analysis.feasible and analysis.infeasibility > 0


def stands_within_bounds(chapel, result):
    assert result.feasible
    for name, spec in result.parameters.items():
        assert spec["min"] <= spec["final"] <= spec["max"], name
    assert analyze(chapel.build(attrs=result.values), solver="clarabel").feasible


@pytest.mark.slow
def test_optimize_four_parameters_reaches_a_standing_chapel(chapel):
    result = optimize(chapel, structure=CLARABEL)
    assert set(result.parameters) == FOUR
    stands_within_bounds(chapel, result)


@pytest.mark.slow
def test_optimize_ten_parameters_reaches_a_standing_chapel(chapel):
    result = optimize(chapel, free=ten_set(), structure=CLARABEL)
    assert set(result.parameters) == set(ten_set())
    stands_within_bounds(chapel, result)
