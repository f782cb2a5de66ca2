"""The bundled mosque.grammar: a dome on a ring of wall piers, with and without flying buttresses.

Counts follow from the rule's structure (one pier per meridian of the dome, pier courses from the
wall height); the geometry is checked independently of the statics (every block on or above the
ground, no interpenetration, every block supported); the statics verdicts are those the file
promises: its defaults need tension, the search finds a design that stands.
"""

import math

import numpy as np
import pytest

from shapegen import load_grammar
from shapegen.search import optimize
from shapegen.statics import StaticsOptions, analyze, find_interfaces
from shapegen.statics.checks import check_model
from shapegen.structures import make_structure

CLARABEL = make_structure("blocks", StaticsOptions(solver="clarabel"))
VARIANTS = {"buttressed piers": {}, "flying buttresses": {"flying_buttresses": 1}}


@pytest.fixture(scope="module")
def mosque():
    return load_grammar("mosque.grammar")


def labelled(model, label):
    return [i for i, block in enumerate(model.blocks) if label in block.tags]


def test_free_parameters_are_window_wall_and_buttress(mosque):
    assert set(mosque.free_parameters) == {"window_width", "wall_thickness", "buttress_size"}


@pytest.mark.parametrize("attrs", VARIANTS.values(), ids=VARIANTS.keys())
def test_blocks_follow_from_the_rule_structure(mosque, attrs):
    model = mosque.build(attrs=attrs)
    values = {**{n: a["value"] for n, a in mosque.parameter_ranges(attrs).items()}, **attrs}
    meridians = int(values["dome_meridians"])
    rings = int(values["dome_rings"])
    courses = max(1, round(values["wall_height"] / values["course"]))
    assert len(labelled(model, "dome")) == meridians * rings
    assert len(labelled(model, "wall_pier")) == meridians * courses
    flyers = labelled(model, "flying_buttress")
    # a flyer of 6 voussoirs on a pier of 5 courses behind each wall pier
    assert len(flyers) == (meridians * 11 if attrs else 0)
    assert 150 <= len(model.blocks) <= 400


@pytest.mark.parametrize("attrs", VARIANTS.values(), ids=VARIANTS.keys())
def test_model_is_sound_geometry(mosque, attrs):
    model = mosque.build(attrs=attrs)
    interfaces = find_interfaces(model)
    check_model(model, interfaces)  # no interpenetration, every block has a path to the ground
    lowest = min(block.vertices[:, 1].min() for block in model.blocks)
    assert lowest == pytest.approx(0.0, abs=1e-9)


def test_each_lune_of_the_dome_rests_on_its_own_pier(mosque):
    model = mosque.build()
    height = mosque.parameter_ranges()["wall_height"]["value"]
    dome = set(labelled(model, "dome"))
    piers = set(labelled(model, "wall_pier"))
    springing = {i for i in dome if model.blocks[i].vertices[:, 1].min() < height + 1e-9}
    meridians = int(mosque.parameter_ranges()["dome_meridians"]["value"])
    assert len(springing) == meridians
    carried = {}
    for interface in find_interfaces(model):
        pair = {interface.first, interface.second}
        if pair & springing and pair & piers:
            (lune,) = pair & springing
            carried.setdefault(lune, set()).update(pair & piers)
    assert set(carried) == springing
    assert all(len(p) == 1 for p in carried.values())
    assert len(set().union(*carried.values())) == meridians  # a different pier under each lune
    # ... and each pier faces the middle of its lune: same azimuth about the dome's axis
    centre = np.array([6.0, 6.0])  # the lot is 12 x 12 m
    for lune, (pier,) in carried.items():
        a = model.blocks[lune].centroid[[0, 2]] - centre
        b = model.blocks[pier].centroid[[0, 2]] - centre
        angle = math.degrees(math.atan2(a[0] * b[1] - a[1] * b[0], a @ b))
        assert abs(angle) < 1e-6


def test_every_flyer_props_a_pier(mosque):
    model = mosque.build(attrs={"flying_buttresses": 1})
    flyers = set(labelled(model, "flying_buttress"))
    piers = set(labelled(model, "wall_pier"))
    propped = set()
    for interface in find_interfaces(model):
        pair = {interface.first, interface.second}
        if pair & flyers and pair & piers:
            propped |= pair & piers
    assert len(propped) == int(mosque.parameter_ranges()["dome_meridians"]["value"])


@pytest.mark.parametrize("attrs", VARIANTS.values(), ids=VARIANTS.keys())
def test_defaults_need_tension(mosque, attrs):
    analysis = analyze(mosque.build(attrs=attrs), solver="clarabel")
    assert not analysis.feasible and analysis.infeasibility > 0


@pytest.mark.slow
@pytest.mark.parametrize("attrs", VARIANTS.values(), ids=VARIANTS.keys())
def test_optimize_reaches_a_standing_design_within_bounds(mosque, attrs):
    result = optimize(mosque, attrs=attrs, structure=CLARABEL)
    assert result.feasible
    for name, spec in result.parameters.items():
        assert spec["min"] <= spec["final"] <= spec["max"], name
    again = analyze(mosque.build(attrs={**attrs, **result.values}), solver="clarabel")
    assert again.feasible
