"""The interpreter: derivations from grammar text to blocks, checked against geometry by hand."""

import json
import math
import re

import numpy as np
import pytest

import shapegen
from shapegen.errors import GrammarError
from shapegen.export.blocks_json import model_to_dict
from shapegen.limits import work_limits


def build(text, **kwargs):
    return shapegen.parse_grammar(text).build(**kwargs)


def bounds(block):
    return block.bounds.round(9).tolist()


# ---------------------------------------------------------------------------- shapes to blocks
def test_lot_extrude_split_gives_boxes_in_derivation_order():
    model = build(
        """
        @StartRule @Lot(6, 2)
        Lot --> extrude(3) split(x) { 1 : A | ~1 : B | 1 : A }
        B --> split(y) { 1 : C | 2 : D }
        """
    )
    assert [b.id for b in model.blocks] == ["b0", "b1", "b2", "b3"]
    assert [b.rule_path for b in model.blocks] == [
        ("Lot", "A"),
        ("Lot", "B", "C"),
        ("Lot", "B", "D"),
        ("Lot", "A"),
    ]
    assert bounds(model.blocks[0]) == [[0, 0, 0], [1, 3, 2]]
    assert bounds(model.blocks[1]) == [[1, 0, 0], [5, 1, 2]]
    assert bounds(model.blocks[2]) == [[1, 1, 0], [5, 3, 2]]
    assert model.volume == pytest.approx(6 * 3 * 2)
    model.validate()


def test_flat_leaves_make_no_blocks():
    model = build("Lot --> split(x) { 1 : A | 1 : B }")
    assert model.blocks == []


def test_nil_deletes_and_push_restores():
    model = build(
        """
        @StartRule @Lot(3, 1)
        Lot --> extrude(1) [ t(10, 0, 0) Moved ] split(x) { 1 : A | 1 : NIL | 1 : B }
        """
    )
    assert [b.rule_path[-1] for b in model.blocks] == ["Moved", "A", "B"]
    assert bounds(model.blocks[0]) == [[10, 0, 0], [13, 1, 1]]
    assert bounds(model.blocks[2]) == [[2, 0, 0], [3, 1, 1]]


def test_transforms_relative_and_absolute():
    model = build(
        """
        @StartRule @Lot(4, 2)
        Lot --> extrude(2) s('0.5, '1, 1) t('0.5, 1, 0) Box.
        """
    )
    assert bounds(model.blocks[0]) == [[1, 1, 0], [3, 3, 1]]


def test_rotation_turns_the_block_about_the_scope_origin():
    model = build(
        """
        @StartRule @Lot(2, 1)
        Lot --> extrude(1) r(0, 90, 0) Box.
        """
    )
    # About y by +90: the scope's x axis goes to -z, its z axis to +x.
    assert bounds(model.blocks[0]) == [[0, 0, -2], [1, 1, 0]]


def test_center_in_the_scope_of_the_push():
    model = build(
        """
        @StartRule @Lot(4, 4)
        Lot --> extrude(2) [ s(1, 1, 1) center(xz) Box. ]
        """
    )
    assert bounds(model.blocks[0]) == [[1.5, 0, 1.5], [2.5, 1, 2.5]]


def test_comp_faces_selectors_and_indices():
    model = build(
        """
        @StartRule @Lot(4, 2)
        Lot --> extrude(3) comp(f) { front : Front | side : Side | top : extrude(0.5) Roof. }
        Side --> report("index", comp.index) report("total", comp.total)
        Front --> extrude(0.25) Porch.
        """
    )
    reports = model.metadata["reports"]
    assert reports["index"] == [0.0, 1.0, 2.0]
    assert reports["total"] == [3.0, 3.0, 3.0]
    porch, roof = model.blocks
    assert porch.rule_path[-1] == "Porch"
    assert bounds(porch) == [[0, 0, 2], [4, 3, 2.25]]  # front face: normal +z at z = depth
    assert bounds(roof) == [[0, 3, 0], [4, 3.5, 2]]


def test_split_index_and_total():
    model = build(
        """
        @StartRule @Lot(10, 1)
        Lot --> extrude(1) split(x) { ~2.1 : A(split.index, split.total) }*
        A(i, n) --> report("i", i) report("n", n)
        """
    )
    assert model.metadata["reports"]["i"] == [0.0, 1.0, 2.0, 3.0, 4.0]
    assert model.metadata["reports"]["n"] == [5.0] * 5
    assert len(model.blocks) == 5


