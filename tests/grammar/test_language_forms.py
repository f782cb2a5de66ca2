"""Forms of CGA's grammar (docs/cga-grammar.md), each by the kind of place it stands in: any value
where an expression stands, splitAndSetbackPerimeter's three-part entries, words that are
keywords only in their place, annotations where the reference puts them."""

from __future__ import annotations

import pytest

from shapegen.errors import GrammarError
from shapegen.grammar import ast, load, parse
from shapegen.grammar.printer import print_grammar


def _definition(grammar: ast.RuleFile, name: str):
    return next(d for d in grammar.definitions if d.name == name)


# A conditional or stochastic value in every place that takes an expression.
VALUE_PLACES = [
    ("comp function value", "f = comp(fe) { all : case scope.sx > 2 : 1 else : 0 }"),
    ("comp function merged", "f = comp(f) { side = 30% : 1 else : 0 | top : 2 }"),
    ("array element", "f = [case 1 > 2 : 1 else : 2, 3, 30% : 4 else : 5]"),
    ("index", "a = [1, 2]\nf = a[case 1 > 2 : 0 else : 1]"),
    ("keyword argument", 'Lot --> i("a.obj", height = case 1 > 2 : 3 else : 4)'),
    ("annotation argument", "@Range(min = 0, max = case 1 > 2 : 3 else : 4)\nattr f = 1"),
    ("local variable", "f with (x := case 1 > 2 : 1 else : 2) = x"),
    ("nested call", "f = max(case 1 > 2 : 1 else : 2, 30% : 3 else : 4)"),
    ("parenthesised", "f = 1 + (case 1 > 2 : 1 else : 2)"),
    ("import override", 'import lib : "lib.cga" (height = case 1 > 2 : 3 else : 4)'),
]


@pytest.mark.parametrize("text", [t for _, t in VALUE_PLACES], ids=[k for k, _ in VALUE_PLACES])
def test_a_value_stands_wherever_an_expression_does(text):
    grammar = parse(text, "x.cga")
    found = [
        node
        for node in _walk(grammar)
        if isinstance(node, ast.CaseExpression | ast.StochasticExpression)
    ]
    assert found, "the conditional or stochastic value was lost"


def _walk(node):
    if isinstance(node, tuple):
        for item in node:
            yield from _walk(item)
        return
    if not hasattr(node, "__dataclass_fields__"):
        return
    yield node
    for field in node.__dataclass_fields__:
        if field not in ("location", "source"):
            yield from _walk(getattr(node, field))


def test_comp_function_with_case_keeps_branches_in_order():
    text = "f = comp(fe) { front : case 1 > 2 : 1 else : 2 | all : 0 }"
    values = _definition(parse(text, "x.cga"), "f").body
    assert isinstance(values, ast.ComponentValues)
    assert [b.selector.name for b in values.branches] == ["front", "all"]
    assert isinstance(values.branches[0].value, ast.CaseExpression)
    assert values.branches[1].value == ast.Number(0.0)


def test_split_and_setback_perimeter_takes_length_depth_operations_and_a_remainder():
    text = (
        "Lot --> splitAndSetbackPerimeter(0) { ~2 : 3 : A | 4 : (case 1 > 2 : 1 else : 0) : B }*"
        " { remainder : C }"
    )
    operation = _definition(parse(text, "x.cga"), "Lot").body.items[0]
    assert operation.name == "splitAndSetbackPerimeter" and operation.repeat
    keys = [
        (b.mode, b.key.name if isinstance(b.key, ast.Name) else b.key.value)
        for b in operation.branches
    ]
    assert keys == [("floating", 2.0), ("absolute", 4.0), ("absolute", "remainder")]
    assert operation.branches[0].depth == ast.Number(3.0)
    assert isinstance(operation.branches[1].depth, ast.CaseExpression)
    assert operation.branches[2].depth is None
    assert [b.body.items[0].name for b in operation.branches] == ["A", "B", "C"]


