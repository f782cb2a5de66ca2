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
from shapegen.errors import GrammarError

ARRAYS = """
const array = [1, 2, 3, 4]
const array2d = [1, 2, 3; 4, 5, 6; 7, 8, 9]
const a = [-1; -2]
const b = [0:2; 3, 3, 3]
const abc = ["B", "C", "D"]
"""


def _value(expression: str):
    grammar = parse_grammar(f"{ARRAYS}attr v = {expression}\nLot --> X.", "values.cga")
    return grammar.attrs["v"]


@pytest.mark.parametrize(
    "expression, expected",
    [
        # func_index.html
        ("str(array[3:-1:1])", "[4,3,2]"),
        ("str(array[[0, 1; 2, 3]])", "[1,2;3,4]"),
        ("str(array2d[1, [0, 2]])", "[4,6]"),
        ("str(array2d[[0, 0, 1], 2])", "[3;3;6]"),
        ("str(array2d[0:2, [0, 2]])", "[1,3;4,6;7,9]"),
        ("array[-1]", 0.0),
        ("str(array[[false, false, true, true, true]])", "[3,4,0]"),
        ("str(array2d[[2, 3], -1:1])", "[0,7,8;0,0,0]"),
        ("str(array2d[[0; 3; 6]])", "[1;4;7]"),
        ("str(array2d[0, [0, 1; 2, 3]])", "[1,2,3,0]"),
        ("str(floatArray()[1:2, 1:3])", "[0,0,0;0,0,0]"),
        ('["a", "b"][5] == ""', True),
        ("[true][1]", False),
        # func_array.html
        ('str(["A", abc, "E"])', "[A,B,C,D,E]"),
        ("str([a, b; b, a])", "[-1,0,1,2;-2,3,3,3;0,1,2,-1;3,3,3,-2]"),
        ('str([stringArray(); "x"; "y"])', "[x;y]"),
        # arrayTypes.html: element-wise operators
        ("str(.![true, false])", "[false,true]"),
        ("str(false .|| [false; true])", "[false;true]"),
        ("str([false; true] .&& true)", "[false;true]"),
        ("str(1 .+ [1; 2])", "[2;3]"),
        ("str(.-[1; 2])", "[-1;-2]"),
        ("str([1, 2; 3, 4] .- 1)", "[0,1;2,3]"),
        ("str(-4 .* [0.25; -0.75; -1])", "[-1;3;4]"),
        ("str([1, 2; 3, 4] .* [4, 3; 2, 1])", "[4,6;6,4]"),
        ("str(12 ./ [2, 3, 4])", "[6,4,3]"),
        ("str([8; -5; 0] .% 3)", "[2;-2;0]"),
        ("abs((7 .% [2.7, -3])[0] - 1.6) < 1e-12 && (7 .% [2.7, -3])[1] == 1", True),
        ("str([1, 1; 2, 2] .!= [1, 2; 1, 2])", "[false,true;true,false]"),
        ('str(["a", "b"] .== "b")', "[false,true]"),
        ("str([1, 2; 3, 4] .> [1, 1; 3, 3])", "[false,true;false,true]"),
        ("str(2 .>= [1, 2, 3])", "[true,true,false]"),
        ('str(["a"; "b"] .> "a")', "[false;true]"),
        ('str(["a", "b"] .+ 1)', "[a1,b1]"),
        ('str([1; 2] .+ ["a"; "b"])', "[1a;2b]"),
        ('str([true; false] .+ "a")', "[truea;falsea]"),
        ("str(array[array .> 2])", "[3,4]"),
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
    "expression, message",
    [
        ("[1, 2] .+ [1; 2]", "equal dimensions"),
        ("1 .+ 2", "works on arrays"),
        ("[true] .* 2", "needs numbers"),
        ('.-["a"]', "needs numbers"),
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


def test_nan_reaching_an_operation_is_an_error_at_the_call():
    grammar = parse_grammar("Lot --> extrude(ln(0 - 1))", "nan.cga")
    with pytest.raises(GrammarError, match="finite number, got nan"):
        grammar.build(lot=(4, 2))


@pytest.mark.parametrize("seed", [0, 7])
def test_seedian_is_the_seed(seed):
    grammar = parse_grammar('Lot --> report("seed", seedian) X.', "seed.cga")
    assert grammar.build(lot=(4, 2), seed=seed).metadata["reports"]["seed"] == float(seed)
