"""Parsing every construct of the .grammar language into the expected AST nodes.

Expected trees are written out by hand from the language reference (docs/grammar.md); node
equality ignores source locations, which are checked separately.
"""

from pathlib import Path

import pytest

from shapegen.errors import SourceLocation
from shapegen.grammar import ast, load, parse

EXAMPLES = Path(__file__).parent / "examples"


def N(value):
    return ast.Number(float(value))


def Nm(name):
    return ast.Name(name)


def Seq(*items):
    return ast.Sequence(tuple(items))


def S(name, *args, leaf=False):
    return ast.Successor(name, tuple(args), leaf=leaf)


def B(op, left, right):
    return ast.Binary(op, left, right)


def C(value, relative=False):
    return ast.Coordinate(value, relative)


def Group(*parts, repeat=False):
    return ast.SplitGroup(tuple(parts), repeat=repeat)


def Split(axis, *parts, repeat=False):
    return ast.Split(axis, Group(*parts, repeat=repeat))


def Entry(size, mode, body):
    return ast.SplitEntry(size, mode, body)


def body_of(text):
    """The body of the rule ``A --> text``."""
    return parse(f"A --> {text}").rules[0].body


def expression_of(text):
    """The value of ``attr x = text``."""
    return parse(f"attr x = {text}").attrs[0].value


# --------------------------------------------------------------------------------------------
# Expressions

EXPRESSIONS = [
    ("3", N(3)),
    ("0.25", N(0.25)),
    (".5", N(0.5)),
    ("1e3", N(1000)),
    ("2.5E-1", N(0.25)),
    ('"abc"', ast.String("abc")),
    (r'"a\"b\\c\nd"', ast.String('a"b\\c\nd')),
    ("true", ast.Boolean(True)),
    ("false", ast.Boolean(False)),
    ("height", Nm("height")),
    ("-2", ast.Unary("-", N(2))),
    ("!flag", ast.Unary("!", Nm("flag"))),
    ("+a", ast.Unary("+", Nm("a"))),
    ("1 + 2 * 3", B("+", N(1), B("*", N(2), N(3)))),
    ("(1 + 2) * 3", B("*", B("+", N(1), N(2)), N(3))),
    ("1 - 2 - 3", B("-", B("-", N(1), N(2)), N(3))),
    ("8 / 4 / 2", B("/", B("/", N(8), N(4)), N(2))),
    ("7 % 3", B("%", N(7), N(3))),
    ("-2 * 3", B("*", ast.Unary("-", N(2)), N(3))),
    ("a || b && c", B("||", Nm("a"), B("&&", Nm("b"), Nm("c")))),
    ("a && b || c", B("||", B("&&", Nm("a"), Nm("b")), Nm("c"))),
    ("1 < 2 == true", B("==", B("<", N(1), N(2)), ast.Boolean(True))),
    ("a != b", B("!=", Nm("a"), Nm("b"))),
    ("a <= b", B("<=", Nm("a"), Nm("b"))),
    ("a >= b", B(">=", Nm("a"), Nm("b"))),
    ("a > b + 1", B(">", Nm("a"), B("+", Nm("b"), N(1)))),
    ("!a == b", B("==", ast.Unary("!", Nm("a")), Nm("b"))),
    ('"w" + 3', B("+", ast.String("w"), N(3))),
    ("sin(30)", ast.Call("sin", (N(30),))),
    ("rand()", ast.Call("rand", ())),
    ("max(1, min(2, 3))", ast.Call("max", (N(1), ast.Call("min", (N(2), N(3)))))),
    ("scope.sx", ast.ShapeAttribute("scope", "sx")),
    ("split.index + 1", B("+", ast.ShapeAttribute("split", "index"), N(1))),
    ("comp.total", ast.ShapeAttribute("comp", "total")),
]


@pytest.mark.parametrize("text, expected", EXPRESSIONS, ids=[t for t, _ in EXPRESSIONS])
def test_expression(text, expected):
    assert expression_of(text) == expected


# --------------------------------------------------------------------------------------------
# Rule bodies and operations