@pytest.mark.parametrize(
    "text",
    [
        # a case body's colons are not a depth's
        "Lot --> split(x) { 1 : case 1 > 2 : A else : B | ~1 : 30% : C else : D }*",
        "Lot --> comp(f) { top : [ case 1 > 2 : A else : B ] | all : C }",
        "Lot --> split(x) { 1 : split(y) { 1 : A | 2 : B } C | ~1 : D }",
    ],
)
def test_two_part_entries_with_colons_inside_stay_two_part(text):
    grammar = parse(text, "x.cga")
    assert not [n for n in _walk(grammar) if getattr(n, "depth", None) is not None]


@pytest.mark.parametrize(
    "text, message",
    [
        ("Lot --> split(x) { 1 : 2 : A }", "three parts are splitAndSetbackPerimeter's"),
        ("Lot --> offset(-1) { 1 : 2 : A }", "not three parts"),
        ("Lot --> split(x) { 1 : A } { remainder : B }", "takes one { ... } block"),
        ("Lot --> setback(1) { front =: A }", "'=:' is only for comp and modify"),
    ],
)
def test_three_part_entries_and_second_blocks_belong_to_their_operation(text, message):
    with pytest.raises(GrammarError, match=message.replace("(", r"\(").replace(")", r"\)")):
        parse(text, "x.cga")


def test_comp_connected_operator_is_read_as_written():
    grammar = parse("Lot --> comp(f) { side =: A | top : B }", "x.cga")
    comp = _definition(grammar, "Lot").body.items[0]
    assert [(b.selector, b.merge, b.connected) for b in comp.branches] == [
        ("side", True, True),
        ("top", False, False),
    ]
    values = _definition(parse("f = comp(f) { side =: 1 }", "x.cga"), "f").body
    assert values.branches[0].connected


# Words that are keywords only in their place.
KEYWORD_PLACES = [
    ("start after an annotation", "@StartRule start Lot --> extrude(3)", "Lot", True),
    ("start after two annotations", '@StartRule @Description("x") start Lot --> X', "Lot", True),
    ("extension start", "extension start Lot --> X", "Lot", True),
    ("start extension", "start extension Lot --> X", "Lot", True),
    ("start as a const", "const start = 2\nLot --> extrude(start)", "start", False),
    ("start as a parameter", "Lot --> A(1)\nA(start) --> extrude(start)", "A", False),
    ("version as an attr", "attr version = 3\nLot --> extrude(version)", "version", False),
    ("attr as a parameter", "f(attr) = attr\nLot --> extrude(f(2))", "f", False),
]


@pytest.mark.parametrize(
    "text, name, start",
    [c[1:] for c in KEYWORD_PLACES],
    ids=[c[0] for c in KEYWORD_PLACES],
)
def test_keywords_are_keywords_only_in_their_place(text, name, start):
    grammar = parse(text, "x.cga")
    definition = _definition(grammar, name)
    if isinstance(definition, ast.Rule):
        assert bool(definition.annotation("StartRule")) == start


def test_a_start_keyword_written_after_an_annotation_marks_one_rule():
    grammar = parse("@Hidden attr a = 1\n@StartRule start Lot --> A\nB --> C", "x.cga")
    assert [r.name for r in grammar.rules if r.annotation("StartRule")] == ["Lot"]


def test_const_and_old_attr_functions_are_functions_in_cga_only():
    grammar = parse("const g(x) = x * 2\nattr w(i) = 3\nLot --> extrude(g(1) + w(0))", "x.cga")
    assert isinstance(_definition(grammar, "g"), ast.Function)
    assert [p.name for p in _definition(grammar, "w").params] == ["i"]
    with pytest.raises(GrammarError, match="const 'g' takes no parameters"):
        parse("const g(x) = x * 2\nLot --> extrude(g(1))", "x.grammar")


def test_version_is_read_only_before_its_string():
    grammar = parse('version "2023.0"\nversion2 = 3\nLot --> extrude(version2)', "x.cga")
    assert grammar.version == "2023.0"


