"""Errors of the .grammar language: table-driven (message fragment, bad snippet, line, column).

Each snippet must fail to load with a GrammarError holding a problem whose message contains the
fragment, at the given 1-based line and column; those of EVALUATION_ERRORS load, and fail so
in the interpreter. Files with several problems report them all.
"""

import re

import pytest

import shapegen
from shapegen.errors import GrammarError, ShapegenError, SourceLocation
from shapegen.grammar import check, load, parse

SYNTAX_ERRORS = [
    ("unexpected name 'B'; expected ')' or ','", "A --> extrude(2 B", 1, 17),
    ("unexpected '->'; a rule is written 'Name --> ...'", "A --> B\nC -> D", 2, 3),
    ("unexpected '->'; a rule is written 'Name --> ...'", "A(x) -> B", 1, 6),
    (
        "expected an expression, a floating size (~1), a percentage like '30%', a relative",
        "A --> B(",
        1,
        9,
    ),
    ("unexpected end of file; expected an expression", "attr x =", 1, 9),
    ("unterminated string", 'attr s = "abc', 1, 10),
    ("unterminated '/*' comment", "A --> B /* no end", 1, 9),
    ("unexpected character '$'", "A --> $", 1, 7),
    ("unexpected end of file; expected 'case' or 'else'", "A --> case x > 1 : B", 1, 21),
    ("unexpected end of file; expected a percentage like '30%' or 'else'", "A --> 30% : B", 1, 14),
    ("unexpected number 2", "A --> split(x) { 1 : A  2 : B }", 1, 25),
    ("'}'", "A --> split(x) { 1 : A", 1, 23),
    ("unexpected '{'", "A --> split(z) { 1 : { 3 : C }* }", 1, 22),
    ("unexpected '='; expected a name", "attr = 3", 1, 6),
    (
        "expected a definition (attr, const, function or rule), end of file or '@'",
        "@Range(1, 2)\n3",
        2,
        1,
    ),
    ("@Range stands before no definition", "attr a = 1\n@Range(1, 2)", 2, 2),
    ("unexpected '*'; expected an expression", "f(x) = x +* 2", 1, 11),
    ("unexpected ')'", "A --> B(1,)", 1, 11),
    ("unexpected ':'", "A --> case : B else : C", 1, 12),
    ("unexpected end of file; expected ']'", "A --> [ B C", 1, 12),
]

STRUCTURE_ERRORS = [
    ("unknown axis 'w' in split(); valid: x, y, z", "A --> split(w) { 1 : B }", 1, 13),
    ("a comp selector must be a face index or one of", "A --> comp(f) { '1 : B }", 1, 17),
    ("unknown axes 'xw' in center(); valid: x, y, z, xy, xz, yz, xyz", "A --> center(xw)", 1, 14),
    (
        "unknown pivot 'middle' in r(); valid: scopeOrigin, scopeCenter",
        "A --> r(middle, 0, 0, 0)",
        1,
        9,
    ),
    ("extrude() takes 1 to 2 arguments, got 3", "A --> extrude(1, 2, 3)", 1, 7),
    ("t() takes 3 arguments, got 2", "A --> t(1, 2)", 1, 7),
    ("r() takes 3 to 4 arguments, got 5", "A --> r(1, 2, 3, 4, 5)", 1, 7),
    ("i() takes 1 to 4 arguments, got 0", "A --> i(width=1)", 1, 7),
    ("print() takes at least 1 argument, got 0", "A --> print()", 1, 7),
    ("color() takes 1 to 4 arguments, got 5", "A --> color(1, 1, 1, 1, 1)", 1, 7),
    ("split() needs a { ... } block of branches", "A --> split(x)", 1, 7),
    ("extrude() takes no { ... } block", "A --> extrude(1) { 1 : B }", 1, 18),
    ("'B' is not a CGA operation, and only operations take a", "A --> B(1) { 1 : C }", 1, 12),
    ("a floating size (~) is not allowed in t()", "A --> t(~1, 0, 0)", 1, 9),
    (
        "a relative value (') is not allowed in the arguments of extrude()",
        "A --> extrude('1)",
        1,
        15,
    ),
    ("extrude() takes no keyword arguments (got 'h=')", "A --> extrude(1, h=2)", 1, 18),
    (
        "arguments of the successor 'B' are plain expressions (a relative value (') is not",
        "A --> B('1)",
        1,
        9,
    ),
    ("'=' is only for comp branches; use ':' in a split", "A --> split(x) { 1 = B }", 1, 18),
    ("a comp block cannot be repeated with '*'", "A --> comp(f) { all : B }*", 1, 15),
    ("comp branches cannot be grouped", "A --> comp(f) { { all : B } }", 1, 17),
    ("set() needs an attribute name as its first argument", "A --> set(1, 2)", 1, 11),
    ("positional arguments must come before keyword ones", "@Range(min=1, 2)\nattr x = 1", 1, 1),
]

