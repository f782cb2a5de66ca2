"""Blocks too small to judge: in a real CityEngine model (``.cga``) a block whose volume is
within the model's volume tolerance of zero (a needle, a sliver of a leaf's cut) is merged
into its leaf's body or carried as load by the block it touches, counted by reason, and the
analysis goes on; a ``.grammar`` design refuses it in one line naming the tolerance and the
block's rules."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.cli import main
from shapegen.engine.grammar_api import parse_grammar
from shapegen.errors import GeometryError
from shapegen.model import Block, Model
from shapegen.model.model import STANDARD_GRAVITY
from shapegen.pipeline import design
from shapegen.statics import analyze
from shapegen.statics.standins import (
    CARRIED,
    MERGED,
    TOUCHING_NOTHING,
    StaticsModel,
    statics_model,
)

LOT = (800.0, 800.0)  # m: a slab this wide makes a 3 cm needle too small to judge

# a 3 x 40 x 3 cm needle standing on a slab 800 m wide: 3.6e-4 m^3 against the model's
# tolerance of 1e-12 times the cube of its size (1131 m), 1.4e-3 m^3
NEEDLE = "Lot --> extrude(2) [ t(10, {height}, 10) s(0.03, 0.4, 0.03) {insert}Needle ] Slab\n"


def _needle(height: float = 2.0, dialect: str = "cga"):
    insert = 'i("builtin:cube") ' if dialect == "cga" else ""
    text = NEEDLE.format(height=height, insert=insert)
    return parse_grammar(text, f"needle.{dialect}")


def test_a_needle_on_a_slab_is_carried_as_load_counted_and_the_slab_judged():
    outcome = design(_needle(), lot=LOT, assess=True)
    assert outcome.assessment is not None and outcome.assessment.judged
    assert outcome.report["analysis"]["feasible"]
    too_small = outcome.report["analysis"]["stand_ins"]["too_small"]
    model = outcome.model
    size = model.size
    assert too_small["volume_floor_m3"] == pytest.approx(1e-12 * size**3)
    assert too_small["blocks"] == 1 and too_small["by_reason"] == {CARRIED: 1}
    # its weight is a load on the slab, at its centroid
    judged = statics_model(model)
    needle = next(b for b in model.blocks if "Needle" in b.rule_path)
    slab = next(b for b in model.blocks if "Slab" in b.rule_path)
    assert [b.id for b in judged.blocks] == [slab.id]
    (load,) = judged.loads
    assert load.block == slab.id
    weight = needle.volume * needle.density * STANDARD_GRAVITY
    np.testing.assert_allclose(load.force, [0.0, -weight, 0.0], rtol=1e-12)
    np.testing.assert_allclose(load.point, needle.centroid, rtol=1e-12)


def test_a_needle_touching_nothing_is_left_out_counted():
    outcome = design(_needle(height=5.0), lot=LOT, assess=True)
    assert outcome.assessment is not None and outcome.assessment.judged
    too_small = outcome.report["analysis"]["stand_ins"]["too_small"]
    assert too_small["by_reason"] == {TOUCHING_NOTHING: 1}
    assert not statics_model(outcome.model).loads


def test_the_printout_counts_the_needle(tmp_path, capsys):
    rule = tmp_path / "needle.cga"
    rule.write_text(NEEDLE.format(height=2.0, insert='i("builtin:cube") '))
    assert main(["build", str(rule), "--lot", "800,800", "--analyze"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "stands yes" in out
    assert "1 block within the model's volume tolerance (0.001448 m^3)" in out
    assert f"not judged: 1 {CARRIED}" in out


def test_a_grammar_design_refuses_its_needle_naming_tolerance_and_rules():
    grammar = _needle(dialect="grammar")
    with pytest.raises(GeometryError) as caught:
        design(grammar, lot=LOT, assess=True)
    message = str(caught.value)
    assert "(rules: Lot -> Needle)" in message
    assert (
        "volume 0.00036 m^3 is within the model's volume tolerance of zero, 0.00145 m^3" in message
    )
    assert "1e-12 times the cube of its size, 1131 m" in message


def test_a_sliver_of_a_leafs_cut_is_merged_into_its_body():
    # two parts of one leaf's body (a cut's pieces) and beside them a sliver 1e-11 m thick of
    # the same body: 4e-10 m^3, below the model's floor of 4.7e-9 m^3
    big = Block.box((0.0, 0.0, 0.0), (10.0, 4.0, 10.0), id="s0.0", body="s0")
    top = Block.box((0.0, 4.0, 0.0), (10.0, 6.0, 10.0), id="s0.2", body="s0")
    sliver = Block.box((10.0, 0.0, 0.0), (10.0 + 1e-11, 4.0, 10.0), id="s0.1", body="s0")
    other = Block.box((10.0 + 1e-11, 0.0, 0.0), (12.0, 4.0, 10.0), id="b1")
    model = Model([big, sliver, top, other], metadata={"dialect": "cga"})
    judged = statics_model(model)
    assert isinstance(judged, StaticsModel)
    assert judged.stand_ins.too_small == {MERGED: 1}
    assert [b.id for b in judged.blocks] == ["s0.0", "s0.2", "b1"]
    (load,) = judged.loads
    assert load.block == "s0.0"  # its own body's, not the block beside it
    analysis = analyze(model)
    assert analysis.feasible
    # the figures per block stay those of the model's own four blocks
    assert analysis.n_blocks == 4 and len(analysis.block_tension) == 4
    assert analysis.block_tension[1] == 0.0


def test_the_same_sliver_stops_a_grammar_design():
    big = Block.box((0.0, 0.0, 0.0), (10.0, 4.0, 10.0), id="b0", rule_path=("Lot", "Wall"))
    sliver = Block.box((10.0, 0.0, 0.0), (10.0 + 1e-11, 4.0, 10.0), id="b1",
                       rule_path=("Lot", "Joint"))  # fmt: skip
    model = Model([big, sliver])
    assert statics_model(model) is model
    with pytest.raises(GeometryError, match=r"block 'b1' \(rules: Lot -> Joint\): volume"):
        analyze(model)