BODIES = [
    ("B", Seq(S("B"))),
    ("B C", Seq(S("B"), S("C"))),
    ("B(1, h)", Seq(S("B", N(1), Nm("h")))),
    ("B.", Seq(S("B", leaf=True))),
    ("NIL", Seq(ast.Nil())),
    ("extrude(3)", Seq(ast.Extrude(N(3)))),
    ("extrude(h * 2) B", Seq(ast.Extrude(B("*", Nm("h"), N(2))), S("B"))),
    (
        "split(x) { 2 : B | ~1 : C | '0.5 : D }",
        Seq(
            Split(
                "x",
                Entry(N(2), "absolute", Seq(S("B"))),
                Entry(N(1), "floating", Seq(S("C"))),
                Entry(N(0.5), "relative", Seq(S("D"))),
            )
        ),
    ),
    (
        "split(y) { 2 : X | 1 : Y }*",
        Seq(
            Split(
                "y",
                Entry(N(2), "absolute", Seq(S("X"))),
                Entry(N(1), "absolute", Seq(S("Y"))),
                repeat=True,
            )
        ),
    ),
    (
        "split(z) { 1 : A | { ~2 : B | { 3 : C }* }* | 1 : D }",
        Seq(
            Split(
                "z",
                Entry(N(1), "absolute", Seq(S("A"))),
                Group(
                    Entry(N(2), "floating", Seq(S("B"))),
                    Group(Entry(N(3), "absolute", Seq(S("C"))), repeat=True),
                    repeat=True,
                ),
                Entry(N(1), "absolute", Seq(S("D"))),
            )
        ),
    ),
    (
        "split(x) { ~scope.sx / 3 : A extrude(1) B }",
        Seq(
            Split(
                "x",
                Entry(
                    B("/", ast.ShapeAttribute("scope", "sx"), N(3)),
                    "floating",
                    Seq(S("A"), ast.Extrude(N(1)), S("B")),
                ),
            )
        ),
    ),
    (
        "comp(f) { front : A | side : B | top : NIL | all : C. }",
        Seq(
            ast.Comp(
                "f",
                (
                    ast.CompBranch("front", Seq(S("A"))),
                    ast.CompBranch("side", Seq(S("B"))),
                    ast.CompBranch("top", Seq(ast.Nil())),
                    ast.CompBranch("all", Seq(S("C", leaf=True))),
                ),
            )
        ),
    ),
    (
        "comp(f) { back : A | left : B | right : C | bottom : D | 0 : E | side = F }",
        Seq(
            ast.Comp(
                "f",
                (
                    ast.CompBranch("back", Seq(S("A"))),
                    ast.CompBranch("left", Seq(S("B"))),
                    ast.CompBranch("right", Seq(S("C"))),
                    ast.CompBranch("bottom", Seq(S("D"))),
                    ast.CompBranch("0", Seq(S("E"))),
                    ast.CompBranch("side", Seq(S("F")), merge=True),
                ),
            )
        ),
    ),
    ("t(1, '0.5, -2)", Seq(ast.Translate(C(N(1)), C(N(0.5), True), C(ast.Unary("-", N(2)))))),
    ("s('1, 2, '0.5)", Seq(ast.Scale(C(N(1), True), C(N(2)), C(N(0.5), True)))),
    ("r(0, 90, 0)", Seq(ast.Rotate(N(0), N(90), N(0)))),
    ("r(scopeCenter, 0, 45, 0)", Seq(ast.Rotate(N(0), N(45), N(0), pivot="center"))),
    ("r(scopeOrigin, 10, 0, 0)", Seq(ast.Rotate(N(10), N(0), N(0), pivot="origin"))),
    ("center(xz)", Seq(ast.Center("xz"))),
    ("center(xyz) center(y)", Seq(ast.Center("xyz"), ast.Center("y"))),
    (
        "[ t(0, 1, 0) B ] C",
        Seq(ast.Push(Seq(ast.Translate(C(N(0)), C(N(1)), C(N(0))), S("B"))), S("C")),
    ),
    ('label("column")', Seq(ast.Label(ast.String("column")))),
    ("set(density, 1800)", Seq(ast.Set("density", N(1800)))),
    ('i("box")', Seq(ast.Insert(ast.String("box")))),
    (
        'i("arch", thickness=0.3, style="gothic")',
        Seq(
            ast.Insert(
                ast.String("arch"),
                (
                    ast.Keyword("thickness", N(0.3)),
                    ast.Keyword("style", ast.String("gothic")),
                ),
            )
        ),
    ),
    ('print("h", h)', Seq(ast.Print((ast.String("h"), Nm("h"))))),
    (
        'report("area", scope.sx)',
        Seq(ast.Report(ast.String("area"), ast.ShapeAttribute("scope", "sx"))),
    ),
    (
        "case h > 2 : B case h > 1 : C else : D",
        ast.ConditionalBody(
            (
                ast.ConditionalBranch(B(">", Nm("h"), N(2)), Seq(S("B"))),
                ast.ConditionalBranch(B(">", Nm("h"), N(1)), Seq(S("C"))),
            ),
            Seq(S("D")),
        ),
    ),
    (
        "case a : case b : X else : Y else : Z",
        ast.ConditionalBody(
            (
                ast.ConditionalBranch(
                    Nm("a"),
                    ast.ConditionalBody(
                        (ast.ConditionalBranch(Nm("b"), Seq(S("X"))),), Seq(S("Y"))
                    ),
                ),
            ),
            Seq(S("Z")),
        ),
    ),
    (
        "30% : B 20.5% : C else : D",
        ast.StochasticBody(
            (ast.StochasticBranch(30.0, Seq(S("B"))), ast.StochasticBranch(20.5, Seq(S("C")))),
            Seq(S("D")),
        ),
    ),
    (
        "split(x) { 1 : case split.index == 0 : A else : 50% : B else : C | 1 : D }",
        Seq(
            Split(
                "x",
                Entry(
                    N(1),
                    "absolute",
                    ast.ConditionalBody(
                        (
                            ast.ConditionalBranch(
                                B("==", ast.ShapeAttribute("split", "index"), N(0)), Seq(S("A"))
                            ),
                        ),
                        ast.StochasticBody((ast.StochasticBranch(50.0, Seq(S("B"))),), Seq(S("C"))),
                    ),
                ),
                Entry(N(1), "absolute", Seq(S("D"))),
            )
        ),
    ),
]


