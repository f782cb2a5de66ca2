"""CityEngine's random streams (engine/derivation/random_streams.py) against numbers measured
from its runtime (PyPRT 1.12; tests/data/cityengine_random.json says how each was measured)."""

import json
from pathlib import Path

import pytest

import shapegen.prt as prt
from shapegen.engine.derivation import random_streams

DATA = Path(__file__).resolve().parents[1] / "data"
MEASURED = json.loads((DATA / "cityengine_random.json").read_text())
CORPUS = DATA / "cga-corpus"
EXTRUSION = CORPUS / "examples_data_extrusion_rule__1c38c522" / "rules" / "extrusion_rule.cga"
BUILDING = (
    CORPUS / "data_Building_From_FootprintSMALL__fc6ce924" / "rules"
    / "Building_From_FootprintSMALL.cga"
)  # fmt: skip
ENVELOPE = CORPUS / "tests_data_envelope2002__3bb69433" / "rules" / "typology" / "envelope2002.cga"


def uniform(x: int) -> float:
    return random_streams.draw(x)[1]


def _generated(lot: str, rule: Path, attrs: dict):
    """The one model ``shapegen.prt`` generates of ``rule`` on the measured ``lot``."""
    shape = prt.InitialShape(MEASURED["lots"][lot])
    (model,) = prt.ModelGenerator([shape]).generate_model([attrs], str(rule))
    return model


def _assert_reports(model, reports: dict) -> None:
    ours = model.get_report()
    for key, value in reports.items():
        assert ours[key] == pytest.approx(value, rel=1e-6), key


@pytest.mark.parametrize("seed, height", MEASURED["extrusion_rule"]["values"].items())
def test_first_successor_draw(seed, height):
    # the start shape's first successor begins at child_stream(start); its first draw
    successor = random_streams.child_stream(random_streams.start(int(seed)))
    # float32 u, then doubles; the report is the volume over the area (round-off 1e-15)
    assert 10.0 + 20.0 * uniform(successor) == pytest.approx(height, rel=1e-13)


@pytest.mark.parametrize("seed, height", MEASURED["extrusion_rule"]["values"].items())
def test_extrusion_rule_derives_cityengine_heights(seed, height):
    model = _generated("12x8", EXTRUSION, {"seed": int(seed)})
    assert model.get_report()["Building Height.0_sum"] == pytest.approx(height, abs=1e-9)


def test_start_of_a_negative_seed_is_its_unsigned_value():
    assert random_streams.start(-1) == 2**32 - 1 - 6015 * 714025 == 106920


@pytest.mark.parametrize("seed, values", MEASURED["attr_streams"]["values"].items())
def test_attr_stream_given_its_offset(seed, values):
    k = MEASURED["attr_streams"]["k"]
    begin = (random_streams.start(int(seed)) + k["Eave_Ht"]) % random_streams.MODULUS
    eave = 96.0 / (5.0 + 5.0 * uniform(begin))
    assert eave == pytest.approx(values["Eave_Ht"], rel=1e-12)
    begin = (random_streams.start(int(seed)) + k["Ridge_Ht"]) % random_streams.MODULUS
    ridge = values["Eave_Ht"] + 3.0 + 3.0 * uniform(begin)
    assert ridge == pytest.approx(values["Ridge_Ht"], rel=1e-12)


@pytest.mark.parametrize("name, measured", MEASURED["attr_offsets"]["values"].items())
def test_attr_offset_follows_from_the_name(name, measured):
    # the compiled rule's attr renamed: its one draw, from the stream k further than the seed's
    assert 96.0 / (5.0 + 5.0 * uniform(measured["k"])) == pytest.approx(
        measured["Eave_Ht_value"], rel=1e-12
    )


def test_attr_offset_of_a_renamed_attr_is_the_original_offset():
    # Eave_Ht under its own name in the renamed package and in the stock one: one offset
    renamed = MEASURED["attr_offsets"]["values"]["Default$Eave_Ht"]["k"]
    assert renamed == MEASURED["attr_streams"]["k"]["Eave_Ht"]


def test_three_way_choice_draws_once_per_branch():
    measured = MEASURED["three_way_choice"]
    names = ("hip", "gable", "gambrel")
    for k in measured["k_candidates"]:
        for seed, roof in measured["values"].items():
            stream = [(random_streams.start(int(seed)) + k) % random_streams.MODULUS]

            def random(stream=stream):
                stream[0], u = random_streams.draw(stream[0])
                return u

            assert names[random_streams.choice(random, (0.4, 0.5))] == roof


def test_draws_reach_one():
    assert uniform(random_streams.MODULUS - 1) != 1.0  # the state stepped from is not drawn
    top = next(x for x in range(random_streams.MODULUS) if random_streams.step(x) == 714024)
    assert uniform(top) == 1.0


@pytest.mark.parametrize("form", ["setback top", "setback everywhere"])
def test_split_pieces_and_their_successors(form):
    measured = MEASURED["splits"]
    for seed, expected in measured["values"][form].items():
        attrs = {"seed": int(seed), "Building_Form": form, **measured["attrs"]}
        model = _generated("trapezoid", BUILDING, attrs)
        vertices = model.get_vertices()
        assert len(vertices) // 3 == expected["vertices"]
        assert sorted({round(x, 3) + 0.0 for x in vertices[0::3]}) == expected["x"]
        assert sorted({round(y, 3) + 0.0 for y in vertices[1::3]}) == expected["y"]


@pytest.mark.slow
@pytest.mark.parametrize("seed, reports", MEASURED["comp_pieces"]["values"].items())
def test_comp_pieces_and_many_branch_choices(seed, reports):
    _assert_reports(_generated("12x8", ENVELOPE, {"seed": int(seed)}), reports)


@pytest.mark.slow
@pytest.mark.parametrize("seed, reports", MEASURED["repeat_split_pieces"]["values"].items())
def test_repeat_split_pieces_on_the_floors_of_an_extruded_polygon(seed, reports):
    # the vertical greenery's tiles (a repeat split, a stochastic NIL per tile) on the walls of
    # floors that are split pieces of an extruded L-lot volume: PyPRT's reports to round-off
    _assert_reports(_generated("L", ENVELOPE, {"seed": int(seed)}), reports)
