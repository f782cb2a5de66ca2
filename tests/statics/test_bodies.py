"""Bodies of several convex parts: glued overlaps, the parts of one leaf, ornaments as load."""

from __future__ import annotations

import math

import numpy as np
import pytest

from shapegen.errors import StaticsError
from shapegen.model import Block, Model, PointLoad
from shapegen.statics import analyze, lateral_capacity
from shapegen.statics.bodies import Bodies, find_bodies
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.interface import GROUND

POST, HEIGHT, ARM = 0.5, 2.0, 0.2  # post width and height, arm thickness (m)
# The arm of length l overhangs the post's base [0, a]: the union's centroid is over the base
# while a H a / 2 + t l^2 / 2 - a t a / 2 <= a (a H + l t - a t), i.e. up to l = a (1 + sqrt(H/t))
TIPPING_LENGTH = POST * (1 + math.sqrt(HEIGHT / ARM))


def overlapping_ell(length: float) -> Model:
    """A post and an arm along its whole top, the arm overlapping the post's top."""
    post = Block.box((0, 0, 0), (POST, HEIGHT, 1), id="post")
    arm = Block.box((0, HEIGHT - ARM, 0), (length, HEIGHT, 1), id="arm")
    return Model([post, arm])


def jointed_ell(length: float, body: str = "ell") -> Model:
    """The same L as two convex parts of one leaf, meeting on the plane x = a."""
    post = Block.box((0, 0, 0), (POST, HEIGHT, 1), id="post", body=body)
    arm = Block.box((POST, HEIGHT - ARM, 0), (length, HEIGHT, 1), id="arm", body=body)
    return Model([post, arm])


@pytest.mark.parametrize("factor, stands", [(0.98, True), (1.02, False)])
def test_overlapping_boxes_are_one_body_standing_while_its_centroid_is_over_the_base(
    factor, stands
):
    model = overlapping_ell(factor * TIPPING_LENGTH)
    analysis = analyze(model)
    assert analysis.feasible is stands
    assert analysis.bodies.count == 1 and analysis.bodies.glued == 1
    report = analysis.to_report()["bodies"]
    assert report["bodies"] == 1 and report["parts"] == 2 and report["glued"] == 1
    # the common volume counts once: the weight is that of the L, not of the two boxes
    area = POST * HEIGHT + factor * TIPPING_LENGTH * ARM - POST * ARM
    assert analysis.total_weight == pytest.approx(2400 * 9.81 * area, rel=1e-9)


@pytest.mark.parametrize("factor", [0.98, 1.02])
def test_parts_of_one_leaf_give_the_verdict_of_the_glued_boxes(factor):
    length = factor * TIPPING_LENGTH
    glued, parts = analyze(overlapping_ell(length)), analyze(jointed_ell(length))
    assert parts.feasible is glued.feasible is (factor < 1)
    assert parts.bodies.count == 1 and parts.bodies.glued == 0
    assert parts.infeasibility_normalized == pytest.approx(
        glued.infeasibility_normalized, rel=1e-6, abs=1e-12
    )
    # the joint between the two parts is not a joint of the statics
    assert all(i.second == GROUND for i in parts.interfaces)


def test_two_parts_that_are_two_bodies_do_not_stand_as_a_cantilever():
    # without the body name the arm is a block of its own, hanging on a vertical joint
    assert not analyze(jointed_ell(0.9 * TIPPING_LENGTH, body="")).feasible


def test_the_tilt_a_glued_body_takes_is_that_of_its_parts_as_one_leaf():
    length = 0.6 * TIPPING_LENGTH
    glued = lateral_capacity(overlapping_ell(length), azimuths=[0, 180])
    parts = lateral_capacity(jointed_ell(length), azimuths=[0, 180])
    for a, b in zip(glued.directions, parts.directions, strict=True):
        assert a.tilt == pytest.approx(b.tilt, abs=1e-6)
    # towards +x the body tips about x = a: tan(theta) = (a - x_c) / y_c
    post, arm, common = POST * HEIGHT, length * ARM, POST * ARM
    total = post + arm - common
    x_c = (post * POST / 2 + arm * length / 2 - common * POST / 2) / total
    y_c = (post * HEIGHT / 2 + (arm - common) * (HEIGHT - ARM / 2)) / total
    assert glued.directions[0].tilt == pytest.approx(
        math.degrees(math.atan((POST - x_c) / y_c)), abs=1e-4
    )


# ------------------------------------------------------------------------------------ ornaments
def pier_with_ornament(**changes) -> Model:
    pier = Block.box((0, 0, 0), (1, 2, 1), id="pier", tags=("wall",))
    finial = Block.box((0.25, 1.8, 0.25), (0.75, 2.5, 0.75), id="finial", tags=("ornament",))
    hanging = Block.box((1.0, 1.0, 0.4), (1.3, 1.5, 0.6), id="boss", tags=("ornament",))
    return Model([pier, finial, hanging], **changes)


