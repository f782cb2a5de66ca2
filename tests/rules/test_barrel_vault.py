"""rules/barrel_vault.grammar: a barrel vault on walls with flying buttresses (seed Figure 13).

Truth values from the rule's layout: a vault of 12 voussoirs in 4 courses (48 blocks), two walls
of 4 courses by 4 stones (32), six buttresses of a 4-course pier and a 6-voussoir flyer (60):
140 blocks. The vault's intrados is flush with the walls' inner faces, so the vault is
``span + 2 vault_thickness`` wide. Each flyer meets its wall in the top course (flyer_height
3.6 m, courses 1 m high), across the joint between two of the wall's 1.5 m stones.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rule_checks import tagged

from shapegen.search import DesignSession
from shapegen.statics import analyze, find_interfaces

RULES = Path(__file__).resolve().parents[2] / "rules"
GRAMMAR = RULES / "barrel_vault.grammar"


@pytest.fixture(scope="module")
def model(grammar):
    return grammar.build()


def test_140_blocks(model):
    assert len(model.blocks) == 140
    assert len(tagged(model, "vault")) == 12 * 4
    assert len(tagged(model, "wall")) == 2 * 4 * 4
    assert len(tagged(model, "flyer")) == 6 * 6
    assert len(tagged(model, "pier")) == 6 * 4


def test_one_free_parameter_the_flyer_angle(grammar):
    assert list(grammar.free_parameters) == ["angle"]
    ranges = grammar.parameter_ranges()
    assert 0 < ranges["angle"]["min"] < ranges["angle"]["max"] <= 90
    assert "span" in grammar.attrs and "span" not in grammar.free_parameters


@pytest.mark.parametrize("span", [5.0, 7.0])
def test_vault_width_follows_the_span(grammar, span):
    model = grammar.build(attrs={"span": span})
    thickness = grammar.attrs["vault_thickness"]
    points = np.vstack([b.vertices for b in tagged(model, "vault")])
    assert np.ptp(points[:, 0]) == pytest.approx(span + 2 * thickness, rel=1e-9)
    walls = np.vstack([b.vertices for b in tagged(model, "wall")])
    inner = np.sort(np.unique(np.round(walls[:, 0], 9)))[1:3]  # the two inner faces
    assert inner[1] - inner[0] == pytest.approx(span, abs=1e-9)


def test_every_flyer_props_two_wall_stones(model):
    kind = {k: ("flyer" if "flyer" in b.tags else "wall" if "wall" in b.tags else "")
            for k, b in enumerate(model.blocks)}  # fmt: skip
    props = [
        i for i in find_interfaces(model)
        if {kind.get(i.first), kind.get(i.second)} == {"flyer", "wall"}
    ]  # fmt: skip
    assert len(props) == 6 * 2
    for interface in props:
        assert abs(interface.normal[0]) == pytest.approx(1.0, abs=1e-9)  # the wall's outer face


def test_default_needs_tension_with_the_pyramid_and_stands_with_the_cone(model):
    # its joints need a little more friction than the 4-sided pyramid's mu / sqrt(2) where a
    # side faces the sliding direction; the exact cone (the default) gives mu in every direction
    assert not analyze(model, pyramid="4").feasible
    assert analyze(model).feasible
    assert analyze(model, solver="clarabel").feasible  # the other back-end's cone agrees


@pytest.mark.slow
def test_session_optimizes_the_angle_and_warm_starts(grammar):
    session = DesignSession(grammar)
    session.set(span=grammar.attrs["span"])
    result = session.optimize()
    assert result.feasible
    lower, upper = result.parameters["angle"]["min"], result.parameters["angle"]["max"]
    assert lower <= result.values["angle"] <= upper
    assert analyze(grammar.build(attrs={"angle": result.values["angle"]})).feasible
    # Warm start: the next update begins at the solution, which already stands.
    again = session.optimize()
    assert again.feasible and again.iterations == 0
    assert again.values == result.values
