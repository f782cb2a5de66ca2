"""A structure shipped by an installed package (entry-point group ``shapegen.structures``) is
found by name, checked at load time and driven by the search like the built-in ones."""

import sys
from pathlib import Path

import pytest

import shapegen
from shapegen import plugins
from shapegen.search import optimize
from shapegen.structures import registry, structure_class

PLUGIN_DIR = Path(__file__).parent / "plugin_pkg"

TOWER = """
@Free @Range(1, 20)
attr height = 12
@StartRule @Lot(2, 2)
@Structure("height_cap", max_height = 8)
Lot --> extrude(height) Stone
"""


@pytest.fixture
def installed(monkeypatch):
    structure_class("blocks")  # the built-ins first
    monkeypatch.setattr(registry, "REGISTRY", dict(registry.REGISTRY))
    monkeypatch.syspath_prepend(str(PLUGIN_DIR))
    monkeypatch.setattr(plugins, "LOADED_GROUPS", set())
    yield
    sys.modules.pop("height_cap_plugin", None)


def test_an_installed_structure_is_found_and_drives_the_search(installed):
    assert structure_class("height_cap").name == "height_cap"
    grammar = shapegen.parse_grammar(TOWER)
    assert grammar.structure == "height_cap"
    result = optimize(grammar)
    assert result.feasible and result.method == "Powell"  # no gradient: derivative-free
    assert result.values["height"] <= 8.0 + 1e-9
    assert result.assessment.section["height"] == pytest.approx(result.values["height"])


def test_an_unknown_argument_of_the_plugin_is_a_load_time_error(installed):
    with pytest.raises(shapegen.GrammarError, match="did you mean 'max_height'"):
        shapegen.parse_grammar(TOWER.replace("max_height", "max_heigth"))