SEMANTIC_ERRORS = [
    (
        "'primitiveQuadd(...)' is neither a CGA operation nor a rule of this file; did you mean "
        "'primitiveQuad'?",
        "A --> extrude(2) primitiveQuadd()",
        1,
        18,
    ),
    (
        "unknown comp selector 'fron'; valid: front, back, left, right, top, bottom",
        "A --> comp(f) { fron : B }",
        1,
        17,
    ),
    ("unknown component type 'q' in comp(); valid: f, e, v", "A --> comp(q) { all : B }", 1, 12),
    (
        "undefined name 'heigth'; did you mean 'height'?",
        "attr height = 1\nattr x = heigth * 2",
        2,
        10,
    ),
    ("undefined name 'k'", "A(h) --> extrude(k)", 1, 18),
    ("undefined name 'hh'; did you mean 'h'?", "A(h) --> extrude(hh)", 1, 18),
    ("undefined function 'sinn'; did you mean 'sin'?", "attr x = sinn(2)", 1, 10),
    ("undefined function 'widht'; did you mean 'width'?", "width(a) = a\nattr x = widht(2)", 2, 10),
    ("sin() takes 1 argument, got 2", "attr x = sin(1, 2)", 1, 10),
    ("rand() takes 0 to 2 arguments, got 3", "attr x = rand(1, 2, 3)", 1, 10),
    ("pow() takes 2 arguments, got 1", "A --> extrude(pow(2))", 1, 15),
    ("function 'f' takes 2 arguments, got 1", "f(a, b) = a\nattr x = f(1)", 2, 10),
    ("function 'f' takes 1 argument: write f(...)", "f(a) = a\nattr x = f", 2, 10),
    ("'pow' is a builtin function: write pow(...)", "attr x = pow", 1, 10),
    ("'h' is not a function", "attr h = 1\nattr x = h(2)", 2, 10),
    ("rule 'B' takes 2 arguments, got 1", "A --> B(1)\nB(p, q) --> C", 1, 7),
    ("rule 'B' takes 0 arguments, got 1", "A --> split(x) { 1 : B(1) }\nB --> C", 1, 22),
    (
        "duplicate definition of 'h' (first defined at <string>:1:6)",
        "attr h = 1\nconst h = 2",
        2,
        7,
    ),
    ("duplicate definition of 'f'", "f(a) = a\nf(b) = 2", 2, 1),
    ("duplicate rule 'A' (first defined at <string>:1:1)", "A --> B\nA --> C", 2, 1),
    ("'sin' is a builtin function; choose another name", "sin(x) = x", 1, 1),
    ("'extrude' is an operation; a rule cannot use its name", "extrude --> A", 1, 1),
    ("'split' is an operation: write split(...)", "A --> split", 1, 7),
    ("parameter 'a' is listed twice", "f(a, a) = a", 1, 6),
    (
        "set() of undefined attr 'heigt'; did you mean 'height'?",
        "attr height = 1\nA --> set(heigt, 2)",
        2,
        7,
    ),
    ("set() of undefined attr 'densty'; did you mean 'density'?", "A --> set(densty, 2)", 1, 7),
    ("set() needs an attr, and 'k' is a const", "const k = 1\nA --> set(k, 2)", 2, 7),
    ("unknown shape attribute 'scope.sw'; did you mean 'scope.s", "attr x = scope.sw", 1, 10),
    ("unknown shape attribute 'scope.q'", "attr x = scope.q", 1, 10),
    ("undefined name 'shape.q'", "attr x = shape.q", 1, 10),
    ("geometry.area() takes 0 to 1 arguments, got 2", "attr x = geometry.area(1, 2)", 1, 10),
    ("'a' depends on itself: a -> b -> a", "attr a = b\nattr b = a + 1", 1, 6),
    ("'c' depends on itself: c -> c", "const c = c * 2", 1, 7),
    (
        "the stochastic percentages add up to 110% (at most 100%)",
        "A --> 60% : B 50% : C else : D",
        1,
        7,
    ),
    ("the stochastic percentages add up to 120%", "f = 60% : 1 60% : 2 else : 3", 1, 5),
    ("unknown annotation '@Rnage'; did you mean 'Range'?", "@Rnage(1, 2)\nattr x = 1", 1, 2),
    ("unknown annotation '@Startrule'; did you mean 'StartRule'?", "@Startrule\nA --> B", 1, 2),
    ("@Free attr 'x' needs a @Range(min=..., max=...)", "@Free\nattr x = 1", 1, 2),
    ("@Range min 5 is greater than its max 1", "@Range(min=5, max=1)\nattr x = 3", 1, 2),
    ("the value 12 of 'x' is outside its @Range [0, 10]", "@Range(0, 10)\nattr x = 12", 2, 10),
    (
        "the value -1 of 'x' is outside its @Range [0, 2]",
        "const lo = 0\n@Range(lo, lo + 2)\nattr x = -1",
        3,
        10,
    ),
    ("@Range needs both a min and a max", "@Range(min=1)\nattr x = 3", 1, 2),
    ("@Range has no argument 'maximum'", "@Range(min=1, maximum=3)\nattr x = 2", 1, 15),
    ("@Description takes 1 argument, got 2", '@Description("a", "b")\nattr x = 2', 1, 2),
    ("a @Range bound must be a number", "@Range(true, 2)\nattr x = 1", 1, 8),
    ("a @Range bound must be a number", '@Free @Range("a", 2)\nattr x = 1', 1, 14),
    (
        "the @Range bounds of @Free attr 'x' must be constants",
        "@Free @Range(0, scope.sx)\nattr x = 1",
        1,
        17,
    ),
    ("@Free attr 'x' must have a numeric value", '@Free @Range(0, 1)\nattr x = "a"', 2, 10),
    ("@StartRule belongs on a rule, not on an attr", "@StartRule\nattr x = 1", 1, 2),
    ("@Free belongs on an attr, not on a rule", "@Free @Range(0, 1)\nA --> B", 1, 2),
    ("@Range belongs on an attr, not on a const", "@Range(0, 1)\nconst c = 0.5", 1, 2),
    (
        "more than one @StartRule (the first is 'A'",
        "@StartRule\nA --> B\n@StartRule\nC --> D",
        3,
        2,
    ),
    ("the start rule 'A' cannot take parameters", "@StartRule\nA(h) --> B", 2, 1),
    ("@Lot belongs on the start rule", "@StartRule\nA --> B\n@Lot(1, 2)\nC --> D", 3, 2),
    ("@Lot sizes must be positive numbers (metres)", "@StartRule @Lot(0, 2)\nA --> B", 1, 17),
    ("@Lot sizes must be at most 1e+09 m", "@StartRule @Lot(1e300, 2)\nA --> B", 1, 17),
    (
        "@Structure belongs on the start rule",
        '@StartRule\nA --> B\n@Structure("cable")\nB --> i("box")',
        3,
        2,
    ),
    ("@Structure belongs on a rule, not on an attr", '@Structure("cable")\nattr x = 1', 1, 2),
    (
        "@Structure names a structure: a string",
        "@StartRule @Structure(3)\nA --> B",
        1,
        23,
    ),
    ("@Lot takes 2 arguments, got 1", "@StartRule @Lot(3)\nA --> B", 1, 13),
    ("'@Hidden' is given twice", "@Hidden @Hidden\nattr x = 1", 1, 10),
    ("@Description takes 1 argument, got 0", "@Description\nattr x = 1", 1, 2),
    ("undefined name 'nope'", "@Description(nope)\nattr x = 1", 1, 14),
]

