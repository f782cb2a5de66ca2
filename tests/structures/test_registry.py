"""The registry of structures: plug-ins found by name, names that are taken, and the grammar's
@Structure(...) checked against it when the grammar is loaded.

The plug-in here is the smallest structure that needs a model: a design stands when the total
volume of its blocks is under a cap given by @Structure("volume_cap", max_volume = ...).
"""

from __future__ import annotations

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError, OptionError, PluginError
from shapegen.search import optimize
from shapegen.structures import (
    Assessment,
    Design,
    Structure,
    StructureArgument,
    available_structures,
    make_structure,
    register_structure,
    structure_class,
)
from shapegen.structures.cable import CableModel
from shapegen.structures.registry import REGISTRY


class VolumeCap(Structure):
    """Stands when the model's total volume is under ``max_volume``."""

    name = "volume_cap"
    description = "total volume under a cap"
    measure_name = "V/V_max"
    needs_model = True
    arguments = {"max_volume": StructureArgument("largest total volume, m³")}

    def assess(self, design: Design, *, margin: float = 0.0) -> Assessment:
        values = self.checked_arguments(design.arguments)
        cap = (1.0 - margin) * values["max_volume"]
        volume = design.model.volume
        stands = volume < cap
        return Assessment(
            structure=self.name,
            stands=stands,
            measure=0.0 if stands else volume / cap,  # zero exactly when it stands
            status="optimal",
            section={"volume": volume, "max_volume": values["max_volume"]},
            margin=margin,
        )


# A 2 m x 2 m lot extruded to `height`: volume 4 height, under the cap of 20 m³ below 5 m.
CAPPED = """
attr cap = 20
@Free @Range(1, 10)
attr height = 8
@StartRule @Lot(2, 2)
@Structure("volume_cap", max_volume = cap)
Lot --> extrude(height) Stone
"""

CABLE_START = """
attr span = 1000
@StartRule @Lot(10, 10)
@Structure("cable", {arguments})
Lot --> extrude(1) Stone
"""


@pytest.fixture
def registry(monkeypatch):
    """The registry, restored after the test: every entry as it was, and no plug-in left."""
    available_structures()  # the built-in structures (and installed plug-ins) are registered
    for name, cls in list(REGISTRY.items()):
        monkeypatch.setitem(REGISTRY, name, cls)
    # Setting a name that was absent makes monkeypatch delete it again after the test.
    monkeypatch.setitem(REGISTRY, VolumeCap.name, VolumeCap)
    del REGISTRY[VolumeCap.name]
    return REGISTRY


def test_a_registered_plug_in_is_found_by_name(registry):
    assert "volume_cap" not in available_structures()
    assert register_structure(VolumeCap) is VolumeCap
    assert structure_class("volume_cap") is VolumeCap
    assert "volume_cap" in available_structures()
    assert {"blocks", "cable"} <= set(available_structures())
    structure = make_structure("volume_cap")
    assert isinstance(structure, VolumeCap) and structure.options is None
    # Registering the same class again changes nothing.
    assert register_structure(VolumeCap) is VolumeCap
    assert structure_class("volume_cap") is VolumeCap


def test_a_grammar_names_the_plug_in_and_the_search_uses_it(registry):
    register_structure(VolumeCap)
    grammar = parse_grammar(CAPPED)
    assert grammar.structure == "volume_cap"
    assert grammar.structure_arguments() == {"max_volume": 20.0}
    model = grammar.build()
    assert model.metadata["structure"] == {"name": "volume_cap", "arguments": {"max_volume": 20.0}}
    assert not VolumeCap().assess(Design.of_model(model)).stands  # 32 m³

    result = optimize(grammar)
    assert result.structure == "volume_cap" and result.measure == "V/V_max"
    assert (result.gradient, result.method) == ("none", "Powell")  # no gradient from the plug-in
    assert result.feasible and result.converged
    assert 1 <= result.values["height"] < 5
    assert result.model.volume < 20 and result.model.volume == pytest.approx(
        4 * result.values["height"]
    )
    assert result.assessment.section["volume"] == result.model.volume
    assert result.evaluations > 1
    # The arguments follow the attrs: a larger cap is met at once.
    roomy = optimize(grammar, attrs={"cap": 40})
    assert roomy.feasible and roomy.iterations == 0 and roomy.values["height"] == 8


