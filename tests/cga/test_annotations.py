"""CityEngine's inspector annotations take CityEngine's own words as arguments; shapegen never
evaluates them, so their names are not looked up (a typo elsewhere still is)."""

from __future__ import annotations

import pytest

import shapegen
from shapegen.errors import GrammarError


@pytest.mark.parametrize(
    "annotation",
    [
        "@Handle(shape=Lot, axis=y, slip=screen, reference=center)",
        "@Location(shape=Lot, slip=screen)",
        "@Out(granularity=separate)",
        '@File("assets") @Group("Building", 1) @Order(2)',
    ],
)
def test_inspector_annotations_load(tmp_path, annotation):
    path = tmp_path / "annotated.cga"
    path.write_text(f"{annotation}\nattr height = 10\n@StartRule\nLot --> extrude(height) X.\n")
    model = shapegen.load_grammar(path).build(lot=(12, 8))
    assert model.blocks[0].volume == pytest.approx(960)


def test_names_in_evaluated_annotations_are_still_checked(tmp_path):
    # an inspector @Range with an undefined name is ignored with a warning; a @Free one bounds
    # the search, so it stays an error
    path = tmp_path / "range.cga"
    path.write_text("@Range(min=1, max=hieght)\nattr height = 10\n@StartRule\nLot --> X.\n")
    grammar = shapegen.load_grammar(path)
    (warning,) = grammar.build(lot=(12, 8)).metadata["warnings"]
    assert "undefined name 'hieght'" in warning and "the @Range is ignored" in warning
    assert grammar.parameter_ranges() == {}
    path.write_text("@Free @Range(min=1, max=hieght)\nattr height = 10\n@StartRule\nLot --> X.\n")
    with pytest.raises(GrammarError, match="undefined name 'hieght'"):
        shapegen.load_grammar(path)
