"""``shapegen city`` with lots in a projected system, --crs, GeoParquet and --tiles from the
command line: a Web Mercator city end to end, and one line for each mistake."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("pyproj")

from shapegen.cli import main  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "docs" / "data"
HOUSE = DATA / "house.grammar"


def _two_lots_in_3857(tmp_path: Path) -> Path:
    """lot-01 and lot-02 of the district, in Web Mercator as docs/data has them."""
    document = json.loads((DATA / "district_3857.geojson").read_text())
    document["features"] = document["features"][:2]
    path = tmp_path / "lots_3857.geojson"
    path.write_text(json.dumps(document))
    return path


def test_a_web_mercator_city_runs_with_tiles(tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["city", str(_two_lots_in_3857(tmp_path)), str(HOUSE), "-o", str(out)]
    assert main([*argv, "--workers", "1", "--tiles", "--set", "storeys=1"]) == 0
    printed = capsys.readouterr().out
    assert "2 lots: 2 stand" in printed and "results.parquet" in printed
    assert "3D Tiles: " in printed and "(2 buildings in 1 tiles)" in printed
    tileset = json.loads((out / "tiles" / "tileset.json").read_text())
    assert tileset["asset"]["version"] == "1.1"
    assert (out / "tiles" / tileset["root"]["content"]["uri"]).is_file()
    run = json.loads((out / "run.json").read_text())
    assert run["frame"]["crs"] == "EPSG:3857"
    assert run["frame"]["origin_lonlat"][1] == pytest.approx(46.434, abs=1e-3)
    rows = (out / "results.csv").read_text().splitlines()
    header = rows[0].split(",")
    width = [float(r.split(",")[header.index("lot_width")]) for r in rows[1:]]
    # make_district.py laid lot-01 14 m wide on the ground (20.3 Web Mercator metres at
    # 46.4 N) and lot-02 12 m
    assert width == pytest.approx([14.0, 12.0], abs=1e-3)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--crs", "EPSG:99999"], "'EPSG:99999' is not a coordinate system pyproj knows"),
        (["--crs", "EPSG:4258"], "another datum than WGS84"),
        (["--crs", "metres"], "--crs metres would take its coordinates for metres"),
        (["--crs", "EPSG:2154"], "--crs EPSG:2154 but its crs member says EPSG:3857"),
        (["--tiles-height", "40"], "--tiles-height applies to --tiles"),
    ],
)
def test_crs_and_tiles_mistakes_are_one_line(tmp_path, capsys, extra, message):
    argv = ["city", str(_two_lots_in_3857(tmp_path)), str(HOUSE), "-o", str(tmp_path / "o")]
    status = main([*argv, "-q", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and message in err[0], err


def test_tiles_of_local_metres_and_a_broken_prj_are_one_line(tmp_path, capsys):
    plain = tmp_path / "plain.geojson"
    document = json.loads((DATA / "district_l93.geojson").read_text())
    plain.write_text(json.dumps(document))
    argv = ["city", str(plain), str(HOUSE), "-o", str(tmp_path / "o"), "-q"]
    assert main([*argv, "--tiles"]) == 2  # no .prj: local metres
    assert "with no place on the earth" in capsys.readouterr().err
    plain.with_suffix(".prj").write_text('PROJCS["oops')
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "plain.prj: not a coordinate system in WKT" in err[0]
