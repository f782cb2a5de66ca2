"""Every code example of CityEngine's CGA reference parses, loads, and derives where it has a rule.

The examples are ``tests/data/cga_reference_examples.json`` (made from the reference pages by
``tools/cga_reference_examples.py``): each is a complete program, or a rule or expression
fragment wrapped in the least context that makes it one. Every program is parsed in the quick
lane; in the slow lane it is loaded (the load-time checks) and, where it has a rule, derived on
a 12 x 8 m lot (an asset the reference does not ship is a missing asset, as in CityEngine: a
warning). CityEngine's workspace holds its library ESRI.lib, which examples import
(``/ESRI.lib/rules/Plants/Plant_Loader.cga``); the reference does not ship it, the corpus does
(PyPRT's envelope2002 test package, version 2021.1), so that workspace is searched last for
imports, as ``--rules-path`` is, its assets absent (warnings).

The examples of a page build on one another, as the reference writes them: an example that
imports a file the page shows under a ``// name.cga`` line (import.html's ``main.cga`` and
``imp.cga``) has that example written beside it as ``name.cga`` (the nearest one on the page,
the following first); and an example that uses a name it does not define (``getColor``,
defined in the page's first example) gets the page's definitions of that name appended (the
nearest example that defines it), one name at a time while the names are found. An example
that shows alternatives of one rule (op_pushpop's two ``House`` rules, "both rules generate
the same result") is refused as CityEngine's compiler refuses a definition made twice (a
"duplicate definition" error marker, cga_changelog); each alternative is then loaded and
derived apart, with the example's other definitions.

The examples that cannot pass are listed in ``cga_reference_examples_expected.json`` with the
stage where they stop and why; each of them must still stop there, so the list stays true (an
entry whose example now passes fails its test: remove the entry).
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import re
from pathlib import Path

import pytest

from shapegen.engine.grammar_api import Grammar
from shapegen.errors import ShapegenError
from shapegen.grammar import load, parse
from shapegen.grammar.printer import print_grammar

DATA = Path(__file__).resolve().parents[1] / "data"
EXAMPLES = json.loads((DATA / "cga_reference_examples.json").read_text("utf-8"))["examples"]
EXPECTED = json.loads((DATA / "cga_reference_examples_expected.json").read_text("utf-8"))
STAGES = ("parse", "load", "derive")
#: a workspace holding CityEngine's ESRI.lib (rules only), from the corpus
ESRI_LIB_WORKSPACE = DATA / "cga-corpus" / "tests_data_envelope2002__c00dca01" / ".ws"
LOT = (12.0, 8.0)


def _id(example: dict) -> str:
    return f"{example['page']}#{example['index']}"


BY_ID = {_id(e): e for e in EXAMPLES}
_FILE_HEADER = re.compile(r"\s*//\s*([\w./-]+\.cga)\b")
_UNDEFINED = re.compile(r"(?:undefined|unknown) name '(\w+)'")
_DUPLICATE = re.compile(r"duplicate rule '([\w.]+)'")
_JOINS = 8  # names taken from the page, at most, per example


def _page_neighbours(example: dict) -> list[dict]:
    """The other examples of ``example``'s page, nearest first (the following one first)."""
    others = [e for e in EXAMPLES if e["page"] == example["page"] and e is not example]
    return sorted(others, key=lambda e: (abs(e["index"] - example["index"]),
                                         e["index"] < example["index"]))  # fmt: skip


def _page_files(example: dict, folder: Path) -> None:
    """Write beside ``example`` the rule files its page shows under a ``// name.cga`` line."""
    written = set()
    for other in _page_neighbours(example):
        match = _FILE_HEADER.match(other["program"])
        if match and match.group(1) not in written:
            written.add(match.group(1))
            (folder / match.group(1)).write_text(other["program"], "utf-8")


def _page_definitions(example: dict, name: str) -> str | None:
    """The definitions of ``name`` in the nearest other example of the page that has one, as
    rule-file text; None when no example of the page defines it."""
    for other in _page_neighbours(example):
        try:
            tree = parse(other["program"], "other.cga")
        except ShapegenError:
            continue
        found = tuple(d for d in tree.definitions if getattr(d, "name", None) == name)
        if found:
            only = dataclasses.replace(tree, definitions=found, imports=(), styles=(), version=None)
            return print_grammar(only)
    return None


