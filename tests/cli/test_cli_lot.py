"""``--lot``: a width and depth, a polygon, a GeoJSON feature (longitude/latitude or metres)
or an OBJ face; bad polygons are one clear line naming the input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import shapely

from shapegen.cli import main
from shapegen.errors import InputFormatError
from shapegen.model.lot import Lot
from shapegen.readers.lot_sources import checked_polygon, read_lot

# WGS84 (the ellipsoid shapegen.readers.projection projects on)
A = 6378137.0
E2 = 6.69437999014e-3


def _metres_per_degree(lat: float) -> tuple[float, float]:
    """Closed-form lengths of one degree of longitude and of latitude at ``lat`` (m): the
    prime-vertical radius times cos(lat), and the meridian radius of curvature."""
    phi = math.radians(lat)
    w = math.sqrt(1 - E2 * math.sin(phi) ** 2)
    east = math.radians(1) * A * math.cos(phi) / w
    north = math.radians(1) * A * (1 - E2) / w**3
    return east, north


def _area_and_turn(points) -> tuple[float, float]:
    x, z = np.asarray(points).T
    shoelace = float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)) / 2
    return abs(shoelace), -np.sign(shoelace)  # +1: counter-clockwise seen from above (+y)


# ------------------------------------------------------------------------------ text forms
@pytest.mark.parametrize("text", ["12,8", "12x8", " 12,8 ", "12X8"])
def test_rectangles(text):
    assert read_lot(text) == Lot.rectangle(12.0, 8.0)


def test_polygon_counter_clockwise_from_above_is_kept():
    assert read_lot("0,8 12,8 12,0 0,0").corners == ((0, 8), (12, 8), (12, 0), (0, 0))


def test_polygon_given_clockwise_is_reversed_keeping_its_first_corner():
    lot = read_lot("0,0 12,0 12,8 0,8 0,0").corners  # the closing corner is dropped too
    assert lot == ((0, 0), (0, 8), (12, 8), (12, 0))
    area, turn = _area_and_turn(lot)
    assert (area, turn) == (96.0, 1.0)


@pytest.mark.parametrize(
    "text, message",
    [
        ("0,0 1,1", r"'0,0 1,1': a lot needs at least 3 distinct corners, got 2"),
        ("0,0 1,1 0,0 1,1", r"the polygon has no area"),
        ("0,0 1,0 3,0", r"the polygon has no area \(its corners are in a line\)"),
        ("0,0 1,1 1,0 0,1", r"the polygon crosses itself \(self-intersection at x=0\.5, z=0\.5\)"),
        ("0,0 nan,1 1,1", r"corner coordinates must be finite numbers"),
        ("0,0 inf,1 1,1", r"corner coordinates must be finite numbers"),
        ("0,0 1 1,1", r"a corner is x,z in metres, got '1'"),
        ("0,0 a,1 1,1", r"'a' is not a number"),
        ("1,x", r"'x' is not a number"),
        ("0,8", r"lot width and depth must be finite numbers > 0 m, got 0 x 8"),
        ("inf,8", r"lot width and depth must be finite numbers > 0 m, got inf x 8"),
        ("12", r"expected WIDTH,DEPTH \(m\), corners"),
    ],
)
def test_bad_lots_are_one_line_naming_the_input(text, message):
    with pytest.raises(InputFormatError, match=message) as caught:
        read_lot(text)
    assert str(caught.value).startswith(f"--lot {text!r}") and "\n" not in str(caught.value)


@pytest.mark.parametrize(
    "text", ["0,0 1,1 1,0 0,1", "0,0 1,0 3,0", "0,0 nan,1 1,1", "1,x", "missing.geojson"]
)
def test_cli_refuses_a_bad_lot_with_status_2(text, capsys):
    assert main(["build", "wall_windows.grammar", "--lot", text]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("shapegen: error: argument --lot: ") and "Traceback" not in err


# ------------------------------------------------------------------------------ GeoJSON
def _lonlat_rectangle(lat=46.434, lon=4.659, width=12.0, depth=8.0, clockwise=False):
    """A width x depth m rectangle (east x north) as lon/lat corners, counter-clockwise."""
    east, north = _metres_per_degree(lat)
    dx, dy = width / east, depth / north
    ring = [[lon, lat], [lon + dx, lat], [lon + dx, lat + dy], [lon, lat + dy], [lon, lat]]
    return ring[::-1] if clockwise else ring


def _write(path, document):
    path.write_text(json.dumps(document))
    return path


def _feature(ring, feature_id=None, kind="Polygon", properties=None):
    coordinates = [ring] if kind == "Polygon" else [[ring]]
    feature = {"type": "Feature", "properties": properties or {},
               "geometry": {"type": kind, "coordinates": coordinates}}  # fmt: skip
    if feature_id is not None:
        feature["id"] = feature_id
    return feature


def test_geojson_lonlat_is_projected_to_metres(tmp_path):
    """A 12 x 8 m rectangle given in degrees comes back 12 x 8 m (closed-form degree lengths)."""
    collection = {"type": "FeatureCollection", "features": [_feature(_lonlat_rectangle())]}
    path = _write(tmp_path / "lot.geojson", collection)
    lot = read_lot(str(path)).corners
    sides = np.linalg.norm(np.diff(np.vstack([lot, lot[:1]]), axis=0), axis=1)
    assert sides == pytest.approx([12, 8, 12, 8], abs=2e-3)
    area, turn = _area_and_turn(lot)
    assert area == pytest.approx(96.0, rel=1e-4) and turn == 1.0
    # east along +x, north along -z, about the lot's centre
    assert np.mean(lot, axis=0) == pytest.approx([0.0, 0.0], abs=1e-4)
    assert lot[1][0] - lot[0][0] == pytest.approx(12.0, abs=2e-3)  # first edge runs east
    assert lot[2][1] - lot[1][1] == pytest.approx(-8.0, abs=2e-3)  # then north: -z


def test_geojson_feature_by_id_and_the_first_polygon(tmp_path):
    features = [
        {"type": "Feature", "geometry": {"type": "Point", "coordinates": [4.66, 46.43]}},
        _feature(_lonlat_rectangle(width=10, depth=10), feature_id="a"),
        _feature(_lonlat_rectangle(width=20, depth=5), properties={"id": 7}, kind="MultiPolygon"),
    ]
    path = _write(tmp_path / "lots.geojson", {"type": "FeatureCollection", "features": features})
    assert _area_and_turn(read_lot(str(path)).corners)[0] == pytest.approx(100, rel=1e-4)
    assert _area_and_turn(read_lot(f"{path}#7").corners)[0] == pytest.approx(100, rel=1e-4)
    with pytest.raises(InputFormatError, match=r"lots\.geojson#b: no feature with id 'b' \(a, 7\)"):
        read_lot(f"{path}#b")


def test_geojson_in_a_projected_crs_is_read_in_ground_metres(tmp_path):
    # Lambert-93 near Cluny, where its scale factor is 0.99905 and its grid north 1.2 degrees
    # off true north: 12 x 8 grid metres are 12.011 x 8.008 on the ground, and the lot is the
    # one its lon/lat corners give
    pyproj = pytest.importorskip("pyproj")
    ring = [[827000, 6594000], [827012, 6594000], [827012, 6594008], [827000, 6594008]]
    crs = {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}}
    geometry = {"type": "Polygon", "coordinates": [ring]}
    path = _write(tmp_path / "m.geojson", {"type": "Feature", "crs": crs, "geometry": geometry})
    lot = np.array(read_lot(str(path)).corners)
    to_lonlat = pyproj.Transformer.from_crs("EPSG:2154", "OGC:CRS84", always_xy=True)
    lonlat = [list(to_lonlat.transform(x, y)) for x, y in ring]
    plain = _write(tmp_path / "ll.geojson", {"type": "Polygon", "coordinates": [lonlat]})
    assert np.abs(lot - np.array(read_lot(str(plain)).corners)).max() < 1e-6
    width, depth = np.hypot(*(lot[1] - lot[0])), np.hypot(*(lot[2] - lot[1]))
    scale = pyproj.Proj("EPSG:2154").get_factors(*lonlat[0]).meridional_scale
    assert width == pytest.approx(12 / scale, abs=1e-3) and width != pytest.approx(12, abs=1e-3)
    assert depth == pytest.approx(8 / scale, abs=1e-3)


@pytest.mark.parametrize(
    "document, message",
    [
        ({"type": "Topology"}, r"not GeoJSON \(type 'Topology'; expected a FeatureCollection"),
        ({"type": "FeatureCollection", "features": []}, r"no Polygon or MultiPolygon feature"),
        ({"type": "Polygon", "coordinates": [[[0, 0], [0.0001, 0], [0, 0.0001]],
                                             [[0, 0], [1e-5, 0], [0, 1e-5]]]},
         r"the lot's holes do not fit inside it \(self-intersection"),  # on the outline
        ({"type": "MultiPolygon", "coordinates": [[[[0, 0], [1e-4, 0], [0, 1e-4]]]] * 2},
         r"a MultiPolygon of 2 parts"),
        ({"type": "Polygon", "coordinates": [[[0, 0], [12, 0], [12, 8], [0, 8]]]},
         r"read as longitude/latitude, the lot spans 12 degrees"),
        ({"type": "Polygon", "coordinates": [[[0, 0], ["a", 0], [0, 1e-4]]]},
         r"a corner that is not two finite numbers"),
        ({"type": "Polygon", "coordinates": [[[0, 0], [1e-4, 1e-4], [1e-4, 0], [0, 1e-4]]]},
         r"the polygon crosses itself"),
    ],
)  # fmt: skip
def test_bad_geojson_is_one_line(tmp_path, document, message):
    path = _write(tmp_path / "bad.geojson", document)
    with pytest.raises(InputFormatError, match=message) as caught:
        read_lot(str(path))
    assert str(caught.value).startswith(f"--lot {path}")


def test_geojson_that_is_not_json(tmp_path):
    path = tmp_path / "x.geojson"
    path.write_text("{not json")
    with pytest.raises(InputFormatError, match=r"x\.geojson:1:2: invalid JSON"):
        read_lot(str(path))


# ------------------------------------------------------------------------------ OBJ
def test_obj_first_face(tmp_path):
    path = tmp_path / "plot.obj"
    path.write_text("# a plot\nv 0 0 0\nv 10 0 0\nv 10 0 6\nv 4 0 6\nv 4 0 3\nv 0 0 3\n"
                    "vt 0 0\nf 1/1 2/1 3/1 4/1 5/1 6/1\nf 1 2 3\n")  # fmt: skip
    lot = read_lot(str(path)).corners
    area, turn = _area_and_turn(lot)
    assert (area, turn) == (10 * 6 - 4 * 3, 1.0)
    assert lot[0] == (0.0, 0.0)  # clockwise from above: reversed, first corner kept
    assert shapely.Polygon(lot).is_valid


@pytest.mark.parametrize(
    "text, message",
    [
        ("v 0 0 0\nv 1 0 0\n", r"the file has no face"),
        ("v 0 0 0\nf 1 2 3\n", r":2: the face names vertex 2, which is not defined"),
        ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", r"\(its first face\): the polygon has no area"),
    ],
)
def test_bad_obj_is_one_line(tmp_path, text, message):
    path = tmp_path / "plot.obj"
    path.write_text(text)
    with pytest.raises(InputFormatError, match=message):
        read_lot(str(path))


def test_checked_polygon_accepts_arrays():
    assert checked_polygon(np.array([[0, 1], [1, 1], [1, 0]]), "test").corners == (
        (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)
    )  # fmt: skip


# ------------------------------------------------------------------------------ end to end
def _blocks(path):
    return json.loads(path.read_text())["blocks"]


def test_a_rectangle_polygon_builds_the_width_by_depth_model(tmp_path):
    """CityEngine's 12 x 8 lot: corners counter-clockwise from above, first edge along +x."""
    polygon, rectangle = tmp_path / "polygon.json", tmp_path / "rectangle.json"
    assert main(["build", "wall_windows.grammar", "--lot", "0,8 12,8 12,0 0,0", "-q",
                 "-o", str(polygon)]) == 0  # fmt: skip
    assert main(["build", "wall_windows.grammar", "--lot", "12x8", "-q", "-o", str(rectangle)]) == 0
    assert _blocks(polygon) == _blocks(rectangle)