def test_ignored_ornaments_ride_on_the_body_below_and_the_ground_carries_all_the_weight():
    model = pier_with_ornament()
    analysis = analyze(model, ignore="ornament")
    bodies = analysis.bodies
    assert bodies.count == 1 and bodies.ignored == 2 and len(bodies.riders) == 2
    assert bodies.host[1] == bodies.host[2] == 0
    weight = 9.81 * sum(b.mass for b in model.blocks)  # the finial overlaps the pier: riding
    assert analysis.total_weight == pytest.approx(weight, rel=1e-12)
    assert analysis.feasible
    # the sign of a resultant: the force on `second`, the ground's reaction is its opposite
    reaction = sum(
        float(np.asarray(f)[1]) * -1.0
        for i, f in zip(analysis.interfaces, analysis.resultant_forces, strict=True)
        if i.second == GROUND
    )
    assert reaction == pytest.approx(weight, rel=1e-6)


def test_an_ornament_is_chosen_by_label_or_rule_and_structural_keeps_only_what_is_named():
    model = pier_with_ornament()
    for block in model.blocks:
        block.rule_path = ("Lot", "Pier" if block.id == "pier" else "Decor")
    by_rule = find_bodies(model, find_interfaces(model), ignore="Decor")
    by_structure = find_bodies(model, find_interfaces(model), structural=["wall"])
    for bodies in (by_rule, by_structure):
        assert bodies.body.tolist() == [0, -1, -1] and bodies.ignored == 2


def test_a_name_no_block_has_is_one_line_with_a_suggestion():
    model = pier_with_ornament()
    with pytest.raises(StaticsError, match=r"--ignore ornamnet: no block has the label or rule"):
        analyze(model, ignore="ornamnet")
    with pytest.raises(StaticsError, match="did you mean 'ornament'"):
        analyze(model, ignore="ornamnet")
    with pytest.raises(StaticsError, match="no block to judge"):
        analyze(model, ignore="wall,ornament")


def test_a_point_load_on_an_ornament_goes_to_its_host():
    model = pier_with_ornament(loads=[PointLoad("finial", (0, -1000.0, 0), (0.5, 2.5, 0.5))])
    with_load = analyze(model, ignore="ornament")
    assert with_load.feasible
    reaction = sum(
        -float(np.asarray(f)[1])
        for i, f in zip(with_load.interfaces, with_load.resultant_forces, strict=True)
        if i.second == GROUND
    )
    assert reaction == pytest.approx(with_load.total_weight + 1000.0, rel=1e-6)


def test_an_ornament_off_the_structure_loads_nothing_and_a_floating_body_is_still_an_error():
    model = pier_with_ornament()
    model.blocks.append(Block.box((3, 0, 0), (3.5, 0.5, 0.5), id="urn", tags=("ornament",)))
    analysis = analyze(model, ignore="ornament")
    assert analysis.bodies.host[3] == -1 and len(analysis.bodies.riders) == 2
    floating = Model([Block.box((0, 1, 0), (1, 2, 1), id="floating")])
    with pytest.raises(StaticsError, match="floating"):
        analyze(floating)


def test_blocks_each_their_own_body_are_judged_as_blocks():
    model = Model([Block.box((0, 0, 0), (1, 1, 1)), Block.box((0.2, 1, 0), (1.4, 2, 1))])
    analysis = analyze(model)
    assert isinstance(analysis.bodies, Bodies) and analysis.bodies.trivial
    assert analysis.problem.bodies is None and "bodies" not in analysis.to_report()


def test_a_cityengine_model_whose_only_block_floats_has_nothing_to_judge():
    # envelope2002: one block touching no support, the rest faces; it rides, no body is left
    floating = Model([Block.box((0, 1, 0), (1, 2, 1))], metadata={"dialect": "cga"})
    analysis = analyze(floating)
    assert analysis.feasible and analysis.bodies.count == 0
    assert analysis.to_report()["free_bodies"] == 0
    assert lateral_capacity(floating, azimuths=[0]).worst.status == "unbounded"


@pytest.mark.parametrize(
    ("name", "dialect"), [("floating.CGA", "cga"), ("floating.grammar", "grammar")]
)
def test_the_statics_read_the_dialect_the_derivation_records(name, dialect):
    # one block lifted off its lot: it rides in a CityEngine model, is an error in a .grammar one
    from shapegen import parse_grammar

    grammar = parse_grammar("@StartRule @Lot(1, 1)\nLot --> t(0, 1, 0) extrude(1) Stone", name)
    model = grammar.build()
    assert grammar.dialect == dialect and model.metadata["dialect"] == dialect
    if dialect == "cga":
        assert analyze(model).bodies.count == 0
    else:
        with pytest.raises(StaticsError, match="touches no support"):
            analyze(model)