def _alternatives(program: str, rule: str) -> list[str]:
    """``program`` once for each definition of ``rule``, with the other definitions kept."""
    tree = parse(program, "alternatives.cga")
    mine = [d for d in tree.definitions if getattr(d, "name", None) == rule]
    rest = tuple(d for d in tree.definitions if getattr(d, "name", None) != rule)
    return [print_grammar(dataclasses.replace(tree, definitions=(d, *rest))) for d in mine]


def _stage_reached(example: dict, folder: Path, last: str) -> tuple[str | None, str]:
    """The first stage up to ``last`` that refuses ``example`` (None when none does) and its
    message; an example showing alternatives of a rule is taken one alternative at a time."""
    stopped, message = _program_stage(example, example["program"], folder, last)
    duplicate = _DUPLICATE.search(message) if stopped == "load" else None
    if duplicate is None:
        return stopped, message
    for alternative in _alternatives(example["program"], duplicate.group(1)):
        stopped, message = _program_stage(example, alternative, folder, last)
        if stopped is not None:
            return stopped, message
    return None, ""


def _program_stage(example: dict, program: str, folder: Path, last: str) -> tuple[str | None, str]:
    """The first stage up to ``last`` that refuses ``program`` (``example``'s text, or one
    alternative of it) and its message, with the page's files and definitions joined."""
    name = _id(example).replace("/", "_") + ".cga"
    path = folder / name
    stage = "parse"
    try:
        parse(program, name)
        if last == "parse":
            return None, ""
        _page_files(example, folder)
    except ShapegenError as exc:
        return stage, str(exc).splitlines()[0]
    joined: set[str] = set()
    while True:
        path.write_text(program, "utf-8")
        try:
            stage = "load"
            tree = load(program, name, origin=path, search_folders=(ESRI_LIB_WORKSPACE,))
            if last == "load" or not example["derive"]:
                return None, ""
            stage = "derive"
            with contextlib.redirect_stdout(io.StringIO()):  # the examples print()
                Grammar(tree, path).build(lot=LOT)
        except ShapegenError as exc:
            message = str(exc).splitlines()[0]
            missing = _UNDEFINED.search(message)
            if missing is None or missing.group(1) in joined or len(joined) >= _JOINS:
                return stage, message
            definitions = _page_definitions(example, missing.group(1))
            if definitions is None:
                return stage, message
            joined.add(missing.group(1))
            program = program + "\n\n" + definitions
            continue
        return None, ""


def _check(example: dict, folder: Path, last: str) -> None:
    expected = EXPECTED.get(_id(example))
    stopped, message = _stage_reached(example, folder, last)
    if expected is None or STAGES.index(expected["stage"]) > STAGES.index(last):
        assert stopped is None, f"{_id(example)} ({example['kind']}) stops at {stopped}: {message}"
        return
    assert stopped == expected["stage"], (
        f"{_id(example)} was listed as stopping at {expected['stage']} "
        f"({expected['reason']}); it now stops at {stopped}: {message or 'it passes'}"
    )


def test_every_example_parses(tmp_path):
    """All in one test: the quick lane pays the parser's time only (about 2 s)."""
    wrong = []
    for example in EXAMPLES:
        try:
            _check(example, tmp_path, "parse")
        except AssertionError as exc:
            wrong.append(str(exc).splitlines()[0])
    assert not wrong, "\n".join(wrong)


@pytest.mark.slow
@pytest.mark.parametrize("example", EXAMPLES, ids=_id)
def test_example_loads_and_derives(example, tmp_path):
    _check(example, tmp_path, "derive")


def test_expected_failures_name_examples_and_say_why():
    for key, entry in EXPECTED.items():
        assert key in BY_ID, f"{key} is no example of the reference"
        assert entry["stage"] in STAGES and entry["reason"].strip(), key
        if entry["stage"] == "derive":
            assert BY_ID[key]["derive"], f"{key} has no rule to derive"


def test_every_kind_is_present_and_fragments_say_their_wrapping():
    kinds = {e["kind"] for e in EXAMPLES}
    assert kinds == {"program", "rule fragment", "expression fragment"}
    assert len(EXAMPLES) > 400  # the reference has several hundred
    for example in EXAMPLES:
        assert (example["wrapping"] == "") == (example["kind"] == "program"), _id(example)
