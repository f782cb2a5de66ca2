"""The builtin functions of CGA's reference and its utility library (celib), each evaluated on a
value the reference gives or that follows from its description, and the geometry functions on
shapes whose answers follow from their coordinates."""

from __future__ import annotations

import math

import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.engine.expressions.arrays import Array, format_value

# (entry, expression, value): a number compares within 1e-9, an array by its printed text
CASES = [
    ("abs", "abs(-2.5)", 2.5),
    ("acos", "acos(0.5)", 60.0),
    ("asin", "asin(0.5)", 30.0),
    ("atan", "atan(1)", 45.0),
    ("atan2", "atan2(1, -1)", 135.0),
    ("ceil", "ceil(-1.2)", -1.0),
    ("cos", "cos(60)", 0.5),
    ("exp", "exp(0)", 1.0),
    ("floor", "floor(-1.5)", -2.0),
    ("isinf", "isinf(-1/0)", True),
    ("isnan", "isnan(ln(-1))", True),
    ("ln", "ln(exp(2))", 2.0),
    ("log10", "log10(1000)", 3.0),
    ("pow", "pow(2, 10)", 1024.0),
    ("rint", "rint(-2.6)", -3.0),
    ("sin", "sin(30)", 0.5),
    ("sqrt", "sqrt(16)", 4.0),
    ("tan", "tan(45)", 1.0),
    # func_bool: strings are false for "f", "false", "0"... and true otherwise
    ("bool", 'bool("0.0")', False),
    (
        "boolArray",
        'boolArray(["true", "1", "0", "f", "false", "schwiizer nati"])',
        "(6)[true,true,false,false,false,true]",
    ),  # noqa: E501
    ("float", 'float("001.5")', 1.5),
    ("floatArray", 'floatArray(["1", "2.5"])', "(2)[1,2.5]"),
    ("isNull", 'isNull(["CityEngine", "\\ue000"])', "(2)[false,true]"),
    ("str", "str(1.69 - 69/100)", "1"),
    ("stringArray", "stringArray([1, 2])", "(2)[1,2]"),
    ("count", 'count("cityengine", "e")', 2.0),
    ("find", 'find("CE_Zero CE_One CE_Two", "CE", 1)', 8.0),
    ("len", 'len("cityengine")', 10.0),
    ("splitString", 'splitString(".b.", ".")', "(3)[,b,]"),
    ("splitString", 'splitString("abc", "")', "(5)[,a,b,c,]"),
    ("splitString", 'splitString("a b  c", "$\\\\s+")', "(3)[a,b,c]"),
    ("substring", 'substring("0123456789", -20, 5)', "01234"),
    ("array", "[-1; -2]", "(2x1)\n   -1\n   -2"),
    ("colon", "[4 : -1 : 2]", "(3)[4,3,2]"),
    ("index", "[1, 2, 3; 4, 5, 6][1, 2]", 6.0),
    ("findFirst", "findFirst([1, 2, 3; 4, 5, 6], 4, 0)", 3.0),
    ("nColumns", "nColumns([1, 2, 3; 4, 5, 6])", 3.0),
    ("nRows", "nRows([1, 2, 3; 4, 5, 6])", 2.0),
    ("setElems", "setElems([0, 0, 0, 0, 0, 0], [1, 3, 5], [1 : 3])", "(6)[0,1,0,2,0,3]"),
    ("size", "size([1, 2; 3, 4])", 4.0),
    ("sortIndices", "sortIndices([3, 1, 2])", "(3)[1,2,0]"),
    ("sortRowIndices", "sortRowIndices([2, 1; 1, 2])", "(2)[1,0]"),
    ("sum", "sum([true, false, true])", 2.0),
    ("sum", 'sum(["a", "b", "c"])', "abc"),
    ("transpose", "transpose([1, 2; 3, 4])", "(2x2)\n   1   3\n   2   4"),
    ("simpleTypes", '1 + 2 * 3 % 4 == 3 && !false && "a" + 1 == "a1"', True),
    ("arrayTypes", "[1, 2] .+ [3, 4]", "(2)[4,6]"),
    ("findLast", 'findLast("rule your city with cityengine", "city")', 20.0),
    ("getPrefix", 'getPrefix("myTexture.has.prefix.jpg", ".")', "myTexture"),
    ("getRange", 'getRange("rule your city with cityengine", "y", "city")', "our city with "),
    ("getRange", 'getRange("CityEngine", "CityEn", "tyEngine")', ""),
    ("getSuffix", 'getSuffix("rule your city with cityengine", "city")', "engine"),
    ("replace", 'replace("myTexture.#.jpg", "#", "1")', "myTexture.1.jpg"),
    ("listAdd", 'listAdd("rule;your;", "city;")', "rule;your;city;"),
    ("listClean", 'listClean(";;cityengine;;;rules")', "cityengine;rules;"),
    ("listCount", 'listCount("rule;your;city;", "*y*")', 2.0),
    ("listFirst", 'listFirst("rule;your;city;")', "rule"),
    ("listFromArray", "listFromArray([true, false])", "true;false;"),
    ("listIndex", 'listIndex("rule;your;city;", "*y")', 2.0),
    ("listItem", 'listItem("rule;your;city;", 2)', "city"),
    ("listLast", 'listLast("rule;your;city;")', "city"),
    ("listRandom", 'listRandom("only;")', "only"),
    ("listRange", 'listRange("rule;your;city;with;cityengine;", 0, 3)', "rule;your;city;"),
    ("listRemove", 'listRemove("floor_1;floor_2;floor_3;", "*_2")', "floor_1;floor_3;"),
    (
        "listRemoveAll",
        'listRemoveAll("rule;your;designs;and;your;cities;", "*u*")',
        "designs;and;cities;",
    ),  # noqa: E501
    ("listRetainAll", 'listRetainAll("floor;floor_1;floor_2;", "*_*")', "floor_1;floor_2;"),
    ("listSize", 'listSize("cityengine;rules;")', 2.0),
    ("listTerminate", 'listTerminate("a;b")', "a;b;"),
    ("listToArray", 'listToArray("rule;your;city;")', "(3)[rule,your,city]"),
    ("fileBasename", 'fileBasename("assets/obj/mygeometry.01.obj")', "mygeometry.01"),
    ("fileDirectory", 'fileDirectory("assets/obj/mygeometry.01.obj")', "assets/obj/"),
    ("fileExtension", 'fileExtension("assets/obj/mygeometry.01.obj")', "obj"),
    ("fileName", 'fileName("assets/obj/mygeometry.01.obj")', "mygeometry.01.obj"),
    ("clamp", "clamp(-11, -10, 10)", -10.0),
    ("max", "max(2, 3)", 3.0),
    ("min", 'min("b", "a")', "a"),
    ("colorHexToR", 'colorHexToR("#ff0000")', 1.0),
    ("colorHexToG", 'colorHexToG("#00ff00")', 1.0),
    ("colorHexToB", 'colorHexToB("#0000ff")', 1.0),
    ("colorHexToO", 'colorHexToO("#ff000080")', 128 / 255),
    ("colorHexToH", 'colorHexToH("#00ff00")', 120.0),
    ("colorHexToS", 'colorHexToS("#ff8080")', 127 / 255),
    ("colorHexToV", 'colorHexToV("#808080")', 128 / 255),
    ("colorHSVToHex", "colorHSVToHex(240, 1, 1)", "#0000ff"),
    ("colorHSVOToHex", "colorHSVOToHex(0, 0, 1, 0)", "#ffffff00"),
    ("colorRGBToHex", "colorRGBToHex(1, 0.5, 0)", "#ff8000"),
    ("colorRGBOToHex", "colorRGBOToHex(0, 0, 0, 1)", "#000000ff"),
    ("colorRamp", 'colorRamp("yellowToRed", 1)', "#ff0000"),
    ("rand", "rand(2, 2)", 2.0),
    ("p", "p(1)", True),
]

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_function_values": tuple(sorted({f"func:{entry}" for entry, _, _ in CASES})),
    "test_geometry_functions_on_a_box": tuple(
        f"func:geometry.{name}"
        for name in (
            "area",
            "angle",
            "boundaryLength",
            "du",
            "dv",
            "height",
            "isClosedSurface",
            "isConcave",
            "isPlanar",
            "isRectangular",
            "nEdges",
            "nFaces",
            "nHoles",
            "nVertices",
            "volume",
        )
    ),
    "test_file_functions_search_the_project": (
        "func:fileExists",
        "func:fileSearch",
        "func:filesSearch",
        "func:fileRandom",
    ),
    "test_the_print_function_returns_its_value": ("func:print",),
}


