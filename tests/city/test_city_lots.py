"""Reading lots: GeoJSON and OSM buildings, coordinates, problems kept as rows, the lot's frame."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.city import city_from_polygons, lot_seed, read_lots
from shapegen.city.work import city_lot, lot_extent
from shapegen.errors import InputFormatError
from shapegen.readers.projection import WGS84_A, WGS84_F

DISTRICT = Path(__file__).resolve().parents[2] / "docs" / "data" / "district.geojson"


def _write(tmp_path, document, name="lots.geojson") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(document) if not isinstance(document, str) else document)
    return path


def _collection(*rings, crs=None):
    document = {
        "type": "FeatureCollection",
        "features": [
            {"type": "Feature", "properties": {"n": k}, "geometry": {"type": "Polygon",
             "coordinates": [[list(p) for p in ring] + [list(ring[0])]]}}
            for k, ring in enumerate(rings)
        ],
    }  # fmt: skip
    if crs:
        document["crs"] = {"type": "name", "properties": {"name": crs}}
    return document


def test_the_district_reads_as_thirty_lots_in_lonlat():
    city = read_lots(DISTRICT)
    assert city.crs == "lonlat" and len(city.lots) == 30 and city.skipped == 1
    problems = {lot.id: lot.problem for lot in city.lots if lot.problem}
    assert set(problems) == {"lot-28"} and "distinct corner" in problems["lot-28"]
    (courtyard,) = [lot for lot in city.lots if lot.id == "lot-29"]
    assert len(courtyard.holes) == 1  # a 20 x 20 m lot around an 8 x 8 m courtyard
    assert courtyard.area == pytest.approx(20 * 20 - 8 * 8, rel=1e-5)
    for lot in city.lots:
        if not lot.problem:
            assert lot.area > 0  # counter-clockwise seen from above


def test_lonlat_is_projected_to_metres_on_the_ellipsoid():
    # 0.001 degree of latitude at 46 N is M * radians, M the meridional radius of curvature.
    lat, lon, d = 46.0, 4.0, 0.001
    ring = [(lon, lat), (lon + d, lat), (lon + d, lat + d), (lon, lat + d)]
    city = city_from_polygons([ring], crs="lonlat")
    lot = city.lots[0]
    e2 = WGS84_F * (2 - WGS84_F)
    phi = math.radians(lat + d / 2)
    meridional = WGS84_A * (1 - e2) / (1 - e2 * math.sin(phi) ** 2) ** 1.5
    north = np.ptp(lot.ring[:, 1])
    assert north == pytest.approx(meridional * math.radians(d), rel=1e-6)
    prime = WGS84_A / math.sqrt(1 - e2 * math.sin(math.radians(lat)) ** 2)
    east = lot.ring[1, 0] - lot.ring[0, 0]
    assert east == pytest.approx(prime * math.cos(math.radians(lat)) * math.radians(d), rel=1e-5)


def test_metres_are_detected_and_centred(tmp_path):
    ring = [(500_000, 5_000_000), (500_012, 5_000_000), (500_012, 5_000_008), (500_000, 5_000_008)]
    city = read_lots(_write(tmp_path, _collection(ring)))
    assert city.crs == "metres" and city.origin == (500_006.0, 5_000_004.0)
    assert np.allclose(city.lots[0].ring, [[-6, -4], [6, -4], [6, 4], [-6, 4]])


def test_metres_near_the_origin_read_as_degrees_are_a_lot_problem(tmp_path):
    ring = [(0, 0), (12, 0), (12, 8), (0, 8)]
    city = read_lots(_write(tmp_path, _collection(ring)))
    assert city.crs == "lonlat" and "are its coordinates metres? (--crs metres)" in (
        city.lots[0].problem
    )
    assert read_lots(_write(tmp_path, _collection(ring)), crs="metres").lots[0].problem is None


def test_clockwise_rings_are_turned_counter_clockwise_keeping_the_first_corner(tmp_path):
    ring = [(0, 0), (0, 8), (12, 8), (12, 0)]  # clockwise
    city = read_lots(_write(tmp_path, _collection(ring)), crs="metres")
    lot = city.lots[0]
    assert lot.area == pytest.approx(96.0)
    assert np.allclose(lot.ring[0], np.array([0, 0]) - city.origin)


@pytest.mark.parametrize(
    ("crs_member", "given", "expected"),
    [
        ("urn:ogc:def:crs:OGC:1.3:CRS84", None, "lonlat"),
        ("EPSG:4326", None, "lonlat"),
        ("EPSG:25832", None, "EPSG:25832"),
        ("urn:ogc:def:crs:EPSG::25832", "EPSG:25832", "EPSG:25832"),
    ],
)
def test_a_crs_member_is_honoured(tmp_path, crs_member, given, expected):
    ring = [(4.0, 46.0), (4.0001, 46.0), (4.0001, 46.0001)]
    if expected != "lonlat":  # UTM 32N metres near Munich
        ring = [(690_000.0, 5_335_000.0), (690_010.0, 5_335_000.0), (690_010.0, 5_335_010.0)]
    city = read_lots(_write(tmp_path, _collection(ring, crs=crs_member)), crs=given)
    assert city.crs == expected


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("not json", "not a GeoJSON file"),
        ({"type": "Topology"}, "not GeoJSON"),
        ({"type": "FeatureCollection", "features": []}, "no polygons"),
        (_collection([(0, 0), (1, 0), (1, 1)], crs="EPSG:99999"), "not a coordinate system"),
    ],
)
def test_bad_files_get_one_line(tmp_path, content, message):
    with pytest.raises(InputFormatError, match=message) as caught:
        read_lots(_write(tmp_path, content))
    assert "\n" not in str(caught.value)


def test_two_lots_with_one_id_are_refused(tmp_path):
    document = _collection([(0, 0), (5, 0), (5, 5)], [(9, 0), (15, 0), (15, 5)])
    for feature in document["features"]:
        feature["id"] = "same"
    with pytest.raises(InputFormatError, match="two lots have the id 'same'"):
        read_lots(_write(tmp_path, document))


@pytest.mark.parametrize(
    ("geometry", "problem"),
    [
        ({"type": "Polygon", "coordinates": [[[0, 0], [2, 2], [2, 0], [0, 2], [0, 0]]]},
         "the polygon crosses itself"),
        ({"type": "MultiPolygon", "coordinates": [[[[0, 0], [1, 0], [1, 1]]],
                                                   [[[5, 0], [6, 0], [6, 1]]]]}, "2 parts"),
        ({"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 0]]]},
             "a lot needs at least 3 distinct corners, got 2"),
        ({"type": "Polygon", "coordinates": [[[0, 0], ["a", 0], [1, 1]]]}, "two finite numbers"),
    ],
)  # fmt: skip
def test_a_lot_that_cannot_be_built_is_kept_with_its_problem(tmp_path, geometry, problem):
    good = {"type": "Polygon", "coordinates": [[[10, 0], [20, 0], [20, 10], [10, 0]]]}
    document = {
        "type": "FeatureCollection",
        "features": [
            {"type": "Feature", "id": "bad", "properties": {}, "geometry": geometry},
            {"type": "Feature", "id": "good", "properties": {}, "geometry": good},
        ],
    }
    city = read_lots(_write(tmp_path, document), crs="metres")
    assert problem in city.lots[0].problem and city.lots[1].problem is None


OSM = """<?xml version="1.0"?>
<osm version="0.6">
 <node id="1" lat="46.4340" lon="4.6590"/><node id="2" lat="46.4340" lon="4.6592"/>
 <node id="3" lat="46.4341" lon="4.6592"/><node id="4" lat="46.4341" lon="4.6590"/>
 <node id="5" lat="46.4345" lon="4.6590"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="4"/><nd ref="1"/>
  <tag k="building" v="house"/><tag k="storeys" v="3"/></way>
 <way id="11"><nd ref="1"/><nd ref="5"/><tag k="highway" v="path"/></way>
