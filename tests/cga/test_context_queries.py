"""The context queries contextCount, contextCompare and minimumDistance (cga_context,
func_contextCount, func_contextCompare, func_minimumDistance) on arrangements whose answers follow
from the shapes' coordinates: the reference's own examples, cut down to a few shapes.

Every ``label()`` of the first pass is a labelled copy of its shape; the second pass answers
from them, the first answers the defaults (0, 0, infinity).
"""

from __future__ import annotations

import math

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError


def _reports(text: str, lot=(4.0, 3.0)) -> dict:
    return parse_grammar(text, "context.cga").build(lot=lot).metadata["reports"]


def test_context_count_counts_every_labelled_tile():
    # func_contextCount's example: a 4 x 3 m lot split into 1 m tiles, each labelled "Tile"
    reports = _reports(
        """
Lot --> split(x) { ~1 : Split }*
Split --> split(z) { ~1 : Tile }*
Tile --> label("Tile") report("n", contextCount(intra, "Tile"))
         report("other", contextCount(intra, "Roof")) report("inter", contextCount(inter, "Tile"))
         report("empty", contextCount(intra, "")) X.
""",
    )
    assert reports["n"] == [12.0] * 12
    assert reports["other"] == [0.0] * 12
    assert reports["inter"] == [0.0] * 12  # one lot: no other shape trees
    assert reports["empty"] == [0.0] * 12


def test_each_label_operation_is_a_labelled_copy():
    # cga_context's "Labels" example: two label operations on one shape count twice
    reports = _reports(
        'Lot --> label("label") report("n", contextCount(intra, "label")) label("label")'
    )
    assert reports["n"] == 2.0


def test_context_compare_ranks_by_height_and_area():
    # func_contextCompare's example within one lot: boxes 2, 5 and 3 m high on 1 x 3 m plots
    reports = _reports(
        """
Lot --> split(x) { 1 : A(2) | 1 : A(5) | 1 : A(3) | ~1 : NIL }
A(h) --> extrude(h) label("m")
         report("highest", contextCompare(intra, "m", world.highest))
         report("lowest", contextCompare(intra, "m", world.lowest))
         report("largest", contextCompare(intra, "m", area.largest))
         report("smallest", contextCompare(intra, "m", area.smallest))
         report("easternmost", contextCompare(intra, "m", world.easternmost))
         report("westernmost", contextCompare(intra, "m", world.westernmost)) X.
""",
    )
    assert reports["highest"] == [2.0, 0.0, 1.0]
    assert reports["lowest"] == [0.0, 0.0, 0.0]  # equal bottoms share the lowest rank
    assert reports["largest"] == [2.0, 0.0, 1.0]  # 22, 46 and 30 m^2
    assert reports["smallest"] == [0.0, 2.0, 1.0]
    assert reports["easternmost"] == [2.0, 1.0, 0.0]  # x grows east
    assert reports["westernmost"] == [0.0, 1.0, 2.0]


def test_minimum_distance_between_scopes():
    # func_minimumDistance's example in one row: the first plot is labelled; distances from it
    reports = _reports(
        """
Lot --> split(x) { 1 : T(0) | 2 : T(1) | 1 : T(2) | ~1 : T(3) }
T(i) --> case i == 0 : label("c") D
         else : D
D --> report("d", minimumDistance(intra, "c")) report("none", minimumDistance(intra, "x")) X.
""",
        lot=(10.0, 3.0),
    )
    assert reports["d"] == pytest.approx([0.0, 0.0, 2.0, 3.0])
    assert all(math.isinf(v) for v in reports["none"])


def test_minimum_distance_between_boxes_apart_in_height():
    # a 1 m box raised 4 m over the labelled 1 m box beside it: the nearest points are corners,
    # 1 m apart across and 3 m apart up
    reports = _reports(
        """
Lot --> split(x) { 1 : extrude(1) label("c") X. | 1 : NIL | 1 : extrude(1) t(0, 4, 0) D }
D --> report("d", minimumDistance(intra, "c")) X.
""",
        lot=(3.0, 1.0),
    )
    assert reports["d"] == pytest.approx(math.hypot(1.0, 3.0))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ('contextCount(here, "a")', "undefined name 'here'"),
        ('contextCompare(intra, "a", world.up)', "undefined name 'world.up'"),
        ('contextCompare(intra, "a", intra)', "comparison is one of"),
        ('contextCount("a", "a")', "target is intra, inter or all"),
        ('contextCount(intra, "a", 1)', "takes 2 arguments"),
        ("contextCount(intra, 1)", "label is a string"),
    ],
)
def test_bad_calls_are_one_line_errors(call, message):
    with pytest.raises(GrammarError, match=message):
        _reports(f'Lot --> label("a") report("v", {call}) X.')