@pytest.mark.parametrize("text, expected", BODIES, ids=[t for t, _ in BODIES])
def test_rule_body(text, expected):
    assert body_of(text) == expected


# --------------------------------------------------------------------------------------------
# Definitions and the file


def test_definitions_in_order_with_annotations():
    grammar = parse(
        """
        version "2023.0"
        @Range(min=1, max=5) @Free
        attr n = 3
        const w = 2 * n
        f(a, b) = a + b
        g = 4
        @StartRule @Lot(20, 10)
        Lot --> extrude(w) A(1, 2)
        A(h, k) --> B
        """
    )
    assert grammar.version == "2023.0"
    assert grammar.definitions == (
        ast.Attribute(
            "n",
            N(3),
            (
                ast.Annotation("Range", (), (ast.Keyword("min", N(1)), ast.Keyword("max", N(5)))),
                ast.Annotation("Free"),
            ),
        ),
        ast.Constant("w", B("*", N(2), Nm("n"))),
        ast.Function("f", (ast.Parameter("a"), ast.Parameter("b")), B("+", Nm("a"), Nm("b"))),
        ast.Function("g", (), N(4)),
        ast.Rule(
            "Lot",
            (),
            Seq(ast.Extrude(Nm("w")), S("A", N(1), N(2))),
            (ast.Annotation("StartRule"), ast.Annotation("Lot", (N(20), N(10)))),
        ),
        ast.Rule("A", (ast.Parameter("h"), ast.Parameter("k")), Seq(S("B"))),
    )
    assert [a.name for a in grammar.attrs] == ["n"]
    assert [c.name for c in grammar.consts] == ["w"]
    assert [f.name for f in grammar.functions] == ["f", "g"]
    assert [r.name for r in grammar.rules] == ["Lot", "A"]
    assert grammar.start_rule.name == "Lot"
    assert grammar.rule("A").params[1].name == "k"
    assert grammar.rule("Missing") is None
    n = grammar.attrs[0]
    assert n.free and n.range == (N(1), N(5))


def test_positional_range_and_no_start_rule():
    grammar = parse("@Range(0, 10)\nattr x = 1\nFirst --> A\nSecond --> B")
    assert grammar.attrs[0].range == (N(0), N(10))
    assert not grammar.attrs[0].free
    assert grammar.start_rule.name == "First"  # without @StartRule, the first rule
    assert grammar.version is None


@pytest.mark.parametrize(
    "text, value",
    [
        (
            "f(a) = case a > 1 : 2 else : 3",
            ast.CaseExpression((ast.CaseBranch(B(">", Nm("a"), N(1)), N(2)),), N(3)),
        ),
        (
            "f(a) = case a > 1 : case a > 2 : 1 else : 2 else : 3",
            ast.CaseExpression(
                (
                    ast.CaseBranch(
                        B(">", Nm("a"), N(1)),
                        ast.CaseExpression((ast.CaseBranch(B(">", Nm("a"), N(2)), N(1)),), N(2)),
                    ),
                ),
                N(3),
            ),
        ),
        (
            "f = 30% : 1 20% : 2 else : 3",
            ast.StochasticExpression(
                (ast.StochasticValue(30.0, N(1)), ast.StochasticValue(20.0, N(2))), N(3)
            ),
        ),
        ("f = 30 % 4", B("%", N(30), N(4))),
    ],
)
def test_function_bodies(text, value):
    assert parse(text).functions[0].body == value