def test_repeat_split_in_a_grammar_matches_cityengine():
    model = build(
        """
        @StartRule @Lot(10, 1)
        Lot --> extrude(1) split(x) { 2 : X | 1 : Y }*
        """
    )
    widths = [b.bounds[1, 0] - b.bounds[0, 0] for b in model.blocks]
    assert [b.rule_path[-1] for b in model.blocks] == ["X", "Y"] * 3 + ["X"]
    assert widths == pytest.approx([2, 1] * 3 + [1])


def test_rule_parameters_and_recursion_that_stops():
    # Halve the mass until pieces are at most 1 m wide: 8 m -> 8 pieces.
    model = build(
        """
        @StartRule @Lot(8, 1)
        Lot --> extrude(1) Halve(0)
        Halve(level) --> case scope.sx > 1 : split(x) { '0.5 : Halve(level + 1) }*
                         else : report("level", level) Stone.
        """
    )
    assert len(model.blocks) == 8
    assert set(model.metadata["reports"]["level"]) == {3.0}


def test_rules_are_overloaded_by_their_number_of_parameters():
    # CGA: Wall and Wall(h) are two rules; the call's argument count picks one.
    model = build(
        """
        @StartRule @Lot(4, 1)
        Lot --> split(x) { 2 : Wall | 2 : Wall(3) }
        Wall --> Wall(1)
        Wall(h) --> extrude(h) Stone.
        """
    )
    assert sorted(round(b.bounds[1, 1], 9) for b in model.blocks) == [1.0, 3.0]


def test_a_call_matching_no_overload_names_the_counts():
    with pytest.raises(GrammarError, match=r"rule 'Wall' takes 0 or 1 arguments, got 2"):
        shapegen.parse_grammar(
            "@StartRule\nLot --> Wall(1, 2)\nWall --> Stone.\nWall(h) --> extrude(h) Stone."
        )


def test_insert_primitive_blocks_get_properties_and_sequential_ids():
    model = build(
        """
        attr density = 1800
        @StartRule @Lot(2, 0.5)
        Lot --> extrude(2) [ label("arch") i("capped_arch", thickness = 0.3, segments = 4) Arch. ]
                t(0, 0, 5) set(fixed, true) Support.
        """
    )
    *pieces, support = model.blocks
    assert sum("voussoir" in b.tags for b in pieces) == 4
    assert [b.id for b in model.blocks] == [f"b{k}" for k in range(len(model.blocks))]
    assert all(b.tags[0] == "arch" and b.density == 1800 for b in pieces)
    assert {t for b in pieces for t in b.tags} >= {"arch", "voussoir", "spandrel"}
    assert support.fixed and not any(b.fixed for b in pieces)
    # The capped arch fills its 2 x 2 x 0.5 scope except the opening under the intrados
    # (half of a 4-gon inscribed in the intrados circle of radius 1 - 0.3).
    opening = 4 * 0.5 * 0.7**2 * math.sin(math.pi / 4)
    assert sum(b.volume for b in pieces) == pytest.approx((2 * 2 - opening) * 0.5)


# ---------------------------------------------------------------------------- attributes
WALL = """
attr height = 3
attr name = "wall"
attr solid = true
const half = height / 2
@StartRule @Lot(4, 1)
Lot --> extrude(height) report("half", half) report("name", name + "!") Check(solid)
Check(flag) --> case flag : Solid. else : NIL
"""


@pytest.mark.parametrize(
    "overrides, height, name, blocks",
    [
        (None, 3.0, "wall", 1),
        ({"height": 5}, 5.0, "wall", 1),
        ({"height": "2.5", "name": "pier"}, 2.5, "pier", 1),
        ({"solid": "false"}, 3.0, "wall", 0),
    ],
)
def test_attr_overrides(overrides, height, name, blocks):
    model = build(WALL, attrs=overrides)
    assert model.metadata["attrs"]["height"] == height
    assert model.metadata["reports"]["half"] == height / 2  # consts follow the attrs
    assert model.metadata["reports"]["name"] == name + "!"
    assert len(model.blocks) == blocks
    if blocks:
        assert model.blocks[0].bounds[1, 1] == pytest.approx(height)


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"heigth": 2}, "did you mean 'height'"),
        ({"half": 2}, "const"),
        ({"height": "tall"}, "is a number"),
        ({"solid": 3}, "true or false"),
    ],
)
def test_bad_attr_overrides(overrides, message):
    with pytest.raises(GrammarError, match=message):
        build(WALL, attrs=overrides)