def _value(expression: str, lot=(12.0, 8.0), before: str = ""):
    grammar = parse_grammar(f'@StartRule\nLot --> {before}report("v", {expression}) X.', "f.cga")
    return grammar.build(lot=lot).metadata["reports"]["v"]


@pytest.mark.parametrize(("entry", "expression", "expected"), CASES)
def test_function_values(entry, expression, expected):
    value = _value(expression)
    if isinstance(value, Array):
        assert format_value(value) == expected
    elif type(expected) is float:
        assert type(value) is float and math.isclose(value, expected, abs_tol=1e-9)
    else:
        assert value == expected


@pytest.mark.parametrize(
    ("before", "expression", "expected"),
    [
        ("extrude(3) ", "geometry.area", 2 * (96 + 36 + 24)),
        ("extrude(3) ", "geometry.area(top)", 96),
        ("extrude(3) ", "geometry.volume", 288),
        ("extrude(3) ", "geometry.height", 3),
        ("extrude(3) ", "geometry.nVertices", 8),
        ("extrude(3) ", "geometry.nFaces", 6),
        ("extrude(3) ", "geometry.nEdges", 12),
        ("extrude(3) ", "geometry.nHoles", 0),
        ("extrude(3) ", "geometry.isClosedSurface", True),
        ("", "geometry.isClosedSurface", False),  # the lot: its edges have one face each
        ("extrude(3) ", "geometry.isConcave", False),
        ("extrude(3) ", "geometry.isPlanar(0.25)", True),
        ("extrude(3) ", "geometry.isRectangular(0)", True),
        ("extrude(3) ", "geometry.boundaryLength", 0),  # closed: no boundary edge
        ("", "geometry.boundaryLength", 40),
        ("extrude(3) ", "geometry.angle(maxSlope)", 90),  # the sides stand vertical
        ("", "geometry.angle(maxSlope)", 0),
        ("extrude(3) comp(f) { front : ", "geometry.du(0, unitSpace)", 12),
        ("extrude(3) comp(f) { front : ", "geometry.dv(0, unitSpace)", 3),
    ],
)
def test_geometry_functions_on_a_box(before, expression, expected):
    tail = " }" if "{" in before else ""
    grammar = parse_grammar(
        f'@StartRule\nLot --> {before}report("v", {expression}) X.{tail}', "g.cga"
    )
    value = grammar.build(lot=(12.0, 8.0)).metadata["reports"]["v"]
    assert value == expected if type(expected) is bool else math.isclose(value, expected)