# Found by the interpreter: the snippet is good .grammar text (it loads), and reading its
# inserts or deriving it stops at the node that fails.
EVALUATION_ERRORS = [
    ("division by zero", "Lot --> extrude(1)\n  split(x) { 1 / (scope.sx - 10) : A }", 2, 16),
    ("needs numbers", 'Lot --> extrude("a" * 2)', 1, 21),
    ("unknown primitive", 'Lot --> extrude(1) i("nosuchthing")', 1, 20),
    ("no parameter 'size'", 'Lot --> extrude(1) i("box", size = 2)', 1, 29),
    ("already 3D", "Lot --> extrude(1) extrude(2)", 1, 20),
    ("must be a finite number, got nan", "Lot --> extrude(1) s(sqrt(0 - 1), 1, 1)", 1, 20),
    ("split size must be a number", 'Lot --> extrude(1) split(x) { "wide" : A }', 1, 31),
    ("must be a number, got a boolean", "Lot --> extrude(1) s(1, true, 1)", 1, 20),
]

ALL_ERRORS = SYNTAX_ERRORS + STRUCTURE_ERRORS + SEMANTIC_ERRORS


def _problem_with(error: GrammarError, fragment: str):
    matches = [(loc, msg) for loc, msg in error.problems if fragment in msg]
    assert matches, f"no problem contains {fragment!r}; got {error.problems}"
    return matches[0]