def test_grammar_attrs_and_free_parameters():
    grammar = shapegen.parse_grammar(
        """
        @Free @Range(min=0.2, max=1.5)
        attr width = 0.5
        @Range(0, 10)
        attr height = 2 * width
        Lot --> extrude(height) split(x) { width : A }*
        """
    )
    assert grammar.attrs == {"width": 0.5, "height": 1.0}
    assert grammar.free_parameters == {"width": {"value": 0.5, "min": 0.2, "max": 1.5}}
    model = grammar.build(attrs={"width": 1.0})
    assert model.metadata["free_parameters"]["width"]["value"] == 1.0
    assert model.metadata["attrs"] == {"width": 1.0, "height": 2.0}


def test_set_applies_to_the_subtree_only():
    model = build(
        """
        @StartRule @Lot(3, 1)
        Lot --> extrude(1) [ set(density, 1000) Inside ] split(x) { 1 : set(density, 500) A
                                                                 | 1 : A | 1 : A }
        A --> B
        """
    )
    assert [b.density for b in model.blocks] == [1000, 500, 2400, 2400]


def test_reserved_attrs_set_block_properties():
    model = build(
        """
        attr structural = false
        @StartRule @Lot(2, 1)
        Lot --> extrude(1) label("roof") split(x) { 1 : set(fixed, true) label("base") A
                                                  | 1 : set(structural, true) A }
        """
    )
    first, second = model.blocks
    assert first.fixed and not first.structural and first.tags == ("roof", "base")
    assert not second.fixed and second.structural and second.tags == ("roof",)
    assert first.density == second.density == 2400


def test_bad_reserved_attr_value_is_a_grammar_error():
    with pytest.raises(GrammarError, match="density"):
        build('Lot --> extrude(1) set(density, "heavy") A')


# ---------------------------------------------------------------------------- randomness
STOCHASTIC = """
@StartRule @Lot(100, 1)
Lot --> extrude(1) split(x) { 1 : Stone }*
Stone --> 30% : label("dark") Block.
          else : label("light") Block.
"""


def labels(model):
    return [b.tags[0] for b in model.blocks]


def test_stochastic_rules_are_deterministic_per_seed():
    grammar = shapegen.parse_grammar(STOCHASTIC)
    assert labels(grammar.build(seed=7)) == labels(grammar.build(seed=7))
    assert labels(grammar.build(seed=7)) != labels(grammar.build(seed=8))


def test_stochastic_rule_frequencies():
    grammar = shapegen.parse_grammar(STOCHASTIC)
    draws = [tag for seed in range(20) for tag in labels(grammar.build(seed=seed))]
    share = draws.count("dark") / len(draws)
    sigma = math.sqrt(0.3 * 0.7 / len(draws))
    assert abs(share - 0.3) < 4 * sigma


def test_draws_do_not_depend_on_other_subtrees():
    template = """
    @StartRule @Lot(2, 1)
    Lot --> extrude(1) split(x) {{ 1 : Left | 1 : Right }}
    Left --> {left}
    Right --> report("right", rand(0, 10))
    """
    small = build(template.format(left="A"), seed=3)
    large = build(template.format(left='split(x) { 0.01 : report("l", rand()) A }*'), seed=3)
    assert small.metadata["reports"]["right"] == large.metadata["reports"]["right"]
    assert 0 <= small.metadata["reports"]["right"] < 10


def test_functions_conditional_recursive_and_stochastic():
    model = build(
        """
        fact(n) = case n <= 1 : 1 else : n * fact(n - 1)
        coin = 50% : "heads" else : "tails"
        hyp(a, b) = sqrt(pow(a, 2) + pow(b, 2))
        Lot --> report("fact", fact(5)) report("coin", coin) report("hyp", hyp(3, 4))
                report("sin", sin(30)) report("atan2", atan2(1, 1))
        """
    )
    reports = model.metadata["reports"]
    assert reports["fact"] == 120.0
    assert reports["coin"] in ("heads", "tails")
    assert reports["hyp"] == pytest.approx(5.0)
    assert reports["sin"] == pytest.approx(0.5)  # degrees, as CGA
    assert reports["atan2"] == pytest.approx(45.0)


def test_same_seed_gives_byte_identical_json():
    text = STOCHASTIC.replace("Block.", "r(0, rand(0, 20), 0) Block.")
    first = json.dumps(model_to_dict(build(text, seed=11)), sort_keys=True)
    second = json.dumps(model_to_dict(build(text, seed=11)), sort_keys=True)
    assert first == second