def test_a_geojson_lot_builds_on_its_footprint(tmp_path):
    grammar = tmp_path / "mass.grammar"
    grammar.write_text("@StartRule\nLot --> extrude(3) Mass.\n")
    collection = {"type": "FeatureCollection",
                  "features": [_feature(_lonlat_rectangle(), feature_id="plot-1")]}  # fmt: skip
    lots = _write(tmp_path / "lots.geojson", collection)
    report = tmp_path / "report.json"
    assert main(["build", str(grammar), "--lot", f"{lots}#plot-1", "-q",
                 "--report", str(report)]) == 0  # fmt: skip
    built = json.loads(report.read_text())
    assert built["blocks"] == 1 and built["volume"] == pytest.approx(12 * 8 * 3, rel=1e-4)


def test_an_l_shaped_lot_is_a_surface_and_says_so(tmp_path, capsys):
    # the lot itself, never extruded, is a surface left out of the statics
    grammar = tmp_path / "mass.grammar"
    grammar.write_text("@StartRule\nLot --> [ extrude(3) Mass. ] Ground.\n")
    report = tmp_path / "report.json"
    assert main(["build", str(grammar), "--lot", "0,10 10,10 10,6 4,6 4,0 0,0",
                 "--report", str(report)]) == 0  # fmt: skip
    out = capsys.readouterr().out
    assert "surfaces  1 drawn, not solid: 1 a face (no volume)" in out
    built = json.loads(report.read_text())
    assert built["left_out"] == {"leaves": 1, "by_reason": {"a face (no volume)": 1}}
    # the L's prism is one solid kept as derived (cut into convex parts only when judged)
    assert built["blocks"] == 0 and built["solids"] == 1
    assert built["volume"] == pytest.approx((100 - 36) * 3.0)


@pytest.mark.parametrize(
    "text, message",
    [
        ("0,0 1e308,0 1e308,1e308 0,1e308", "must lie within 1e+09 m of the origin"),
        ("1e308,1e308", "width and depth must be at most 1e+09 m"),
    ],
)
def test_a_lot_beyond_float_range_is_refused_in_one_line(text, message, capsys):
    assert main(["build", "wall_windows.grammar", "--lot", text]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert message in err[-1] and "Traceback" not in "\n".join(err)


def test_a_polygon_s_holes_follow_it_after_a_bar():
    lot = read_lot("0,8 12,8 12,0 0,0 | 4,3 4,5 8,5 8,3")
    assert lot.area == pytest.approx(12 * 8 - 4 * 2)
    assert len(lot.holes) == 1 and len(lot.holes[0]) == 4
    from shapegen.editor.exports import command_line

    line = command_line(None, {}, lot=lot)
    written = line.split("--lot ")[1].strip("'")
    assert read_lot(written) == lot  # the editor's command line gives the same lot back
    with pytest.raises(InputFormatError, match="holes do not fit"):
        read_lot("0,8 12,8 12,0 0,0 | 10,3 14,3 14,5")
