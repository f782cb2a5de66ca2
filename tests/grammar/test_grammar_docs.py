"""The examples of docs/grammar.md: each loads, each builds, and the split cases are CityEngine's.

Building needs ``shapegen.parse_grammar``; those tests skip only while it does not exist.
"""

import re
from pathlib import Path

import numpy as np
import pytest

import shapegen
from shapegen.grammar import load

DOCS = Path(__file__).resolve().parents[2] / "docs" / "grammar.md"
DOC_TEXT = DOCS.read_text()
EXAMPLES = re.findall(r"```grammar\n(.*?)```", DOC_TEXT, re.S)


def _parse_grammar():
    parse_grammar = getattr(shapegen, "parse_grammar", None)
    if parse_grammar is None:
        pytest.skip("shapegen.parse_grammar does not exist yet")
    return parse_grammar


def _first_line(text: str) -> str:
    return next(line for line in text.splitlines() if line.strip() and not line.startswith("@"))


def test_there_is_an_example_per_construct():
    joined = "\n".join(EXAMPLES)
    for construct in [
        "version",
        "attr ",
        "const ",
        "case ",
        "else",
        "%",
        "@StartRule",
        "@Lot(",
        "@Range(",
        "@Free",
        "@Hidden",
        "@Description(",
        "extrude(",
        "split(x)",
        "split(y)",
        "}*",
        "'",
        "~",
        "comp(f)",
        "t(",
        "r(",
        "s(",
        "center(",
        "[",
        "NIL",
        "label(",
        "set(",
        "i(",
        "print(",
        "report(",
        "scope.sx",
        "split.index",
        "/*",
        "//",
        "#",
        "sin(",
        "rand(",
        "sqrt(",
        "&&",
        "!",
        ".\n",
    ]:
        assert construct in joined, f"no example uses {construct!r}"


@pytest.mark.parametrize("text", EXAMPLES, ids=[_first_line(t)[:40] for t in EXAMPLES])
def test_doc_example_loads(text):
    grammar = load(text, "docs/grammar.md")
    assert grammar.rules


@pytest.mark.parametrize("text", EXAMPLES, ids=[_first_line(t)[:40] for t in EXAMPLES])
def test_doc_example_builds(text):
    model = _parse_grammar()(text).build()
    assert len(model.blocks) >= 1
    for block in model.blocks:
        assert block.volume > 0


# CityEngine's documented split cases on a scope of 10 m along x: (pattern, [(name, size m)]).
SPLIT_CASES = [
    ("{ 3.3 : Z | ~3 : Y | 5 : X }", [("Z", 3.3), ("Y", 1.7), ("X", 5.0)]),
    ("{ ~0.5 : Z | ~0.1 : Y | ~0.2 : X }", [("Z", 6.25), ("Y", 1.25), ("X", 2.5)]),
    (
        "{ 2 : X | 1 : Y }*",
        [("X", 2.0), ("Y", 1.0), ("X", 2.0), ("Y", 1.0), ("X", 2.0), ("Y", 1.0), ("X", 1.0)],
    ),
    ("{ ~2.1 : G }*", [("G", 2.0)] * 5),
    ("{ '0.5 : Z | '0.1 : Y | '0.2 : X }", [("Z", 5.0), ("Y", 1.0), ("X", 2.0)]),
]


@pytest.mark.parametrize("pattern, expected", SPLIT_CASES, ids=[c[0] for c in SPLIT_CASES])
def test_split_cases_are_documented(pattern, expected):
    assert f"split(x) {pattern}" in DOC_TEXT


@pytest.mark.parametrize("pattern, expected", SPLIT_CASES, ids=[c[0] for c in SPLIT_CASES])
def test_split_cases_match_cityengine(pattern, expected):
    text = f"@StartRule\n@Lot(10, 1)\nLot --> extrude(1) split(x) {pattern}\n"
    model = _parse_grammar()(text).build()
    pieces = sorted(
        (float(block.bounds[0][0]), block.rule_path[-1], float(np.ptp(block.vertices[:, 0])))
        for block in model.blocks
    )
    assert [name for _, name, _ in pieces] == [name for name, _ in expected]
    assert [size for _, _, size in pieces] == pytest.approx([size for _, size in expected])
    starts = [start for start, _, _ in pieces]
    assert starts == pytest.approx(
        np.concatenate([[0.0], np.cumsum([s for _, s in expected])[:-1]])
    )
