"""One GeoJSON reader for lots and cities: the same input is a lot in both, or the same problem."""

from __future__ import annotations

import json

import pytest

from shapegen.city import read_lots
from shapegen.errors import InputFormatError
from shapegen.model.lot import Lot
from shapegen.readers import geojson
from shapegen.readers.lot_sources import read_lot


@pytest.mark.parametrize(
    "position, expected",
    [([1, 2], True), ((1.5, 2), True), ([1, 2, 3], True), ([True, 2], False),
     ([1, float("nan")], False), (["1", 2], False), ([1], False), ({"x": 1}, False)],
)  # fmt: skip
def test_a_position_is_two_finite_numbers(position, expected):
    assert geojson.is_point(position) is expected


def test_ids_read_the_same_whole_number_however_written():
    assert geojson.feature_id({"id": 7.0}) == geojson.feature_id({"properties": {"id": 7}}) == "7"
    assert geojson.feature_id({"properties": {}}) is None


@pytest.mark.parametrize(
    "geometry, problem",
    [
        ({"type": "MultiPolygon", "coordinates": [[[[0, 0], [1, 0], [1, 1]]]] * 2},
         "a MultiPolygon of 2 parts"),
        ({"type": "Polygon", "coordinates": [[[0, 0], [True, 0], [1, 1]]]},
         "a corner that is not two finite numbers"),
    ],
)  # fmt: skip
def test_a_lot_and_a_city_refuse_a_ring_in_the_same_words(tmp_path, geometry, problem):
    path = tmp_path / "lots.geojson"
    feature = {"type": "Feature", "id": "a", "properties": {}, "geometry": geometry}
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}))
    with pytest.raises(InputFormatError) as caught:
        read_lot(str(path))
    assert problem in str(caught.value)
    assert problem in read_lots(path, crs="metres").lots[0].problem


def test_a_courtyard_is_a_lot_with_a_hole_in_a_lot_and_in_a_city(tmp_path):
    # RFC 7946: a Polygon's rings after the first are its holes; here a square of 9e-4 degrees
    # at the equator with a courtyard of a third of its side in the middle
    outer = [[0, 0], [9e-4, 0], [9e-4, 9e-4], [0, 9e-4], [0, 0]]
    inner = [[3e-4, 3e-4], [3e-4, 6e-4], [6e-4, 6e-4], [6e-4, 3e-4], [3e-4, 3e-4]]
    geometry = {"type": "Polygon", "coordinates": [outer, inner]}
    feature = {"type": "Feature", "id": "a", "properties": {}, "geometry": geometry}
    path = tmp_path / "lots.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}))
    lot = read_lot(str(path))
    assert len(lot.holes) == 1 and len(lot.holes[0]) == 4
    whole = Lot.polygon(lot.corners).area
    assert lot.area == pytest.approx(whole * 8 / 9, rel=1e-6)
    (city_lot,) = read_lots(path).lots
    assert city_lot.problem is None and len(city_lot.holes) == 1
    assert city_lot.area == pytest.approx(lot.area, rel=1e-9)