def test_a_file_description_may_end_the_file():
    text = 'Lot --> extrude(3)\n@RuleFileDescription("Creates a mass from a lot.")'
    assert [d.name for d in parse(text, "x.cga").definitions] == ["Lot"]


def test_inline_with_a_strategy_takes_a_block_of_operations():
    grammar = parse("Lot --> inline(unify) { extrude(3) A }", "x.cga")
    inline = _definition(grammar, "Lot").body.items[0]
    assert inline.name == "inline" and inline.arguments[0].value.name == "unify"
    assert inline.branches[0].key is None
    assert [type(i).__name__ for i in inline.branches[0].body.items] == ["Extrude", "Successor"]


@pytest.mark.parametrize(
    "text",
    [
        "Lot --> splitAndSetbackPerimeter(0) { ~2 : (case 1 > 2 : 1 else : 0) : A | 4 : 1 : B }*"
        " { remainder : C }",
        "Lot --> comp(f) { side =: A | top = B | 0 : C }",
        "f = comp(f) { side =: 1 | top = 2 }",
        "Lot --> inline(unify) { extrude(3) A }",
        "Lot --> inline(recompose) A",
    ],
)
def test_new_forms_print_back_to_the_same_tree(text):
    tree = parse(text, "x.cga")
    assert parse(print_grammar(tree), "x.cga").definitions == tree.definitions


def test_a_parameter_may_stand_as_a_comp_selector():
    """op_comp.html: a selector may be a bool (a logical expression)."""
    load("R(q) --> comp(f) { q : A }\nLot --> extrude(3) R(true)", "x.cga")
    with pytest.raises(GrammarError, match="unknown comp selector 'qq'"):
        load("R(q) --> comp(f) { qq : A }\nLot --> extrude(3) R(true)", "x.cga")


def test_a_rule_may_take_an_operations_name_with_another_arity_in_cga():
    """Changelog 2019.1: a call to an operation with another signature goes to a rule of that
    signature; with the operation's own arity the name stays the operation's."""
    text = "Lot --> extrude(4, 2, 1)\nextrude(a, b, c) --> extrude(a + b + c) Mass."
    grammar = load(text, "x.cga")
    call = _definition(grammar, "Lot").body.items[0]
    assert isinstance(call, ast.Successor) and call.called and len(call.args) == 3
    rule = next(r for r in grammar.rules if r.name == "extrude")
    assert isinstance(rule.body.items[0], ast.Extrude)
    with pytest.raises(GrammarError, match=r"extrude\(\) takes 1 to 2 arguments, got 3"):
        load("Lot --> extrude(4, 2, 1)", "x.cga")
    with pytest.raises(GrammarError, match="'extrude' is an operation; a rule cannot use its"):
        load("Lot --> extrude(4)\nextrude(a) --> X", "x.cga")
    with pytest.raises(GrammarError, match=r"extrude\(\) takes 1 to 2 arguments, got 3"):
        load(text, "x.grammar")


@pytest.mark.parametrize(
    "old, new",
    [
        ("Lot --> subtract Hole", "Lot --> subtract { OperandA. | Hole }"),
        ("Lot --> subtract(swap) Hole", "Lot --> subtract { Hole | OperandB. }"),
        ("Lot --> union Hole(2) X", "Lot --> union { OperandA. | Hole(2) } X"),
    ],
)
def test_the_deprecated_boolean_form_reads_as_its_two_operand_rewrite(old, new):
    """Changelog 2025.0: ``subtract Rule`` => ``subtract { OperandA. | Rule }``, ``subtract(swap)
    Rule`` => ``subtract { Rule | OperandB. }``."""
    tree = parse(old, "x.cga")
    assert tree.definitions == parse(new, "x.cga").definitions
    assert parse(print_grammar(tree), "x.cga").definitions == tree.definitions


def test_nested_inline_blocks_print_back_to_the_same_tree():
    tree = parse("R --> inline(unify) { inline(unify) { NIL } } X", "x.cga")
    assert parse(print_grammar(tree), "x.cga").definitions == tree.definitions
