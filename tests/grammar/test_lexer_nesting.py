"""The post-lexer's look ahead at blocks: a bare block (``scatter(...) { ops }``) is told from a
block of branches by reading each block's own level once, and blocks nested beyond
MAX_BLOCK_NESTING are refused where the depth is passed."""

import pytest

from shapegen.errors import GrammarError
from shapegen.grammar import parse
from shapegen.grammar.lexer import MAX_BLOCK_NESTING, lark_parser

DEPTH = 10 * MAX_BLOCK_NESTING


@pytest.mark.parametrize(
    "opening",
    [
        pytest.param("split(x){ 1: ", id="branches"),
        pytest.param("split(x){ ", id="bare"),
        pytest.param("scatter(surface, 5, uniform) { ", id="scatter"),
    ],
)
def test_blocks_nested_ten_thousand_deep_are_refused_at_the_depth_passed(opening):
    text = "Lot --> " + opening * DEPTH + "A" + " }" * DEPTH + "\n"
    with pytest.raises(GrammarError, match="nests too deeply") as raised:
        parse(text, "deep.cga")
    location = raised.value.location
    brace_at = len("Lot --> ") + MAX_BLOCK_NESTING * len(opening) + opening.index("{") + 1
    assert (location.line, location.column) == (1, brace_at)


def _brace_types(text: str) -> list[str]:
    tokens = lark_parser().lex(text)
    return [token.type for token in tokens if token.type.endswith("LBRACE")]


@pytest.mark.parametrize(
    "text, expected",
    [
        ("A --> scatter(surface, 5, uniform) { B }", ["BARE_LBRACE"]),
        ("A --> split(x) { 1 : B }", ["LBRACE"]),
        # a bare block inside the branch of a split, and branches inside a bare block
        ("A --> split(x) { 1 : scatter(volume, 2, uniform) { B C } }", ["LBRACE", "BARE_LBRACE"]),
        (
            "A --> scatter(volume, 2, uniform) { split(x) { 1 : B | ~1 : C } D }",
            ["BARE_LBRACE", "LBRACE"],
        ),
        # a key inside a nested group does not make the outer block one of branches
        ("A --> scatter(volume, 2, uniform) { t(f(x = 1), 0, 0) B }", ["BARE_LBRACE"]),
        # a group of split parts and an empty block are not bare
        ("A --> split(x) { { 1 : B }* }", ["LBRACE", "LBRACE"]),
        ("A --> scatter(volume, 2, uniform) { }", ["LBRACE"]),
        # a block that never closes is not bare
        ("A --> scatter(volume, 2, uniform) { B", ["LBRACE"]),
    ],
)
def test_a_block_is_bare_when_its_own_level_has_no_key(text, expected):
    assert _brace_types(text) == expected
