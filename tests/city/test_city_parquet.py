"""results.parquet: GeoParquet 1.1 read back with pyarrow: the rows, their types (warnings as
lists, timings as numbers), each lot's polygon in the input's coordinates, the geo metadata."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
pyproj = pytest.importorskip("pyproj")

import shapely  # noqa: E402

from shapegen.city import city_from_polygons, read_lots  # noqa: E402
from shapegen.city.outputs import write_tables  # noqa: E402
from shapegen.city.work import new_record  # noqa: E402

LAMBERT = Path(__file__).resolve().parents[2] / "docs" / "data" / "district_l93.geojson"


def _records(city):
    """A record per lot as a run leaves them: built lots with warnings and timings, the lots
    that cannot be built as errors."""
    records = []
    for k, lot in enumerate(city.lots):
        record = new_record(lot.id, k)
        if lot.problem is None:
            record.update(status="ok", stands=k % 3 != 0, measure=0.0 if k % 3 else 0.25,
                          structure="blocks", blocks=12 + k, left_out=0, seconds=0.5 + k,
                          peak_rss_mib=150.0, footprint="rectangle", lot=[8.0, 9.0],
                          attrs={"jetty": 0.1 * k, "roof": "gable" if k % 2 else 3},
                          from_properties=["jetty"],
                          warnings=[f"warning {k}", "second"] if k % 4 == 0 else [])  # fmt: skip
        else:
            record.update(error=lot.problem, seconds=0.0)
        records.append(record)
    return records


def test_the_table_reads_back_with_its_polygons_and_metadata(tmp_path):
    city = read_lots(LAMBERT)
    records = _records(city)
    written = write_tables(tmp_path, city, records, scene=False)
    assert written["parquet"] == tmp_path / "results.parquet"
    table = pq.read_table(written["parquet"])
    assert table.num_rows == len(city.lots) == 30
    columns = table.column_names
    assert columns[-1] == "geometry" and {"warnings", "seconds", "peak_rss_mib"} <= set(columns)
    assert table.schema.field("warnings").type == pa.list_(pa.string())
    assert table.schema.field("seconds").type == pa.float64()
    assert table.schema.field("stands").type == pa.bool_()
    assert table.schema.field("attr.roof").type == pa.string()  # a number here, text there
    rows = table.to_pylist()
    assert rows[0]["warnings"] == ["warning 0", "second"] and rows[1]["warnings"] == []
    assert [r["seconds"] for r in rows] == [r["seconds"] for r in records]
    assert [r["id"] for r in rows] == [lot.id for lot in city.lots]
    failed = [r for r in rows if r["status"] == "error"]
    assert failed and all(r["error"] for r in failed)
    for row, lot in zip(rows, city.lots, strict=True):
        shape = shapely.from_wkb(row["geometry"])
        expected = np.array(lot.geometry["coordinates"][0])
        # the polygon as read, in Lambert-93 metres (holes too)
        assert np.allclose(np.array(shape.exterior.coords), expected, atol=1e-9)

    geo = json.loads(table.schema.metadata[b"geo"])
    assert geo["version"] == "1.1.0" and geo["primary_column"] == "geometry"
    column = geo["columns"]["geometry"]
    assert column["encoding"] == "WKB" and column["geometry_types"] == ["Polygon"]
    assert pyproj.CRS.from_json_dict(column["crs"]).equals(pyproj.CRS("EPSG:2154"))
    x0, y0, x1, y1 = column["bbox"]
    assert 820_000 < x0 < x1 < 830_000 and 6_590_000 < y0 < y1 < 6_600_000

    document = json.loads((tmp_path / "results.geojson").read_text())
    assert document["crs"]["properties"]["name"] == "urn:ogc:def:crs:EPSG::2154"
    assert document["shapegen"]["crs"] == "EPSG:2154"


@pytest.mark.parametrize(("crs", "expected"), [("lonlat", "OGC:CRS84"), ("metres", None)])
def test_lonlat_says_crs84_and_local_metres_say_unknown(tmp_path, crs, expected):
    ring = [(4.659, 46.434), (4.6591, 46.434), (4.6591, 46.4341)]
    if crs == "metres":
        ring = [(0, 0), (10, 0), (10, 10)]
    city = city_from_polygons([ring], crs=crs)
    write_tables(tmp_path, city, _records(city), scene=False)
    table = pq.read_table(tmp_path / "results.parquet")
    column = json.loads(table.schema.metadata[b"geo"])["columns"]["geometry"]
    if expected is None:
        assert column["crs"] is None  # GeoParquet: null is an unknown system
    else:
        assert pyproj.CRS.from_json_dict(column["crs"]).equals(pyproj.CRS(expected))
    assert "crs" not in json.loads((tmp_path / "results.geojson").read_text())


def test_without_pyarrow_the_rest_is_written_and_one_line_says_so(tmp_path, monkeypatch):
    import shapegen.city.parquet as parquet

    monkeypatch.setattr(parquet, "have_pyarrow", lambda: False)
    city = city_from_polygons([[(0, 0), (10, 0), (10, 10)]], crs="metres")
    written = write_tables(tmp_path, city, _records(city), scene=False)
    assert "parquet" not in written and not (tmp_path / "results.parquet").exists()
    assert (tmp_path / "results.csv").is_file()
    assert "\n" not in parquet.PARQUET_MISSING and "pyarrow" in parquet.PARQUET_MISSING