@pytest.mark.parametrize(
    "fragment, snippet, line, column", ALL_ERRORS, ids=[case[0][:50] for case in ALL_ERRORS]
)
def test_error_message_and_place(fragment, snippet, line, column):
    with pytest.raises(GrammarError) as caught:
        load(snippet, "<string>")
    location, message = _problem_with(caught.value, fragment)
    assert (location.line, location.column) == (line, column), message
    assert location.file == "<string>"


@pytest.mark.parametrize(
    "fragment, snippet, line, column",
    SYNTAX_ERRORS + STRUCTURE_ERRORS,
    ids=[case[0][:50] for case in SYNTAX_ERRORS + STRUCTURE_ERRORS],
)
def test_parse_alone_reports_syntax_and_structure(fragment, snippet, line, column):
    with pytest.raises(GrammarError) as caught:
        parse(snippet)
    _problem_with(caught.value, fragment)


@pytest.mark.parametrize(
    "fragment, snippet, line, column",
    SEMANTIC_ERRORS,
    ids=[case[0][:50] for case in SEMANTIC_ERRORS],
)
def test_semantic_problems_come_from_check(fragment, snippet, line, column):
    grammar = parse(snippet)  # the syntax is fine
    with pytest.raises(GrammarError) as caught:
        check(grammar)
    _problem_with(caught.value, fragment)


