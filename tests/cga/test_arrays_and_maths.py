"""Arrays and maths as CityEngine's reference gives them: an index outside an array gives the
default of its type (func_index "Invalid indexing"), an array of indices gives an array of its
shape, an array literal places arrays as blocks (func_array), the element-wise operators work
element by element (arrayTypes.html), and the maths follow IEEE
arithmetic (func_sqrt: "If x is negative, nan is generated"). The expected values are the
reference's own examples."""

from __future__ import annotations

import math

import pytest

from shapegen import parse_grammar
from shapegen.engine.expressions.arrays import Array
from shapegen.errors import GrammarError

ARRAYS = """
const array = [1, 2, 3, 4]
const array2d = [1, 2, 3; 4, 5, 6; 7, 8, 9]
const a = [-1; -2]
const b = [0:2; 3, 3, 3]
const abc = ["B", "C", "D"]
const table = [4, 0, 1; 2, 1, 9; 1, 3, 0; 2, 1, 0]
sortRows(a, columnPrecedence) =
    a[sortRowIndices(a[0:nRows(a)-1, columnPrecedence]), 0:nColumns(a)-1]
"""


def _array(notation: str) -> Array:
    """The array the reference's comment notation ``[1,2;3,4]`` stands for."""
    rows = [row.split(",") for row in notation[1:-1].split(";")]

    def element(text: str) -> object:
        if text in ("true", "false"):
            return text == "true"
        try:
            return float(text)
        except ValueError:
            return text

    return Array(tuple(element(t) for row in rows for t in row), len(rows), len(rows[0]))


def _value(expression: str):
    grammar = parse_grammar(f"{ARRAYS}attr v = {expression}\nLot --> X.", "values.cga")
    return grammar.attrs["v"]


@pytest.mark.parametrize(
    "expression, expected",
    [
        # func_index.html
        ("array[3:-1:1]", _array("[4,3,2]")),
        ("array[[0, 1; 2, 3]]", _array("[1,2;3,4]")),
        ("array2d[1, [0, 2]]", _array("[4,6]")),
        ("array2d[[0, 0, 1], 2]", _array("[3;3;6]")),
        ("array2d[0:2, [0, 2]]", _array("[1,3;4,6;7,9]")),
        ("array[-1]", 0.0),
        ("array[[false, false, true, true, true]]", _array("[3,4,0]")),
        ("array2d[[2, 3], -1:1]", _array("[0,7,8;0,0,0]")),
        ("array2d[[0; 3; 6]]", _array("[1;4;7]")),
        ("array2d[0, [0, 1; 2, 3]]", _array("[1,2,3,0]")),
        ("floatArray()[1:2, 1:3]", _array("[0,0,0;0,0,0]")),
        ('["a", "b"][5] == ""', True),
        ("[true][1]", False),
        # func_array.html
        ('["A", abc, "E"]', _array("[A,B,C,D,E]")),
        ("[a, b; b, a]", _array("[-1,0,1,2;-2,3,3,3;0,1,2,-1;3,3,3,-2]")),
        ('[stringArray(); "x"; "y"]', _array("[x;y]")),
        # arrayTypes.html: element-wise operators
        (".![true, false]", _array("[false,true]")),
        ("false .|| [false; true]", _array("[false;true]")),
        ("[false; true] .&& true", _array("[false;true]")),
        ("1 .+ [1; 2]", _array("[2;3]")),
        (".-[1; 2]", _array("[-1;-2]")),
        ("[1, 2; 3, 4] .- 1", _array("[0,1;2,3]")),
        ("-4 .* [0.25; -0.75; -1]", _array("[-1;3;4]")),
        ("[1, 2; 3, 4] .* [4, 3; 2, 1]", _array("[4,6;6,4]")),
        ("12 ./ [2, 3, 4]", _array("[6,4,3]")),
        ("[8; -5; 0] .% 3", _array("[2;-2;0]")),
        ("abs((7 .% [2.7, -3])[0] - 1.6) < 1e-12 && (7 .% [2.7, -3])[1] == 1", True),
        ("[1, 1; 2, 2] .!= [1, 2; 1, 2]", _array("[false,true;true,false]")),
        ('["a", "b"] .== "b"', _array("[false,true]")),
        ("[1, 2; 3, 4] .> [1, 1; 3, 3]", _array("[false,true;false,true]")),
        ("2 .>= [1, 2, 3]", _array("[true,true,false]")),
        ('["a"; "b"] .> "a"', _array("[false;true]")),
        ('["a", "b"] .+ 1', _array("[a1,b1]")),
        ('[1; 2] .+ ["a"; "b"]', _array("[1a;2b]")),
        ('[true; false] .+ "a"', _array("[truea;falsea]")),
        ("array[array .> 2]", _array("[3,4]")),
        # arrayTypes.html: relational and equality operators on whole arrays, string concatenation
        ("[1, 2] < [1, 3]", True),
        ('["a", "b"] < ["a"; "b"]', False),
        ("[1, 2] <= [1, 2]", True),
        ('["a"; "b"] <= ["a"]', False),
        ("[1, 3] > [1, 2]", True),
        ('["a"; "b"] > ["a"]', True),
        ("[1, 2, 3] >= [1, 2]", True),
        ('["a"; "b"] >= ["a"; "b"]', True),
        ("[1, 2; 9, 9] < [1, 2, 0]", True),
        ("[1, 2] == [1, 2]", True),
        ('["a", "b"] == ["a"; "b"]', False),
        ("[1, 2] != [1; 2]", True),
        ('"array: " + ["element"]', "array: (1)[element]"),
        ('[true, true] + " is an array"', "(2)[true,true] is an array"),
        # func_sortIndices.html, func_sortRowIndices.html
        ('["c", "b", "d", "a"][sortIndices(["c", "b", "d", "a"])]', _array("[a,b,c,d]")),
        ("sortIndices([2, 1, 3, 3, 1])", _array("[1,4,0,2,3]")),
        (
            'sortIndices(["e", "c", "d"; "b", "a", "c"; "d", "a", "d"])',
            _array("[1,2,0;4,3,5;7,6,8]"),
        ),
        ("sortRowIndices(table)", _array("[2,3,1,0]")),
        ("table[sortRowIndices(table), 0:nColumns(table)-1]", _array("[1,3,0;2,1,0;2,1,9;4,0,1]")),
        ("sortRows(table, 1)", _array("[4,0,1;2,1,9;2,1,0;1,3,0]")),
        ("sortRows(table, [1, 0, 2])", _array("[4,0,1;2,1,0;2,1,9;1,3,0]")),
        ('sortRowIndices(["b"; "a"; "b"])', _array("[1,0,2]")),
        # maths (IEEE)
        ("isnan(sqrt(-1))", True),
        ("isnan(ln(-1))", True),
        ("ln(0)", -math.inf),
        ("isnan(asin(2))", True),
        ("exp(1000)", math.inf),
        ("pow(2, 10)", 1024.0),
    ],
)
def test_follows_the_reference(expression, expected):
    assert _value(expression) == expected


