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


def test_unknown_call_is_an_undefined_rule_warning_with_a_suggestion():
    # CityEngine's compiler warns of an undefined rule (cga_changelog: an invocation that is
    # no operation and no rule) and the shape stays a leaf; a .grammar file refuses it
    grammar = load("Lot --> extrude(2) primitiveQuadd()", "r.cga")
    (warning,) = grammar.warnings
    assert "r.cga:1:20" in warning and "did you mean 'primitiveQuad'" in warning
    with pytest.raises(GrammarError, match="did you mean 'primitiveQuad'"):
        load("Lot --> extrude(2) primitiveQuadd()", "r.grammar")


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
        ("str([1:5])", "(5)[1,2,3,4,5]"),  # colon.html
        ("str([1:2:5])", "(3)[1,3,5]"),
        ("nRows([1; 2])", 2.0),
        ("colorRGBToHex(1, 0, 0)", "#ff0000"),
        ('colorHexToG("#00ff00")', 1.0),
        ("p(1)", True),
        ("p(0)", False),
    ],
)
def test_builtins_follow_the_reference(expression, expected):
    assert _value(expression) == expected


def _reports_on_a_box(operations: str) -> dict:
    """The reports of ``operations`` run on the lot extruded by 2 m (a 12 x 8 x 2 box)."""
    text = f"attr a = 0\nLot --> extrude(2) {operations} X."
    return parse_grammar(text, "g.cga").build(lot=(12, 8)).metadata["reports"]


def test_geometry_and_scope_reads():
    reports = _reports_on_a_box(
        'report("area", geometry.area()) report("h", scope.elevation) '
        'report("n", geometry.nVertices)'
    )
    assert reports["area"] == pytest.approx(2 * 12 * 8 + 2 * 2 * (12 + 8))
    assert reports["n"] == 8.0
    assert reports["h"] == 0.0


def test_geometry_selectors_are_read_as_names():
    reports = _reports_on_a_box(
        'report("top", geometry.area(top)) report("slope", geometry.angle(maxSlope))'
    )
    assert reports["top"] == pytest.approx(12 * 8)
    assert reports["slope"] == pytest.approx(90.0)  # the box's walls are vertical


def test_functions_overload_by_arity_even_over_a_builtin():
    grammar = parse_grammar(
        "height(x) = 2 * x\nheight = 5\nsize = 3\n"
        'Lot --> report("one", height(4)) report("none", height) report("mine", size) '
        'report("builtin", size([1, 2])) X.',
        "f.cga",
    )
    assert grammar.build().metadata["reports"] == {
        "one": 8.0,
        "none": 5.0,
        "mine": 3.0,
        "builtin": 2.0,
    }
    with pytest.raises(GrammarError, match="'sin' is a builtin function"):
        load("sin(x) = x\nLot --> X", "f.cga")


def test_scatter_takes_a_block_of_operations():
    (rule, _) = load(
        "Lot --> scatter(surface, 10, uniform) { Tree(2) t(0, 1, 0) }\nTree(h) --> X", "s.cga"
    ).rules
    (branch,) = rule.body.items[0].branches
    assert branch.key is None and len(branch.body.items) == 2
    with pytest.raises(GrammarError, match=r"offset\(\) needs 'key : operations'"):
        load("Lot --> offset(-1) { A }", "s.cga")
    # a split's group of parts is not a block of operations
    assert load("Lot --> split(x) { { ~1 : A }* }", "s.cga").rules


def test_case_values_as_function_arguments():
    assert _value('len(case 1 > 2 : "ab" else : "abc")') == 3.0


@pytest.mark.parametrize("arguments", ["0, scope.xy, 5, 5, 1", "0, scope.xz, '1, '20, 0, '8"])
def test_setup_projection_older_forms(arguments):
    grammar = parse_grammar(f"Lot --> setupProjection({arguments}) projectUV(0) X.", "p.cga")
    model = grammar.build(lot=(12, 8))
    ((name, values), _) = model.surfaces[0].appearance.uv
    assert name == "setupProjection"
    if "'8" in arguments:  # '8: eight times the scope's extent along v (z: 8 m)
        assert values[2:] == pytest.approx((12.0, 20 * 8, 0.0, 8 * 8))
    else:  # (uvSet, axes, width, height, uwFactor): offsets 0
        assert values[2:] == (5.0, 5.0, 0.0, 0.0, 1.0)


