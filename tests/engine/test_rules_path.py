"""The rules path, one type (engine.project.rule_packages.RulesPath): made and checked once at
the edge (the command line's --rules-path, load_grammar's rules_path), SHAPEGEN_RULES_PATH read
when it is made, then handed to the import resolution as it is."""

from __future__ import annotations

import os

import pytest

from shapegen import load_grammar
from shapegen.engine.project.rule_packages import RULES_PATH_VARIABLE, RulesPath
from shapegen.errors import GrammarError


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