@pytest.mark.parametrize(
    "fragment, snippet, line, column",
    EVALUATION_ERRORS,
    ids=[case[0][:50] for case in EVALUATION_ERRORS],
)
def test_evaluation_errors_point_at_the_node(fragment, snippet, line, column):
    load(snippet, "<string>")  # the language is fine: the error comes from the interpreter
    with pytest.raises(GrammarError, match=re.escape(fragment)) as caught:
        shapegen.parse_grammar(snippet).build()
    assert (caught.value.location.line, caught.value.location.column) == (line, column)
    assert "^" in str(caught.value)  # the caret under the source line


def test_rendering_has_place_source_line_and_caret():
    with pytest.raises(GrammarError) as caught:
        load("attr height = 1\nattr x = heigth * 2\n", "wall.grammar")
    error = caught.value
    assert isinstance(error, ShapegenError)
    assert (error.line, error.column) == (2, 10)
    assert error.location == SourceLocation("wall.grammar", 2, 10)
    assert str(error).splitlines() == [
        "wall.grammar:2:10: undefined name 'heigth'; did you mean 'height'?",
        "    attr x = heigth * 2",
        "             ^",
    ]


def test_several_problems_reported_together_in_file_order():
    text = "\n".join(
        [
            "attr height = 1",
            "attr x = heigth",  # 2: undefined name
            "@Free",  # 3: @Free without @Range
            "attr y = 2",
            "A --> split(w) { 1 : B(1) }",  # 5: unknown axis (parser) and rule arity (checks)
            "B --> extrude(sin(1, 2))",  # 6: builtin arity
        ]
    )
    with pytest.raises(GrammarError) as caught:
        load(text, "many.grammar")
    places = [(loc.line, loc.column) for loc, _ in caught.value.problems]
    assert places == [(2, 10), (3, 2), (5, 13), (5, 22), (6, 15)]
    rendered = str(caught.value)
    for line_number, _ in places:
        assert f"many.grammar:{line_number}:" in rendered
    assert rendered.count("^") == len(places)


def test_syntax_errors_in_several_definitions_reported_together():
    text = "A --> extrude(1\nattr ok = 1\nB -> C\nattr x = (2\n"
    with pytest.raises(GrammarError) as caught:
        load(text)
    lines = [loc.line for loc, _ in caught.value.problems]
    assert lines == [2, 3, 4]


VALID = [
    # A successor without a rule is a leaf; 'Name.' is an explicit leaf.
    "A --> Window(2) Door. B\nB --> C",
    "A --> B.\nB --> C",
    # The reserved attrs need no declaration, and may be declared.
    "A --> set(density, 2000) set(fixed, true) set(structural, false) extrude(density / 1000)",
    "attr density = 1800\nA --> set(density, density * 1.1) B",
    # Definitions may refer forward; functions may recurse; parameters shadow attrs.
    "attr a = b + 1\nattr b = 2\nA --> extrude(a)",
    "f(n) = case n <= 0 : 0 else : f(n - 1) + 1\nA --> extrude(f(3))",
    "attr h = 1\nA(h) --> extrude(h)",
    "attr a = g(0)\ng(x) = case x > 0 : a else : 1",
    # Builtins with optional arguments; CGA's interface annotations are accepted.
    'attr r = rand() + rand(1, 2)\n@Order(1) @Group("g") @Enum(1, 2, 3) @Angle\nattr q = 2',
    # comp with face indices and the CGA selector names.
    "A --> extrude(1) comp(f) { 0 : B | vertical : C | horizontal : D }",
    '@StartRule @Lot(4, 2) @Hidden @Description("start")\nA --> B',
    "@Free @Range(min=0, max=2 * 1.5)\nattr t = 1.5",
]


@pytest.mark.parametrize("text", VALID)
def test_valid_files_load(text):
    load(text)


def test_a_problem_met_twice_is_reported_once():
    # At the end of the file the parser's error recovery meets the same problem twice.
    with pytest.raises(GrammarError) as caught:
        load("@StartRule\nLot --> extrude(\n")
    assert len(caught.value.problems) == 1
    assert str(caught.value).count("unexpected end of file") == 1
