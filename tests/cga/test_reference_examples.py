"""Every code example of CityEngine's CGA reference parses, loads, and derives where it has a rule.

The examples are ``tests/data/cga_reference_examples.json`` (made from the reference pages by
``tools/cga_reference_examples.py``): each is a complete program, or a rule or expression
fragment wrapped in the least context that makes it one. Every program is parsed in the quick
lane; in the slow lane it is loaded (the load-time checks) and, where it has a rule, derived on
a 12 x 8 m lot (an asset the reference does not ship is a missing asset, as in CityEngine: a
warning).

The examples that cannot pass are listed in ``cga_reference_examples_expected.json`` with the
stage where they stop and why; each of them must still stop there, so the list stays true (an
entry whose example now passes fails its test: remove the entry).
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

from shapegen.engine.grammar_api import Grammar
from shapegen.errors import ShapegenError
from shapegen.grammar import load, parse

DATA = Path(__file__).resolve().parents[1] / "data"
EXAMPLES = json.loads((DATA / "cga_reference_examples.json").read_text("utf-8"))["examples"]
EXPECTED = json.loads((DATA / "cga_reference_examples_expected.json").read_text("utf-8"))
STAGES = ("parse", "load", "derive")
LOT = (12.0, 8.0)


def _id(example: dict) -> str:
    return f"{example['page']}#{example['index']}"


BY_ID = {_id(e): e for e in EXAMPLES}


def _stage_reached(example: dict, folder: Path, last: str) -> tuple[str | None, str]:
    """The first stage up to ``last`` that refuses ``example`` (None when none does) and its
    message."""
    name = _id(example).replace("/", "_") + ".cga"
    path = folder / name
    path.write_text(example["program"], "utf-8")
    stage = "parse"
    try:
        parse(example["program"], name)
        if last == "parse":
            return None, ""
        stage = "load"
        tree = load(example["program"], name, origin=path)
        if last == "load" or not example["derive"]:
            return None, ""
        stage = "derive"
        with contextlib.redirect_stdout(io.StringIO()):  # the examples print()
            Grammar(tree, path).build(lot=LOT)
    except ShapegenError as exc:
        return stage, str(exc).splitlines()[0]
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
