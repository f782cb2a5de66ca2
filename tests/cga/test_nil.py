"""NIL (op_nil) deletes the current shape: it leaves no leaf, and the operations written after
it still run, as in CityEngine's runtime (its report of envelope2002 counts a report() written
after NIL: "total report for optimisation", 0.08 x the 38.4 m2 "Floor area")."""

from __future__ import annotations

from shapegen import parse_grammar


def _build(text: str):
    return parse_grammar(text, "nil.cga").build(lot=(4, 2))


def test_a_report_after_nil_counts_and_the_shape_leaves_nothing():
    model = _build('Lot --> extrude(3) comp(f) { top : report("a", 1) NIL report("b", 2) NIL }')
    assert model.metadata["reports"] == {"a": 1.0, "b": 2.0}
    assert model.metadata["leaves"] == 0


def test_a_successor_after_nil_is_derived():
    model = _build("Lot --> extrude(3) NIL A\nA --> s('0.5, '1, '1) B.")
    assert len(model.blocks) == 1
    assert model.blocks[0].volume == 0.5 * 4 * 2 * 3


def test_nil_in_a_split_makes_a_hole():
    model = _build("Lot --> extrude(3) split(x) { 1 : A. | 2 : NIL | ~1 : B. }")
    assert sorted(round(b.volume, 9) for b in model.blocks) == [6.0, 6.0]


def test_nil_inside_brackets_deletes_the_pushed_copy_only():
    # op_pushpop: ']' pops the pushed shape and deletes it; the shape outside stays a leaf
    model = _build("Lot --> extrude(3) [ t(5, 0, 0) NIL ]")
    assert len(model.blocks) == 1 and model.blocks[0].volume == 24.0
