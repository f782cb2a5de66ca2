"""--structural, --ignore and @Structure("blocks", structural=..., ignore=...): the structure."""

from __future__ import annotations

import json

from shapegen.cli import main
from shapegen.export.blocks_json import write_blocks_json
from shapegen.model import Block, Model


def _pier(tmp_path):
    pier = Block.box((0, 0, 0), (1, 2, 1), id="pier", tags=("wall",))
    boss = Block.box((1.0, 1.0, 0.4), (1.3, 1.5, 0.6), id="boss", tags=("ornament",))
    path = tmp_path / "pier.json"
    write_blocks_json(Model([pier, boss]), path)
    return path


def test_an_ignored_ornament_rides_on_the_pier(tmp_path, capsys):
    path, report = _pier(tmp_path), tmp_path / "r.json"
    # the boss hangs on the pier's side: as a block of its own it would slide off
    assert main(["analyze", str(path), "--report", str(report), "-q"]) == 0
    assert json.loads(report.read_text())["stands"] is False
    assert main(["analyze", str(path), "--ignore", "ornament", "--report", str(report)]) == 0
    judged = json.loads(report.read_text())
    assert judged["stands"] is True and judged["bodies"]["riding"] == 1
    assert "ornaments ride as load" in capsys.readouterr().out
    assert main(["analyze", str(path), "--structural", "wall", "--report", str(report)]) == 0
    assert json.loads(report.read_text())["bodies"]["ignored"] == 1


def test_a_name_no_block_has_and_a_misplaced_option_are_one_line(tmp_path, capsys):
    path = _pier(tmp_path)
    assert main(["analyze", str(path), "--ignore", "ornamnet"]) == 2
    err = capsys.readouterr().err
    assert "--ignore ornamnet" in err and "'ornament'" in err and len(err.splitlines()) == 1
    assert main(["build", "arch_columns.grammar", "--ignore", "wall"]) == 2
    err = capsys.readouterr().err
    assert "--ignore" in err and "--analyze" in err and len(err.splitlines()) == 1
    assert main(["build", "suspension_bridge.grammar", "--analyze", "--ignore", "deck"]) == 2
    err = capsys.readouterr().err
    assert "block statics" in err and len(err.splitlines()) == 1


def test_the_rule_says_what_is_structure(tmp_path):
    rule = tmp_path / "pier.grammar"
    rule.write_text(
        '@Structure("blocks", ignore = "Boss")\n'
        "Lot --> extrude(2) split(x) { 1: Pier | ~1: NIL }\n"
        "Pier --> [ t(1, 1, 0.4) s(0.3, 0.5, 0.2) Boss ] X\n"
    )
    report = tmp_path / "r.json"
    code = main(["build", str(rule), "--lot", "2,1", "--analyze", "--report", str(report), "-q"])
    assert code == 0, report
    analysis = json.loads(report.read_text())["analysis"]
    assert analysis["bodies"]["ignore"] == ["Boss"] and analysis["bodies"]["riding"] == 1
