"""The printer (shapegen.grammar.printer) writes back what the parser read: parse, print, parse
gives an equal tree (nodes compare without their source locations), for hand-written forms of
every kind of node, for every rule file of the corpora, and for generated programs
(tests/cga/test_generated_programs.py).

The corpora: the bundled rules, tests/data/cga-corpus and the shared corpus of PyPRT's packages
(one file per distinct text; the small ones in the quick lane, all of them in the slow one), and
the wild corpus (``$SHAPEGEN_CGA_WILD`` or /work/cga-wild, slow, skipped when absent).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import pytest

from shapegen.errors import GrammarError
from shapegen.grammar import ast, parse
from shapegen.grammar.printer import print_body, print_expression, print_grammar

ROOT = Path(__file__).resolve().parents[2]
SHARED_CORPUS = Path("/work/shared/cga-corpus")
WILD_CORPUS = Path(os.environ.get("SHAPEGEN_CGA_WILD", "/work/cga-wild"))
QUICK_SIZE = 3000  # characters: files up to this size round-trip in the quick lane


def round_trip(text: str, filename: str = "<string>.cga") -> tuple[ast.RuleFile, ast.RuleFile]:
    """The tree of ``text`` and the tree of its printed form."""
    first = parse(text, filename)
    printed = print_grammar(first)
    try:
        second = parse(printed, filename)
    except GrammarError as error:
        raise AssertionError(f"the printed text does not parse: {error}\n{printed}") from None
    return first, second


def assert_round_trip(text: str, filename: str = "<string>.cga") -> None:
    first, second = round_trip(text, filename)
    assert second == first, _first_difference(first, second)


def _first_difference(first: ast.RuleFile, second: ast.RuleFile) -> str:
    for a, b in zip(first.definitions, second.definitions, strict=False):
        if a != b:
            return f"\nread:    {a}\nprinted: {b}\nas text: {print_grammar(second)[:2000]}"
    return (
        f"definitions {len(first.definitions)} -> {len(second.definitions)}, "
        f"imports equal {first.imports == second.imports}, styles {first.styles} -> "
        f"{second.styles}, version {first.version!r} -> {second.version!r}"
    )


FORMS = [
    # definitions, annotations, with-clauses
    'version "2023.1"\n@Range(min=1, max=10) @Description("h")\nattr height = 10\nLot --> X',
    '@Enum("a", "b", restricted=false) attr style = "a"\nconst k = 2\nLot --> X',
    "f(a, b) = a + b * 2\ng = case f(1, 2) > 3 : 1 case true : 2 else : 3\nLot --> X",
    "h(a) = 20% : a 30.5% : 2 * a else : 0\nLot --> X",
    "f(a) with (x := a * 2 y := x + 1) = x + y\nLot --> X",
    '@StartRule\nLot --> A(1, "s", true)\nA(n, s, b) --> case n > 0 && b : X else : NIL',
    "start Lot --> extrude(3) X",
    "extension Roof --> roofHip(30) X\nLot --> Roof",
    # expressions
    "f = (1 + 2) * 3 - -4 / (5 % 2) + +1\nLot --> X",
    "f = !(true || false) && 1 < 2 == (3 >= 4)\nLot --> X",
    "f = 1 - (2 - 3) - 4\ng = 2 / (3 * 4)\nLot --> X",
    "f = [1, 2; 3, 4][0, 1] + size([1:2:9]) + [1, 2, 3][:]\nLot --> X",
    "f = [1, 2] .+ [3, 4] .* 2\nLot --> X",
    'f = "a \\"quoted\\" back\\\\slash" + str(1.5e-7)\nLot --> X',
    "f = scope.sx + geometry.area(top) + split.index + seedian\nLot --> X",
    "f = comp(fe) { all : 2 | front = 3 }\nLot --> X",
    "f = max(case scope.sx > 2 : 1 else : 2, 3)\nLot --> X",
    # rule bodies
    "Lot --> extrude(3) split(y) { ~1 : Floor | '0.2 : Roof | 1 : NIL }*",
    "Lot --> split(x, noAdjust) { 1 : A | { ~2 : B | 1 : C }* | 1 : D }",
    "Lot --> split(u, uvSpace, 0) { 0.5 : A | ~1 : B }*",
    "Lot --> comp(f) { front : A | side = B | 0 : C | top : NIL }",
    "Lot --> comp(fe) { front : A | all : B }",
    "Lot --> t(1, '0.5, 0) s('1, 2, 3) r(scopeCenter, 0, 90, 0) r(1, 2, 3) center(xz)",
    'Lot --> [ t(0, 1, 0) A ] [ B. ] C(1, 2) D() label("x") set(height, 2)',
    'Lot --> i("builtin:cube") i("a.obj", yUp, keepSizeAndPosition) i("box", depth = 2)',
    'Lot --> print("a", 1) report("k", 2) color("#ff0000") color(1, 0, 0)',
    "Lot --> offset(-1) { inside : A | border : B } setback(2) { front : C | remainder : D }",
    "Lot --> roofHip(30, 0.5) roofGable(byHeight, 2) extrude(world.y, 3) innerRect",
    "Lot --> scatter(surface, 10, uniform) { Tree } union { A | B } inline { A B }",
    "Lot --> inline(unify) A inline B",
    "Lot --> inline(unify) { inline(unify) { A(1) } } inline(recompose) { split(x) { 1 : A } }",
    "Lot --> 30% : A 20% : case scope.sx > 3 : B else : C else : D",
    "Lot --> case scope.sx > 3 : 50% : A else : B case true : C else : D",
    'import lib : "lib.cga" (height, width = 3, Roof --> X)\nimport "other.cga" ()\nLot --> X',
    'import p (styleA) : "x.cga"\nLot --> p(height = 2).Building(1)',
    "Lot --> X\nstyle Red\nLot --> Y",
    # nested choices and operators that sit close together
    "f = case 1 > 2 : case 2 > 1 : 1 else : 2 else : 30% : 4 else : 5\nLot --> X",
    "f(x) with (a := case x > 1 : 2 else : 3 b := 50% : 1 else : 2) = a + b\nLot --> X",
    "Lot --> A(case 1 > 2 : 1 else : 2, 3) B",
    "Lot --> 50% : 50% : A else : B else : [ case 1 > 2 : A else : B ] C",
    "f = -(-1) + -(2 * 3) + !(!true) + (-2)[0] + 2 .- -1 + (1 + 2)[0]\nLot --> X",
    'f = "a" + (case true : "b" else : "c")[0]\nLot --> X',
]


@pytest.mark.parametrize("text", FORMS)
def test_every_form_round_trips(text):
    assert_round_trip(text)


@pytest.mark.parametrize(
    ("expression", "text"),
    [
        (
            ast.Binary("-", ast.Number(1), ast.Binary("-", ast.Number(2), ast.Number(3))),
            "1 - (2 - 3)",
        ),
        (
            ast.Binary("*", ast.Binary("+", ast.Number(1), ast.Number(2)), ast.Number(3)),
            "(1 + 2) * 3",
        ),
        (ast.Unary("-", ast.Unary("-", ast.Name("a"))), "- -a"),
        (ast.Number(0.25), "0.25"),
        (ast.Number(3.0), "3"),
        (ast.String('say "hi"'), '"say \\"hi\\""'),
    ],
)
def test_expressions_print_with_the_fewest_parentheses(expression, text):
    assert print_expression(expression) == text


def test_a_body_prints_as_written():
    grammar = parse("Lot --> extrude(3) comp(f) { top : Roof | side : Wall }")
    assert print_body(grammar.rules[0].body) == "extrude(3) comp(f) { top : Roof | side : Wall }"


def test_a_changed_tree_prints_differently():
    """The comparison can fail: a tree with one number changed is not equal after printing."""
    grammar = parse("Lot --> extrude(3) X")
    (extrude, _) = grammar.rules[0].body.items
    other = parse(print_grammar(grammar).replace("extrude(3)", "extrude(4)"))
    assert other != grammar
    assert other.rules[0].body.items[0] == ast.Extrude(ast.Number(4.0))
    assert extrude == ast.Extrude(ast.Number(3.0))


def _distinct(paths) -> list[Path]:
    seen: dict[str, Path] = {}
    for path in sorted(paths):
        digest = hashlib.sha1(path.read_bytes()).hexdigest()
        seen.setdefault(digest, path)
    return list(seen.values())


def _corpus_files() -> list[Path]:
    paths = [*ROOT.glob("rules/**/*.grammar"), *ROOT.glob("tests/data/cga-corpus/**/*.cga")]
    if SHARED_CORPUS.is_dir():
        paths += SHARED_CORPUS.glob("**/*.cga")
    return _distinct(paths)


CORPUS = _corpus_files()


def _case(path: Path):
    name = str(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)
    marks = [pytest.mark.slow] if path.stat().st_size > QUICK_SIZE else []
    return pytest.param(path, id=name, marks=marks)


@pytest.mark.parametrize("path", [_case(path) for path in CORPUS])
def test_corpus_files_round_trip(path):
    text = path.read_text(encoding="utf-8", errors="replace")
    assert_round_trip(text, path.name)


def test_the_corpus_is_there():
    assert len(CORPUS) >= 40


@pytest.mark.slow
@pytest.mark.skipif(not WILD_CORPUS.is_dir(), reason=f"no wild corpus at {WILD_CORPUS}")
def test_the_wild_corpus_round_trips():
    """Every file of the wild corpus that parses prints back to the same tree; the files the
    parser refuses are counted (their refusals are the wild corpus tool's business)."""
    paths = _distinct(p for p in WILD_CORPUS.glob("**/*") if p.suffix.lower() == ".cga")
    failures, refused = [], 0
    for path in paths:
        text = path.read_text(encoding="utf-8", errors="replace")
        try:
            first = parse(text, path.name)
        except GrammarError:
            refused += 1
            continue
        try:
            second = parse(print_grammar(first), path.name)
        except GrammarError as error:
            failures.append(f"{path}: printed text refused: {str(error).splitlines()[0]}")
            continue
        if second != first:
            failures.append(f"{path}: {_first_difference(first, second)[:300]}")
    print(f"wild corpus: {len(paths)} distinct files, {refused} refused by the parser")
    assert not failures, "\n".join(failures[:20])


@pytest.mark.slow
def test_the_reference_examples_round_trip():
    """Every code example of CityEngine's CGA reference that parses (tests/data/
    cga_reference_examples.json, made by tools/cga_reference_examples.py) prints back to the
    same tree."""
    examples = json.loads((ROOT / "tests/data/cga_reference_examples.json").read_text())
    failures, parsed = [], 0
    for example in examples["examples"]:
        name = f"{example['page']}#{example['index']}.cga"
        try:
            first = parse(example["program"], name)
        except GrammarError:
            continue  # the reference examples' own test follows the refusals
        parsed += 1
        try:
            second = parse(print_grammar(first), name)
        except GrammarError as error:
            failures.append(f"{name}: printed text refused: {str(error).splitlines()[0]}")
            continue
        if second != first:
            failures.append(f"{name}: {_first_difference(first, second)[:300]}")
    assert parsed >= 400
    assert not failures, "\n".join(failures[:20])
