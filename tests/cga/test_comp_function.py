"""The comp function (func_comp): one value per component, in the comp operation's order,
the shape left as it is. Checked on a 4 x 2 x 3 box: its edges' lengths, its faces' areas, the
default of components no selector takes, '=' evaluated once on the merged faces."""

from __future__ import annotations

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError


def _report(body: str):
    grammar = parse_grammar(f'Lot --> extrude(3) report("v", str({body})) X.', "comp.cga")
    return grammar.build(lot=(4, 2)).metadata["reports"]["v"]


def _numbers(text: str) -> list[float]:
    """The elements of a printed row, ``(3)[1,2,3]``."""
    return [float(v) for v in text.split(")", 1)[1].strip("[]").split(",")]


def test_edge_lengths_of_a_box():
    lengths = _numbers(_report("comp(e) { all : scope.sx }"))
    assert len(lengths) == 12
    assert sorted(lengths) == [2.0] * 4 + [3.0] * 4 + [4.0] * 4


def test_face_values_follow_the_comp_operation_order():
    # comp(f): 0 bottom, 1 top, then the sides from the lot's first edge (4, 2, 4, 2 m wide)
    assert _numbers(_report("comp(f) { all : geometry.area }")) == [8, 8, 12, 6, 12, 6]
    assert _numbers(_report("comp(f) { side : comp.index | top : 9 }")) == [0, 9, 0, 1, 2, 3]


def test_merge_evaluates_once_on_the_selected_faces():
    assert _numbers(_report("comp(f) { side = geometry.area }")) == [0, 0, 36, 36, 36, 36]


@pytest.mark.parametrize(
    "body, expected",
    [
        ('comp(f) { bottom : "b" }', "(6)[b,,,,,]"),  # as func_splitString prints (3)[,b,]
        ("comp(f) { top : true }", "(6)[false,true" + ",false" * 4 + "]"),
    ],
)
def test_components_no_selector_takes_get_the_default(body, expected):
    assert _report(body) == expected


def test_values_of_two_types_are_refused():
    with pytest.raises(GrammarError, match="must be of one type"):
        _report('comp(f) { top : 1 | bottom : "a" }')


def test_the_shape_is_left_as_it_is():
    grammar = parse_grammar(
        'Lot --> extrude(3) report("n", size(comp(f) { all : 1 })) report("h", scope.sy) X.',
        "comp.cga",
    )
    model = grammar.build(lot=(4, 2))
    assert model.metadata["reports"] == {"n": 6.0, "h": 3.0}
    assert len(model.blocks) == 1
