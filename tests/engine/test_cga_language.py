"""CityEngine rule text as written: the issue's examples load, or fail with one line naming
what shapegen does not do; builtins give the reference's documented results."""

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError
from shapegen.grammar import ast, load


@pytest.mark.parametrize(
    "text",
    [
        "Lot --> extrude(2) primitiveQuad()",
        "Lot --> scaleUV(0, 2, 2) rotateUV(0, 45) A",
        "Lot --> softenNormals(30) A",
        "Lot --> shapeL(2, 3) { shape : A | remainder : B }",
        "Lot --> shapeU(2, 3, 3) { shape : A | remainder : NIL }",
        "Lot --> shapeO(1, 1, 1, 1) { shape : A | remainder : B }",
        "Lot --> extrude(3) resetGeometry() A",
        "Lot --> extrude(3) reverseNormals A",
        'version "2019.0"\nLot --> extrude(9)\nstyle Blue\nLot --> extrude(2)',
    ],
)
def test_issue_examples_parse(text):
    grammar = load(text, "rule.cga")
    assert grammar.rules


def test_operation_without_node_is_generic():
    (rule,) = load("Lot --> scaleUV(0, 2, 3) A", "r.cga").rules
    operation = rule.body.items[0]
    assert isinstance(operation, ast.Operation)
    assert operation.name == "scaleUV"
    assert [a.value.value for a in operation.arguments] == [0.0, 2.0, 3.0]


def test_unknown_call_is_a_load_error_with_a_suggestion():
    with pytest.raises(GrammarError, match="did you mean 'primitiveQuad'"):
        load("Lot --> extrude(2) primitiveQuadd()", "r.cga")


def test_undefined_rule_stays_a_leaf():
    assert load("Lot --> extrude(2) Window", "r.cga").rules


def test_only_default_style_is_kept():
    grammar = load("Lot --> A\nstyle Other\nLot --> B", "r.cga")
    assert grammar.styles == ("Other",)
    assert len(grammar.rules) == 1


def test_missing_import_is_one_line_naming_the_paths_tried(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(GrammarError, match='import of "lib.cga": no such file .tried .*lib.cga'):
        load('import lib : "lib.cga"\nLot --> lib.X', "r.cga")


def _value(expression: str):
    grammar = parse_grammar(f"attr v = {expression}\nLot --> X.", "values.cga")
    return grammar.attrs["v"]


@pytest.mark.parametrize(
    "expression, expected",
    [
        ('find("CE_Zero CE_One CE_Two", "CE", 1)', 8.0),  # func_find.html
        ('find("CE_Zero CE_One CE_Two", "asdf", 1)', -1.0),
        ('count("cityengine", "e")', 2.0),  # func_count.html
        ('substring("0123456789", 2, 5)', "234"),  # func_substring.html
        ('substring("0123456789", -20, 5)', "01234"),
        ('substring("0123456789", 5, 0)', ""),
        ('listItem("rule;your;city;", 2)', "city"),  # celib/listItem.html
        ('listSize("rule;your;city;")', 3.0),
        ('isNull("\\ue000")', True),
        ('case 1 > 2 : "a" else : "b"', "b"),
        ("size([1, 2, 3; 4, 5, 6])", 6.0),
        ("[1, 2; 3, 4][1, 0]", 3.0),  # arrayTypes.html
        ("[1, 2, 3][1]", 2.0),
        ("str([1:5])", "[1,2,3,4,5]"),  # colon.html
        ("str([1:2:5])", "[1,3,5]"),
        ("nRows([1; 2])", 2.0),
        ("colorRGBToHex(1, 0, 0)", "#ff0000"),
        ('colorHexToG("#00ff00")', 1.0),
        ("p(1)", True),
        ("p(0)", False),
    ],
)
def test_builtins_follow_the_reference(expression, expected):
    assert _value(expression) == expected


def test_geometry_and_scope_reads():
    grammar = parse_grammar(
        'attr a = 0\nLot --> extrude(2) report("area", geometry.area()) '
        'report("h", scope.elevation) report("n", geometry.nVertices) X.',
        "g.cga",
    )
    reports = grammar.build(lot=(12, 8)).metadata["reports"]
    assert reports["area"] == pytest.approx(2 * 12 * 8 + 2 * 2 * (12 + 8))
    assert reports["n"] == 8.0
    assert reports["h"] == 0.0