def test_an_l_shaped_lot_is_concave():
    lot = [(0, 8), (12, 8), (12, 4), (6, 4), (6, 0), (0, 0)]
    assert _value("geometry.isConcave", lot=lot) is True


def test_file_functions_search_the_project(tmp_path):
    # func_fileSearch: a sorted string list of the project's files matching the query (relative
    # to the assets folder, the project or the workspace; $ starts a regular expression);
    # filesSearch the same as an array; fileRandom one of them
    for name in ("b.png", "a.png", "c.jpg"):
        (tmp_path / "assets" / name).parent.mkdir(exist_ok=True)
        (tmp_path / "assets" / name).write_bytes(b"")
    (tmp_path / "rules").mkdir()
    rule = tmp_path / "rules" / "files.cga"
    rule.write_text(
        "@StartRule\n"
        'Lot --> report("one", fileSearch("assets/*.png")) '
        'report("all", listSize(fileSearch("*.png"))) '
        'report("array", filesSearch("assets/*.png")) '
        'report("exists", fileExists("assets/c.jpg")) report("no", fileExists("assets/d.jpg")) '
        'report("random", fileRandom("assets/*.jpg")) report("regex", fileSearch("$[ab].png")) '
        'report("and", fileSearch("*.png b*")) X.\n'
    )
    reports = load_grammar(rule).build(lot=(4.0, 4.0)).metadata["reports"]
    assert reports["one"] == "/assets/a.png;/assets/b.png;"
    assert reports["all"] == 2.0
    assert format_value(reports["array"]) == "(2)[/assets/a.png,/assets/b.png]"
    assert (reports["exists"], reports["no"]) == (True, False)
    assert reports["random"] == "/assets/c.jpg"
    assert reports["regex"] == "/assets/a.png;/assets/b.png;"  # relative to the assets folder
    assert reports["and"] == "/assets/b.png;"  # whitespace is AND


def test_the_print_function_returns_its_value(capsys):
    # func_print: prints the value and returns it
    assert _value('print("a" + 1)') == "a1"
    assert capsys.readouterr().out == "a1\n"
