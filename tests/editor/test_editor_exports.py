"""The exports: the report, the attrs as JSON, and the ``shapegen build`` line that builds the
design again (read back by the command's own parser)."""

import json
import shlex
import struct
from pathlib import Path

import pytest
from editor_http import request, serving

from shapegen.cli import build_parser
from shapegen.editor.exports import command_line, set_argument
from shapegen.engine.project.rules_path import find_bundled_rule
from shapegen.model.lot import Lot


@pytest.mark.parametrize(
    ("name", "value", "argument", "read_back"),
    [
        ("span", 7.0, "span=7", 7),
        ("span", 0.1, "span=0.1", 0.1),
        ("span", 1 / 3, "span=0.3333333333333333", 1 / 3),
        ("span", -2.5e-7, "span=-2.5e-07", -2.5e-7),
        ("mortar", True, "mortar=true", True),
        ("stone", "granite", "stone=granite", "granite"),
        ("stone", "12", 'stone="12"', "12"),  # a string that would read as a number
        ("stone", "true", 'stone="true"', "true"),
        ("tint", "#aa8844", "tint=#aa8844", "#aa8844"),
        ("name", "two words", "name=two words", "two words"),
    ],
)
def test_a_value_is_written_as_set_reads_it_back(name, value, argument, read_back):
    assert set_argument(name, value) == argument
    words = shlex.split(command_line(Path("x.grammar"), {name: value}))
    args = build_parser().parse_args(words[1:])
    assert args.assignments == [(name, read_back)]


def test_the_command_line_gives_seed_and_lot_when_not_the_defaults():
    line = command_line(Path("x.grammar"), {}, seed=3, lot=Lot.rectangle(12.5, 8))
    args = build_parser().parse_args(shlex.split(line)[1:])
    assert (args.seed, args.lot) == (3, Lot.rectangle(12.5, 8.0))
    polygon = Lot.polygon([(0, 0), (5, 8.5), (10, 0)])  # counter-clockwise seen from above
    line = command_line(Path("x.grammar"), {}, lot=polygon)
    args = build_parser().parse_args(shlex.split(line)[1:])
    assert args.lot == polygon and polygon.corners == ((0, 0), (5, 8.5), (10, 0))


def test_a_bundled_rule_is_named_by_its_name_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not where the rules are: a path would be absolute
    for path in (find_bundled_rule("cluny.grammar"), find_bundled_rule("cluny.grammar").resolve()):
        assert command_line(path, {"bays": 6}) == "shapegen build cluny.grammar --set bays=6"


def test_the_exports_of_the_current_design(stack_file):
    with serving(stack_file) as server:
        request(server, "POST", "/api/attrs", {"offset": 0.35, "stone": "granite"})
        status, kind, content = request(server, "GET", "/api/attrs.json")
        exported = json.loads(content)
        assert status == 200 and kind == "application/json"
        assert exported["set"] == {"offset": 0.35, "stone": "granite"}
        assert exported["attrs"] == {
            "offset": 0.35, "stone": "granite", "mortar": False, "courses": 2
        }  # fmt: skip
        for key, given in (("command", exported["set"]), ("command_every_attr", exported["attrs"])):
            words = shlex.split(exported[key])
            assert words[:2] == ["shapegen", "build"] and Path(words[2]).name == "stack.grammar"
            args = build_parser().parse_args(words[1:])
            assert dict(args.assignments) == given
        report = json.loads(request(server, "GET", "/api/report.json")[2])
        assert report["attrs"]["offset"] == 0.35 and report["blocks"] == 2
        assert report["analysis"]["feasible"] is True
        status, kind, model = request(server, "GET", "/api/model.glb")
        assert struct.unpack("<4sI", model[:8]) == (b"glTF", 2)
        for path in ("/api/attrs.json", "/api/report.json"):
            assert request(server, "POST", path, {})[0] == 405
