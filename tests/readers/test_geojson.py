"""One GeoJSON reader for lots and cities: the same input is a lot in both, or the same problem."""

from __future__ import annotations

import json

import pytest

from shapegen.city import read_lots
from shapegen.errors import InputFormatError
from shapegen.readers import geojson
from shapegen.readers.lots import read_lot


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
        ({"type": "Polygon", "coordinates": [[[0, 0], [9, 0], [9, 9]], [[1, 1], [2, 1], [2, 2]]]},
         "with 1 hole(s)"),
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