def test_comp_sel_and_trim_reads():
    grammar = parse_grammar(
        "Lot --> extrude(3) comp(f) { front : A | side : B | all = C }\n"
        'A --> report("a", comp.sel) X.\nB --> report("b", comp.sel) X.\n'
        'C --> report("c", comp.sel) set(trim.vertical, false) report("t", trim.vertical) X.',
        "c.cga",
    )
    reports = grammar.build().metadata["reports"]
    assert reports["a"] == "front" and reports["b"] == ["side"] * 3 and reports["c"] == "all"
    assert reports["t"] is False


@pytest.mark.parametrize(
    "given, expected",
    [
        ("[4, 5]", (4.0, 5.0)),
        ("4,5,6", (4.0, 5.0, 6.0)),
        ([7, 8], (7.0, 8.0)),
        ((1.5,), (1.5,)),
        ("[]", ()),
    ],
)
def test_set_of_an_array_attr_converts(given, expected):
    grammar = parse_grammar('attr a = [1, 2, 3]\nLot --> report("n", size(a)) X.', "a.cga")
    model = grammar.build(attrs={"a": given})
    assert model.metadata["attrs"]["a"].values == expected
    assert model.metadata["reports"]["n"] == float(len(expected))


@pytest.mark.parametrize(
    "attr, given, message",
    [
        ("a", "1,x", "attr 'a' is an array of numbers, and 'x' is not one of them"),
        ("a", 5, "attr 'a' is an array of numbers, got 5"),
        ("b", "true, maybe", "attr 'b' is an array of booleans, and 'maybe'"),
        ("s", [1, 2], None),
        ("t", [1, 2], "attr 't' is a string, got \\[1, 2\\]"),
    ],
)
def test_set_of_an_array_attr_refuses_in_one_line(attr, given, message):
    grammar = parse_grammar(
        'attr a = [1, 2]\nattr b = [true]\nattr s = ["x"]\nattr t = "q"\nLot --> X.', "a.cga"
    )
    if message is None:  # numbers for strings are written as CGA writes them, as for one string
        assert grammar.build(attrs={attr: given}).metadata["attrs"][attr].values == ("1", "2")
        return
    with pytest.raises(GrammarError, match=message) as caught:
        grammar.build(attrs={attr: given})
    assert "\n" not in str(caught.value)


def test_convert_positions_and_orientations():
    """func_convert's example on a 10 x 10 lot placed at the origin with the world's axes: the
    scope origin after t('0.2, 0, '0.7) is at (2, 0, 7) in world coordinates, and its
    orientation after r(-10, 70, 0) is (-10, 70, 0); back from world to scope is the inverse."""
    grammar = parse_grammar(
        "Init --> extrude(3) t('0.2, 0, '0.7) s('0.5, '1, '0.5) r(-10, 70, 0)\n"
        '  report("p", convert(scope, world, pos, [0, 0, 0]))\n'
        '  report("x", convert(x, scope, world, pos, 0, 0, 0))\n'
        '  report("o", convert(scope, world, orient, [0, 0, 0]))\n'
        '  report("back", convert(world, scope, pos, convert(scope, world, pos, [1, 2, 3])))\n'
        "  X.",
        "c.cga",
    )
    reports = grammar.build(lot=(10, 10)).metadata["reports"]
    assert reports["p"].values == pytest.approx((2.0, 0.0, 7.0))
    assert reports["x"] == pytest.approx(2.0)
    assert reports["o"].values == pytest.approx((-10.0, 70.0, 0.0))
    assert reports["back"].values == pytest.approx((1.0, 2.0, 3.0))
    # the lot's pivot is its first vertex, (0, 0, 10): the scope's origin is 10 m before it
    pivot = parse_grammar(
        'Lot --> report("p", convert(scope, pivot, pos, [0, 0, 0])) X.', "c.cga"
    ).build(lot=(10, 10))
    assert pivot.metadata["reports"]["p"].values == pytest.approx((0.0, 0.0, -10.0))
