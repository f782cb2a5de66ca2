"""Hostile lot files found by hand: each is one line naming the file, exit status 2."""

from __future__ import annotations

import json

import pytest

from shapegen.cli import main

SQUARE = [[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]]
OSM = (
    b'<?xml version="1.0" encoding="x-unknown-99"?><osm version="0.6">'
    b'<node id="1" lat="48.0" lon="2.0"/><node id="2" lat="48.0001" lon="2.0"/>'
    b'<node id="3" lat="48.0001" lon="2.0001"/>'
    b'<way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><nd ref="1"/>'
    b'<tag k="building" v="yes"/></way></osm>'
)


def _geojson(tmp_path, crs_name):
    document = {
        "type": "FeatureCollection",
        "crs": {"type": "name", "properties": {"name": crs_name}},
        "features": [
            {"type": "Feature", "properties": {},
             "geometry": {"type": "Polygon", "coordinates": [SQUARE]}},
        ],
    }  # fmt: skip
    path = tmp_path / "lots.geojson"
    path.write_text(json.dumps(document), encoding="utf-8")
    return path


def _one_line(capsys, argv) -> str:
    assert main(argv) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    return lines[0]


@pytest.mark.parametrize("door", ["city", "--lot"])
def test_a_system_proj_cannot_invert_is_one_line(tmp_path, capsys, door):
    # pyproj reads it, but cannot make the transformation: ProjError in a traceback
    lots = _geojson(tmp_path, "+proj=tmerc +to_meter=1e-300 +lon_0=0")
    rule = tmp_path / "r.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) i("box")\n', encoding="utf-8")
    if door == "city":
        argv = ["city", str(lots), str(rule), "-o", str(tmp_path / "out"), "--workers", "1"]
    else:
        argv = ["build", str(rule), "--lot", str(lots)]
    line = _one_line(capsys, argv)
    assert "'+proj=tmerc +to_meter=1e-300 +lon_0=0'" in line
    assert "pyproj cannot take it to longitude/latitude" in line
    assert not (tmp_path / "out" / "results.csv").exists()


def test_osm_xml_in_an_unknown_encoding_is_one_line(tmp_path, capsys):
    lots = tmp_path / "lots.osm"
    lots.write_bytes(OSM)
    rule = tmp_path / "r.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) i("box")\n', encoding="utf-8")
    argv = ["city", str(lots), str(rule), "-o", str(tmp_path / "out"), "--workers", "1"]
    line = _one_line(capsys, argv)
    assert f"{lots}: invalid XML: unknown encoding: x-unknown-99" in line


@pytest.mark.parametrize("name", ["site_x.osm", "lots.geojson.gz", "a,b.txt"])
def test_a_lot_file_of_another_kind_is_named_not_read_as_sizes(tmp_path, capsys, name):
    # "site_x.osm" was read as WIDTHxDEPTH: "'.../site_' is not a number"
    lot = tmp_path / name
    lot.write_bytes(b"<osm/>")
    rule = tmp_path / "r.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) i("box")\n', encoding="utf-8")
    line = _one_line(capsys, ["build", str(rule), "--lot", str(lot)])
    suffix = lot.suffix
    assert f"a lot is read from a .geojson, .json or .obj file, not a {suffix} file" in line
