"""Values a rule reads of its shape: geometry.isOriented with its selector (func_geometry), the
deprecated uid and initialShape.symbol (cga_changelog), getGeoCoord without a georeference
(func_getGeoCoord), geometry.materials as CityEngine's runtime names the one material, and the
geometry functions shapegen does not answer refused when the file loads."""

from __future__ import annotations

import math

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_is_oriented_takes_a_face_selector": ("func:geometry.isOriented",),
    "test_uid_numbers_each_shape_with_a_warning": ("attr:uid",),
    "test_initial_shape_names": (
        "attr:initialShape.startRule",
        "attr:initialShape.name",
        "attr:initialShape.symbol",
    ),
    "test_get_geo_coord_without_a_georeference": ("func:getGeoCoord",),
    "test_geometry_materials_names_the_one_material": ("func:geometry.materials",),
}


def _build(text: str, lot=(12.0, 8.0)):
    return parse_grammar("@StartRule\n" + text, "values.cga").build(lot=lot)


@pytest.mark.parametrize(
    ("where", "selector", "expected"),
    [
        ("", "world.up", True),
        ("", "world.down", True),
        ("", "world.north", True),
        ("", "top", True),
        ("comp(f) { front : ", "world.south", True),
        ("comp(f) { front : ", "world.up", False),
        ("comp(f) { front : ", "front", True),  # a comp face's normal is its scope's z
        ("comp(f) { front : ", "object.side", True),
        ("comp(f) { top : ", "world.side", False),
        ("comp(f) { top : ", "street.front", False),
    ],
)
def test_is_oriented_takes_a_face_selector(where, selector, expected):
    # func_geometry: true if at least one of the geometry's faces matches the selector
    close = " }" if where else ""
    model = _build(
        f'Lot --> extrude(3) {where}report("o", geometry.isOriented({selector})) X.{close}'
    )
    assert model.metadata["reports"]["o"] is expected


def test_uid_numbers_each_shape_with_a_warning():
    model = _build(
        'Lot --> extrude(3) report("lot", uid) report("again", uid) '
        'split(x) { 6 : report("piece", uid) X. }*'
    )
    reports = model.metadata["reports"]
    assert reports["lot"] == reports["again"]  # the same shape
    pieces = reports["piece"]
    assert len(set(pieces)) == 2 and reports["lot"] not in pieces
    assert any("uid is deprecated" in w for w in model.metadata["warnings"])


def test_initial_shape_names():
    model = _build(
        'Lot --> report("start", initialShape.startRule) report("name", initialShape.name) '
        'report("symbol", initialShape.symbol) X.'
    )
    reports = model.metadata["reports"]
    assert reports["start"] == reports["symbol"] == "Lot"
    assert reports["name"] == "Lot"
    assert any("initialShape.symbol is deprecated" in w for w in model.metadata["warnings"])


def test_get_geo_coord_without_a_georeference():
    # the scene's own coordinates in metres: X east (+x), Y north (-z) of the scope's origin;
    # no WGS84 coordinate without a georeference
    model = _build(
        "Lot --> extrude(3) comp(f) { right : "
        'report("X", getGeoCoord(X)) report("Y", getGeoCoord(Y)) report("lat", getGeoCoord(lat)) '
        "X. }"
    )
    reports = model.metadata["reports"]
    assert (reports["X"], reports["Y"]) == (12.0, -8.0)  # the right face starts at (12, 0, 8)
    assert math.isnan(reports["lat"])
    assert any("no georeference" in w for w in model.metadata["warnings"])


# PyPRT 1.12 reports geometry.materials as (1)[CityEngineMaterial] for the lot, extrude(5),
# primitiveCube(), primitiveSphere() and i() of an asset not found (its box of 6 faces).
@pytest.mark.parametrize("before", ["", "extrude(5) ", "primitiveSphere() ", 'i("none.obj") '])
def test_geometry_materials_names_the_one_material(before):
    model = _build(
        f'Lot --> {before}report("m", str(geometry.materials)) '
        'report("i", findFirst(geometry.materials, "CityEngineMaterial")) X.'
    )
    assert model.metadata["reports"]["m"] == "(1)[CityEngineMaterial]"
    assert model.metadata["reports"]["i"] == 0.0
    assert any("geometry.materials: " in w for w in model.metadata["warnings"])


@pytest.mark.parametrize("read", ["geometry.groups"])
def test_geometry_functions_shapegen_does_not_answer_are_refused_when_loaded(read):
    with pytest.raises(GrammarError, match="is not supported by shapegen"):
        parse_grammar(f"@StartRule\nLot --> print({read}) X.", "values.cga")
