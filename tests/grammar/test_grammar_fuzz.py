"""Fuzzing the loader: random text and mutated valid files yield a Grammar or a GrammarError.

Nothing else may come out of ``load`` (no lark exception, no IndexError, no RecursionError), and
every GrammarError must render. Seeds are the example files and the examples of
docs/grammar.md. Deterministic: derandomized, no example database.
"""

import re
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from shapegen.errors import GrammarError
from shapegen.grammar import ast, load

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = Path(__file__).parent / "examples"


def _seed_files() -> list[str]:
    seeds = [path.read_text() for path in sorted(EXAMPLES.glob("*.grammar"))]
    docs = ROOT / "docs" / "grammar.md"
    if docs.exists():
        seeds += re.findall(r"```grammar\n(.*?)```", docs.read_text(), re.S)
    seeds += [path.read_text() for path in sorted((ROOT / "rules").glob("*.grammar"))]
    return seeds


SEEDS = _seed_files()

# Tokens of the language, and a few near misses, for insertion.
TOKENS = [
    "-->",
    "->",
    "=",
    "==",
    "(",
    ")",
    "{",
    "}",
    "}*",
    "[",
    "]",
    "|",
    ":",
    ",",
    ".",
    "'",
    "~",
    "%",
    "30%",
    "*",
    "/",
    "+",
    "-",
    "!",
    "&&",
    "||",
    "<",
    ">=",
    "@",
    "@Range(0, 1)",
    "@Free",
    "@StartRule",
    "attr",
    "const",
    "case",
    "else",
    "version",
    "NIL",
    "true",
    "x",
    "y",
    "xz",
    "f",
    "front",
    "side",
    "split(x)",
    "comp(f)",
    "extrude(1)",
    "t('1, 0, 0)",
    "scope.sx",
    "split.index",
    "A",
    "B(1)",
    "C.",
    "0",
    "1e999",
    "-1",
    '"s"',
    '"',
    "/*",
    "*/",
    "#",
    "//",
    "\n",
    " ",
    "\t",
    "\r",
    "é",
    "\x00",
    "sin(",
    "rand(1, 2)",
]
TOKEN_PATTERN = re.compile(r"-->|[A-Za-z_][A-Za-z0-9_]*|\d+(\.\d*)?|\S")

FUZZ_SETTINGS = settings(
    max_examples=100,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


def _load_or_grammar_error(text: str) -> None:
    try:
        grammar = load(text, "fuzz.grammar")
    except GrammarError as error:
        assert error.problems
        assert str(error)
        return
    assert isinstance(grammar, ast.RuleFile)


@st.composite
def mutated_files(draw) -> str:
    text = draw(st.sampled_from(SEEDS))
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(
            st.sampled_from(
                [
                    "delete",
                    "duplicate",
                    "swap",
                    "insert",
                    "token_delete",
                    "token_duplicate",
                    "token_swap",
                ]
            )
        )
        if kind in ("token_delete", "token_duplicate", "token_swap"):
            spans = [m.span() for m in TOKEN_PATTERN.finditer(text)]
            if len(spans) < 2:
                continue
            i = draw(st.integers(0, len(spans) - 1))
            start, end = spans[i]
            if kind == "token_delete":
                text = text[:start] + text[end:]
            elif kind == "token_duplicate":
                text = text[:end] + " " + text[start:end] + text[end:]
            else:
                j = draw(st.integers(0, len(spans) - 1))
                (a, b), (c, d) = sorted([spans[i], spans[j]])
                if b <= c:
                    text = text[:a] + text[c:d] + text[b:c] + text[a:b] + text[d:]
            continue
        if not text:
            text = draw(st.sampled_from(TOKENS))
            continue
        i = draw(st.integers(0, len(text) - 1))
        if kind == "delete":
            j = draw(st.integers(i, min(len(text), i + 8)))
            text = text[:i] + text[j:]
        elif kind == "duplicate":
            j = draw(st.integers(i, min(len(text), i + 8)))
            text = text[:j] + text[i:j] + text[j:]
        elif kind == "swap":
            j = draw(st.integers(0, len(text) - 1))
            i, j = sorted((i, j))
            if i != j:
                text = text[:i] + text[j] + text[i + 1 : j] + text[i] + text[j + 1 :]
        else:
            text = text[:i] + draw(st.sampled_from(TOKENS)) + text[i:]
    return text


@FUZZ_SETTINGS
@given(
    st.text(
        alphabet=st.sampled_from("AB x(){}[]|:=-->.'~%*@0123456789\"/#\n abcfsplit"), max_size=80
    )
    | st.text(max_size=60)
)
def test_random_text_gives_grammar_or_grammar_error(text):
    _load_or_grammar_error(text)


@FUZZ_SETTINGS
@given(mutated_files())
def test_mutated_valid_files_give_grammar_or_grammar_error(text):
    _load_or_grammar_error(text)


def test_seeds_are_valid():
    assert len(SEEDS) >= 3
    for text in SEEDS:
        load(text)