@pytest.mark.parametrize(
    "expression, printed",
    [
        # func_array.html
        ("str(abc)", "(3)[B,C,D]"),
        ('str(["A", abc, "E"])', "(5)[A,B,C,D,E]"),
        ("str(a)", "(2x1)\n   -1\n   -2"),
        ("str(b)", "(2x3)\n   0   1   2\n   3   3   3"),
        (
            "str([a, b; b, a])",
            "(4x4)\n   -1   0   1    2\n   -2   3   3    3\n    0   1   2   -1\n    3   3   3   -2",
        ),
        # func_colon.html, "Floating point imprecision": printed with an implicit rounding
        ("str([0.5 : 3])", "(3)[0.5,1.5,2.5]"),
        ("str([4 : 2])", "(0)[]"),
        ("str([0 : 0.15 : 0.5])", "(4)[0,0.15,0.3,0.45]"),
        ("[0 : 0.15 : 0.5][3] == 0.45", False),
        # func_str.html
        ("str(1.69 - 69/100)", "1"),
        ("str(0.1 + 0.2)", "0.3"),
    ],
)
def test_prints_arrays_as_the_reference_does(expression, printed):
    assert _value(expression) == printed


@pytest.mark.parametrize(
    "expression, message",
    [
        ("[1, 2] .+ [1; 2]", "equal dimensions"),
        ("1 .+ 2", "works on arrays"),
        ("[true] .* 2", "needs numbers"),
        ('.-["a"]', "needs numbers"),
        ('[1, 2] < ["a", "b"]', "two arrays of numbers or two of strings"),
        ("[true] < [false]", "two arrays of numbers or two of strings"),
        ("[1] < 2", "two numbers, two strings or two arrays"),
        ("sortRowIndices([true; false])", "sorts numbers or strings"),
    ],
)
def test_element_wise_operators_refuse_in_one_line(expression, message):
    with pytest.raises(GrammarError, match=message):
        _value(expression)


def test_blocks_side_by_side_need_as_many_rows():
    with pytest.raises(GrammarError, match="same number of rows"):
        _value("[a, [1, 2]]")


def test_empty_arrays_keep_their_type():
    with pytest.raises(GrammarError, match="values of one type"):
        _value("[floatArray(), stringArray()]")


def test_nan_reaching_an_operation_is_zero_with_a_warning_at_the_call():
    # cga_changelog 2013.1: the runtime replaces an inf/nan float parameter with zero by default
    model = parse_grammar("Lot --> extrude(ln(0 - 1))", "nan.cga").build(lot=(4, 2))
    assert model.metadata["warnings"] == [
        "nan.cga:1:9: extrude height is nan: replaced by 0, as CityEngine does"
    ]
    with pytest.raises(GrammarError, match="finite number, got nan"):
        parse_grammar("Lot --> extrude(ln(0 - 1))", "nan.grammar").build(lot=(4, 2))


@pytest.mark.parametrize("seed", [0, 7])
def test_seedian_is_the_seed(seed):
    grammar = parse_grammar('Lot --> report("seed", seedian) X.', "seed.cga")
    assert grammar.build(lot=(4, 2), seed=seed).metadata["reports"]["seed"] == float(seed)