@pytest.mark.parametrize(
    "text, names",
    [
        # A rule body has no terminator: the next definition starts at a name followed by
        # '-->' or '=' (directly or after a parenthesised list), wherever the line breaks are.
        ("A --> B C --> D", ["A", "C"]),
        ("A --> B(1) C(x) --> D", ["A", "C"]),
        ("A --> B f(x) = x g = 2 attr h = 1 const k = 2 E --> F", ["A", "f", "g", "h", "k", "E"]),
        ("attr h = 1 f(a) = a A --> B", ["h", "f", "A"]),
        ('A --> i("box", w=1) B --> C', ["A", "B"]),
        ("A -->\n  B\n  C\n\nD -->\n  E", ["A", "D"]),
    ],
)
def test_definition_boundaries(text, names):
    assert [d.name for d in parse(text).definitions] == names


@pytest.mark.parametrize(
    "text",
    [
        "# hash comment\nA --> B",
        "// line comment\nA --> B // after\n",
        "/* block\n comment */ A --> /* inside */ B",
        "A --> B # trailing",
        'attr s = "# not a comment" A --> B',
    ],
)
def test_comments(text):
    assert parse(text).rules[0].body == Seq(S("B"))


def test_crlf_line_endings():
    grammar = parse("attr h = 1\r\nA -->\r\n  extrude(h)\r\n")
    assert grammar.rules[0].body == Seq(ast.Extrude(Nm("h")))
    assert grammar.rules[0].location.line == 2


def test_locations():
    grammar = parse(
        "attr h = 1\n@StartRule\nLot --> extrude(h)\n   split(x) { 1 : A | ~2 : B(h + 1) }\n",
        "f.grammar",
    )
    attr = grammar.attrs[0]
    assert attr.location == SourceLocation("f.grammar", 1, 6)
    assert attr.value.location == SourceLocation("f.grammar", 1, 10)
    rule = grammar.rules[0]
    assert rule.location == SourceLocation("f.grammar", 3, 1)
    assert rule.annotations[0].location == SourceLocation("f.grammar", 2, 2)
    extrude, split = rule.body.items
    assert extrude.location == SourceLocation("f.grammar", 3, 9)
    assert extrude.height.location == SourceLocation("f.grammar", 3, 17)
    assert split.location == SourceLocation("f.grammar", 4, 4)
    successor = split.group.parts[1].body.items[0]
    assert successor.location == SourceLocation("f.grammar", 4, 28)
    plus = successor.args[0]
    assert plus.location == SourceLocation("f.grammar", 4, 32)  # a binary sits at its operator


def test_nodes_are_frozen_and_hashable():
    grammar = parse("A --> extrude(1) B")
    with pytest.raises(AttributeError):
        grammar.rules[0].name = "C"
    assert hash(grammar) == hash(parse("A -->\n extrude(1)\n B"))


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.grammar")), ids=lambda p: p.name)
def test_example_files_load(path):
    grammar = load(path.read_text(), path.name)
    assert grammar.rules and grammar.filename == path.name
    assert grammar.source == path.read_text()


def test_walk_reaches_every_node_in_field_order():
    grammar = parse(
        "@Range(min=0, max=lo)\nattr h = 2\n"
        "A --> extrude(h) split(y) { 1 : B(f(h)) | ~1 : [ t(0, 'scope.sx, 0) C ] }"
    )
    names = [node.name for node in ast.walk(grammar) if isinstance(node, ast.Name | ast.Call)]
    assert names == ["lo", "h", "f", "h"]
    successors = [node.name for node in ast.walk(grammar) if isinstance(node, ast.Successor)]
    assert successors == ["B", "C"]
    assert [type(n) for n in ast.children(grammar.rules[0].body)] == [ast.Extrude, ast.Split]


def test_walk_does_not_recurse():
    deep = ast.Number(1.0)
    for _ in range(5000):
        deep = ast.Binary("+", deep, ast.Number(1.0))
    assert sum(isinstance(node, ast.Number) for node in ast.walk(deep)) == 5001
