"""Lots in any coordinate system pyproj knows: a GeoJSON crs member, a .prj beside the file,
--crs; every system read as ground metres; one line for each mistake."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

pyproj = pytest.importorskip("pyproj")

from shapegen.city import city_from_polygons, read_lots  # noqa: E402
from shapegen.errors import InputFormatError  # noqa: E402
from shapegen.readers.lot_sources import read_lot  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "docs" / "data"
LONLAT = DATA / "district.geojson"
MERCATOR = DATA / "district_3857.geojson"
LAMBERT = DATA / "district_l93.geojson"  # EPSG:2154 said by district_l93.prj alone


def _square_on_the_ground(side_m: float, lon=4.659, lat=46.434) -> np.ndarray:
    """``(4, 2)`` lon/lat of a square with geodesic sides of ``side_m`` (pyproj.Geod), its
    first edge due east."""
    geod = pyproj.Geod(ellps="WGS84")
    corners = [(lon, lat)]
    for azimuth in (90.0, 0.0, 270.0):
        lon, lat, _ = geod.fwd(lon, lat, azimuth, side_m)
        corners.append((lon, lat))
    return np.array(corners)


def _in(code: str, lonlat: np.ndarray) -> list[tuple[float, float]]:
    transformer = pyproj.Transformer.from_crs("OGC:CRS84", code, always_xy=True)
    x, y = transformer.transform(lonlat[:, 0], lonlat[:, 1])
    return list(zip(x, y, strict=True))


def test_the_district_in_web_mercator_and_lambert_93_loads_without_options():
    reference = read_lots(LONLAT)
    for path, code in [(MERCATOR, "EPSG:3857"), (LAMBERT, "EPSG:2154")]:
        city = read_lots(path)
        assert city.crs == code and city.frame()["crs"] == code
        assert [lot.id for lot in city.lots] == [lot.id for lot in reference.lots]
        assert [lot.problem for lot in city.lots] == [lot.problem for lot in reference.lots]
        assert np.allclose(city.origin_lonlat, reference.origin_lonlat, atol=1e-8)
        for lot, same in zip(city.lots, reference.lots, strict=True):
            # the same lots, to the millimetre (the files are rounded to 0.1 mm)
            assert lot.ring.shape == same.ring.shape
            assert np.abs(lot.ring - same.ring).max(initial=0.0) < 1e-3, lot.id
            assert lot.geometry != same.geometry  # the input coordinates are kept as read


@pytest.mark.parametrize("code", ["EPSG:3857", "EPSG:2154", "EPSG:32631"])
def test_a_10_m_square_on_the_ground_is_10_m_in_every_system(code):
    square = _square_on_the_ground(10.0)
    corners = _in(code, square)
    city = city_from_polygons([corners], crs=code)
    ring = city.lots[0].ring
    sides = np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)
    assert np.allclose(sides, 10.0, atol=1e-3), sides
    assert city.lots[0].area == pytest.approx(100.0, abs=0.02)
    if code == "EPSG:3857":
        # Web Mercator's metres are 1/cos(lat) of the ground's: 14.5 of them for 10 m at 46.4 N
        mercator = np.hypot(*np.subtract(corners[1], corners[0]))
        assert mercator / 10.0 == pytest.approx(1 / math.cos(math.radians(46.434)), rel=3e-3)


def test_a_lot_from_a_projected_file_is_the_lonlat_lot():
    for path in (MERCATOR, LAMBERT):
        got = np.array(read_lot(f"{path}#lot-01").corners)
        assert np.abs(got - np.array(read_lot(f"{LONLAT}#lot-01").corners)).max() < 1e-3


def test_crs_option_and_file_must_agree(tmp_path):
    assert read_lots(MERCATOR, crs="EPSG:3857").crs == "EPSG:3857"
    assert read_lots(MERCATOR, crs="urn:ogc:def:crs:EPSG::3857").crs == "EPSG:3857"
    with pytest.raises(InputFormatError, match="--crs metres would take"):
        read_lots(MERCATOR, crs="metres")
    with pytest.raises(InputFormatError, match="--crs EPSG:2154 but its crs member says EPSG:3857"):
        read_lots(MERCATOR, crs="EPSG:2154")
    # a file without a crs member nor .prj is read in the system --crs names
    plain = json.loads(LAMBERT.read_text())
    path = tmp_path / "lots.geojson"
    path.write_text(json.dumps(plain))
    city = read_lots(path, crs="EPSG:2154")
    assert np.abs(city.lots[0].ring - read_lots(LONLAT).lots[0].ring).max() < 1e-3
    # the same coordinates as local metres: another frame, refused by nothing, said in the frame
    assert read_lots(path, crs="metres").frame()["crs"] == "metres"


def _lots_file(tmp_path, crs_member=None, prj=None) -> Path:
    ring = [[827000.0, 6594000.0], [827010.0, 6594000.0], [827010.0, 6594010.0]]
    document = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
         "coordinates": [ring + [ring[0]]]}}]}  # fmt: skip
    if crs_member is not None:
        document["crs"] = crs_member
    path = tmp_path / "lots.geojson"
    path.write_text(json.dumps(document))
    if prj is not None:
        path.with_suffix(".prj").write_text(prj)
    return path


@pytest.mark.parametrize(
    ("member", "prj", "option", "message"),
    [
        ({"type": "name", "properties": {"name": "EPSG:99999"}}, None, None,
         "'EPSG:99999' is not a coordinate system pyproj knows"),
        (None, None, "EPSG:99999", "--crs EPSG:99999: 'EPSG:99999' is not a coordinate system"),
        (None, "PROJCS[broken", None, "lots.prj: not a coordinate system in WKT"),
        (None, "\udcff", None, "lots.prj: cannot read it"),
        ({"type": "name", "properties": {"name": "EPSG:4258"}}, None, None,
         r"EPSG:4258 \(ETRS89\) is longitude/latitude on another datum than WGS84"),
        (None, None, "EPSG:4978", r"EPSG:4978 \(WGS 84\) is not a map projection"),
        ({"type": "link", "properties": {"href": "x"}}, None, None, "its crs member names no"),
        ({"type": "name", "properties": {"name": "EPSG:3857"}},
         pyproj.CRS("EPSG:2154").to_wkt(), None,
         "its crs member says EPSG:3857 and .*lots.prj says EPSG:2154"),
    ],
)  # fmt: skip
def test_each_crs_mistake_is_one_line(tmp_path, member, prj, option, message):
    if prj == "\udcff":
        path = _lots_file(tmp_path)
        path.with_suffix(".prj").write_bytes(b"\xff\xfe\x00bad")
    else:
        path = _lots_file(tmp_path, member, prj)
    with pytest.raises(InputFormatError, match=message) as caught:
        read_lots(path, crs=option)
    assert "\n" not in str(caught.value)


def test_osm_stays_lonlat(tmp_path):
    osm = tmp_path / "b.osm"
    osm.write_text(
        '<?xml version="1.0"?><osm version="0.6">'
        '<node id="1" lat="46.4340" lon="4.6590"/><node id="2" lat="46.4340" lon="4.6592"/>'
        '<node id="3" lat="46.4341" lon="4.6592"/>'
        '<way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="1"/>'
        '<tag k="building" v="yes"/></way></osm>'
    )
    city = read_lots(osm)
    assert city.crs == "lonlat" and city.lots[0].problem is None
    assert read_lots(osm, crs="EPSG:4326").crs == "lonlat"
    with pytest.raises(InputFormatError, match="OSM nodes are longitude/latitude"):
        read_lots(osm, crs="EPSG:2154")