</osm>
"""


def test_osm_buildings_are_closed_ways_tagged_building(tmp_path):
    city = read_lots(_write(tmp_path, OSM, "town.osm"))
    assert [lot.id for lot in city.lots] == ["way/10"]
    lot = city.lots[0]
    assert lot.properties == {"building": "house", "storeys": "3"}
    assert 15.0 < np.ptp(lot.ring[:, 0]) < 16.0 and 11.0 < np.ptp(lot.ring[:, 1]) < 11.2


def test_seeds_come_from_the_lot_id_and_the_run_seed():
    assert lot_seed("lot-01") == lot_seed("lot-01")
    seeds = {lot_seed(f"lot-{k}") for k in range(200)}
    assert len(seeds) == 200 and all(0 <= s < 2**31 for s in seeds)
    assert lot_seed("lot-01", 1) != lot_seed("lot-01", 0)


@pytest.mark.parametrize("angle", [0.0, 30.0, 135.0, 250.0])
def test_a_rectangular_lot_is_derived_on_its_polygon_without_mirroring(angle):
    width, depth = 12.0, 8.0
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    along, left = np.array([c, s]), np.array([-s, c])  # east/north; left of the first edge
    corner = np.array([100.0, -50.0])
    ring = np.array([corner, corner + width * along, corner + width * along + depth * left,
                     corner + depth * left])  # fmt: skip
    lot, footprint = lot_extent(ring)
    assert footprint == "rectangle" and lot == pytest.approx((width, depth))
    model = parse_grammar("Lot --> extrude(1) X.", "lot.cga").build(lot=city_lot(ring).tolist())
    (block,) = model.blocks
    footprint_xz = {tuple(np.round(v[[0, 2]], 6)) for v in block.vertices}
    expected = {tuple(np.round([e, -n], 6)) for e, n in ring}  # east +x, north -z
    assert footprint_xz == expected


def test_a_lot_that_is_not_a_rectangle_has_its_bounding_rectangle_as_scope():
    ring = np.array([(0, 0), (14, 0), (12, 10), (1, 9)], dtype=float)
    lot, footprint = lot_extent(ring)
    assert footprint == "polygon" and lot == pytest.approx((14.0, 10.0))