def test_a_taken_name_is_refused_unless_replaced(registry):
    class OtherCable(CableModel):
        pass

    with pytest.raises(PluginError, match="'cable' is already registered by .*CableModel"):
        register_structure(OtherCable)
    assert structure_class("cable") is CableModel
    with pytest.raises(PluginError, match="pass replace=True"):
        register_structure(OtherCable)
    assert register_structure(replace=True)(OtherCable) is OtherCable
    assert structure_class("cable") is OtherCable
    assert isinstance(make_structure("cable"), OtherCable)


@pytest.mark.parametrize(
    ("bad", "words"),
    [(int, "decorates a subclass of Structure"), (Structure, "needs a class attribute 'name'")],
)
def test_only_named_structures_register(registry, bad, words):
    with pytest.raises(PluginError, match=words):
        register_structure(bad)


SUGGESTION = r"unknown structure 'cabel' \(did you mean 'cable'\?\)"


def test_unknown_structure_name_is_an_error_with_a_suggestion():
    with pytest.raises(OptionError, match=SUGGESTION):
        structure_class("cabel")


def test_unknown_structure_in_a_grammar_is_a_load_time_error():
    text = CABLE_START.replace('@Structure("cable", {arguments})', '@Structure("cabel")')
    with pytest.raises(GrammarError, match=SUGGESTION):
        parse_grammar(text)


def test_a_plug_in_is_unknown_to_a_grammar_until_registered(registry):
    with pytest.raises(GrammarError, match="unknown structure 'volume_cap'"):
        parse_grammar(CAPPED)
    register_structure(VolumeCap)
    assert parse_grammar(CAPPED).structure == "volume_cap"


REQUIRED = "main_span = span, sag = span / 10, lanes = 4, max_cable_diameter = 1"


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        (REQUIRED + ", spam = 2", r"structure 'cable' has no argument 'spam'; its arguments: "),
        (REQUIRED + ", side_spam = 2", r"no argument 'side_spam' \(did you mean 'side_span'\?\)"),
        ("main_span = span", r"@Structure\('cable'\) needs the argument\(s\) sag, lanes, max_cab"),
        ("sag = 100, lanes = 4, max_cable_diameter = 1", r"needs the argument\(s\) main_span\n"),
    ],
)
def test_cable_arguments_are_checked_when_the_grammar_loads(arguments, words):
    with pytest.raises(GrammarError, match=words):
        parse_grammar(CABLE_START.format(arguments=arguments))


def test_plug_in_arguments_are_checked_when_the_grammar_loads(registry):
    register_structure(VolumeCap)
    with pytest.raises(GrammarError, match=r"needs the argument\(s\) max_volume"):
        parse_grammar(CAPPED.replace("max_volume = cap", "").replace('cap", ', 'cap"'))
    with pytest.raises(GrammarError, match="structure 'volume_cap' has no argument 'volume'"):
        parse_grammar(CAPPED.replace("max_volume = cap", "max_volume = cap, volume = 2"))


def test_a_structure_is_named_by_a_string():
    text = CABLE_START.replace('@Structure("cable", {arguments})', "@Structure(3)")
    with pytest.raises(GrammarError, match="@Structure names a structure: a string"):
        parse_grammar(text)


def test_a_grammar_without_structure_is_judged_by_block_statics():
    grammar = parse_grammar("@StartRule @Lot(1, 1)\nLot --> extrude(1) Stone\n")
    assert grammar.structure == "blocks"
    assert grammar.structure_arguments() == {}


def test_the_registry_holds_only_the_built_in_structures_after_these_tests():
    assert "volume_cap" not in available_structures()
    assert structure_class("cable") is CableModel
