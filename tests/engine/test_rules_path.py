"""The rules path, one type (engine.project.rule_packages.RulesPath): made and checked once at
the edge (the command line's --rules-path, load_grammar's rules_path), SHAPEGEN_RULES_PATH read
when it is made, then handed to the import resolution as it is."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from shapegen import load_grammar
from shapegen.cli import main as cli
from shapegen.engine.project import rule_packages
from shapegen.engine.project.rule_packages import RULES_PATH_VARIABLE, RulesPath
from shapegen.errors import GrammarError


def _project(tmp_path: Path) -> tuple[Path, Path]:
    """A rule importing a file of ESRI.lib, which lies in a folder of the rules path."""
    helpers = tmp_path / "lib" / "ESRI.lib" / "rules" / "Helpers"
    helpers.mkdir(parents=True)
    (helpers / "box.cga").write_text("attr h = 4\nBox --> extrude(h) A.\n")
    rules = tmp_path / "proj" / "rules"
    rules.mkdir(parents=True)
    rule = rules / "main.cga"
    rule.write_text('import b : "/ESRI.lib/rules/Helpers/box.cga"\n@StartRule\nLot --> b.Box\n')
    return rule, tmp_path / "lib"


def test_the_options_come_before_the_variable_each_checked_once(tmp_path, monkeypatch):
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir(), second.mkdir()
    monkeypatch.setenv(RULES_PATH_VARIABLE, os.pathsep.join([str(second), str(first)]))
    made = RulesPath.of([first])
    assert made.folders == (first.resolve(), second.resolve())  # once each, the option's first
    assert RulesPath.of(made) is made and RulesPath.of([first]) == made
    assert made.exported() == os.pathsep.join([str(first.resolve()), str(second.resolve())])


def test_an_entry_that_is_no_folder_is_one_line_naming_where_it_came_from(tmp_path, monkeypatch):
    monkeypatch.setenv(RULES_PATH_VARIABLE, str(tmp_path / "gone"))
    with pytest.raises(GrammarError) as caught:
        RulesPath.of()
    assert str(caught.value) == (
        f"{RULES_PATH_VARIABLE} '{tmp_path / 'gone'}': not a folder nor a rule package (.rpk) to"
        " look imports up in"
    )
    monkeypatch.setenv(RULES_PATH_VARIABLE, "")
    with pytest.raises(GrammarError, match=r"^--rules-path '.*nowhere': not a folder"):
        load_grammar(tmp_path / "x.cga", rules_path=[tmp_path / "nowhere"])


def test_the_command_line_refuses_a_missing_folder_in_one_line_before_any_work(tmp_path, capsys):
    rule, _ = _project(tmp_path)
    written = tmp_path / "m.json"
    missing = tmp_path / "nowhere"
    status = cli(["build", str(rule), "--rules-path", str(missing), "-o", str(written)])
    assert status == 2 and not written.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"shapegen: error: --rules-path '{missing}': not a folder nor a rule package"
                   " (.rpk) to look imports up in"]  # fmt: skip


def test_loads_take_the_rules_path_made_once(tmp_path, monkeypatch):
    rule, library = _project(tmp_path)
    monkeypatch.setenv(RULES_PATH_VARIABLE, str(library))
    rule_packages._checked_rules_path.cache_clear()
    for _ in range(3):  # the variable's entries are checked at its first read, not every load
        assert load_grammar(rule).build(lot=(12, 8)).volume == pytest.approx(384)
    info = rule_packages._checked_rules_path.cache_info()
    assert (info.misses, info.hits) == (1, 2)
    given = RulesPath.of([library])  # a RulesPath made at the edge is passed down as it is
    monkeypatch.setenv(RULES_PATH_VARIABLE, "")
    assert load_grammar(rule, rules_path=given).build(lot=(12, 8)).volume == pytest.approx(384)
    with pytest.raises(GrammarError, match="no such file"):
        load_grammar(rule)