def test_print_writes_values(capsys):
    build('Lot --> print("width", scope.sx, true)', lot=(2.5, 1))
    assert capsys.readouterr().out == "width 2.5 true\n"


# ---------------------------------------------------------------------------- lot
@pytest.mark.parametrize(
    "annotation, lot, expected",
    [("@Lot(6, 2)", None, (6, 2)), ("@Lot(6, 2)", (3, 4), (3, 4)), ("", None, (10, 10))],
)
def test_lot_size(annotation, lot, expected):
    model = build(f"@StartRule {annotation}\nLot --> extrude(1) Box.", lot=lot)
    assert bounds(model.blocks[0]) == [[0, 0, 0], [expected[0], 1, expected[1]]]
    assert model.metadata["lot"] == list(map(float, expected))


# ---------------------------------------------------------------------------- limits and errors
def test_runaway_recursion_reports_the_chain():
    grammar = shapegen.parse_grammar("Lot --> extrude(1) Tower\nTower --> t(0, 1, 0) Tower")
    with pytest.raises(GrammarError) as caught:
        grammar.build(max_depth=40)
    message = str(caught.value)
    assert "max_depth" in message
    assert re.search(r"Lot -> Tower x 4\d", message)
    assert caught.value.location.line == 2


def test_too_many_shapes_reports_the_chain():
    grammar = shapegen.parse_grammar(
        "Lot --> extrude(1) split(x) { ~0.5 : Grow }*\nGrow --> Grow Grow"
    )
    with pytest.raises(GrammarError, match=r"max_shapes.*Lot -> Grow x") as caught:
        grammar.build(max_shapes=500)
    assert caught.value.location.line == 2


def test_runaway_repeat_split_is_stopped():
    grammar = shapegen.parse_grammar("Lot --> extrude(1) split(x) { 1e-9 : A }*")
    with pytest.raises(GrammarError, match="max_shapes"):
        grammar.build(max_shapes=1000)


def test_block_vertices_are_rotation_of_scope_corners():
    model = build(
        """
        @StartRule @Lot(2, 1)
        Lot --> extrude(1) t(1, 0, 0) r(0, 0, 30) Box.
        """
    )
    block = model.blocks[0]
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    expected = np.array([1.0, 0, 0]) + np.array([[2, 1, 1]]) * [[1, 1, 1]] @ turn.T
    assert np.allclose(block.vertices.max(axis=0)[2], 1.0)
    assert np.allclose(block.vertices[6], expected[0])  # the far corner (2, 1, 1) in scope
    assert block.volume == pytest.approx(2.0)


def test_endless_function_recursion_is_a_grammar_error():
    with pytest.raises(GrammarError, match="calls itself too deeply") as caught:
        build("f(n) = f(n + 1) + 1\nLot --> extrude(f(1))")
    assert caught.value.location.line == 1


def test_endless_tail_recursion_stops_at_max_calls():
    # a call in tail position nests no deeper: the count of calls (or the clock) stops it
    with work_limits(max_calls=2_000), pytest.raises(GrammarError, match="max_calls") as caught:
        build("f(n) = f(n + 1)\nLot --> extrude(f(1))")
    assert "endless recursion" in str(caught.value)
    assert caught.value.location.line == 1


def test_tail_recursion_runs_100000_deep():
    # deeper than Python's stack and than max_call_depth: CityEngine evaluates it
    model = build(
        """
        tally(i, acc) = case i == 0 : acc else : tally(i - 1, acc + 1)
        even(n) = case n == 0 : true else : odd(n - 1)
        odd(n) = case n == 0 : false else : even(n - 1)
        heads(i, acc) = case i == 0 : acc
                        else : heads(i - 1, acc + (case p(0.5) : 1 else : 0))
        Lot --> report("count", tally(100000, 0)) report("even", even(20001))
                report("heads", heads(4000, 0))
        """
    )
    reports = model.metadata["reports"]
    assert reports["count"] == 100000.0
    assert reports["even"] is False
    assert abs(reports["heads"] - 2000) < 4 * math.sqrt(4000 * 0.25)


def test_non_tail_recursion_is_bounded_by_max_call_depth():
    text = 'f(n) = case n > 0 : f(n - 1) + 1 else : 0\nLot --> report("f", f(150))'
    assert build(text).metadata["reports"]["f"] == 150.0
    with work_limits(max_call_depth=100), pytest.raises(GrammarError, match="max_call_depth"):
        build(text)
