"""Hostile rule packages and lot files, each small and made here: every one ends the command
with exit status 2, one line naming the file and the problem (the limit by name where one is
passed), and nothing written: no output, nothing left half-unpacked in the package cache.

The slow fuzzers (test_fuzz_hostile.py) try thousands of such files; what they find lands here.
"""

from __future__ import annotations

import gzip
import json
import math
import re

import pytest
from hostile_files import (
    RULE,
    feature_collection,
    geojson_bytes,
    package_bytes,
    small_package,
    square,
    with_header_fixed,
)

from shapegen.cli import main
from shapegen.limits import work_limits

pytestmark = pytest.mark.usefixtures("package_cache")


def _refused(capsys, argv: list[str], path, pattern: str) -> str:
    status = main(argv)
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert status == 2, captured.err
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"shapegen: error: {path}:"), lines[0]
    assert re.search(pattern, lines[0]), lines[0]
    assert "Traceback" not in captured.err
    return lines[0]


def _damaged_stream(data: bytes) -> bytes:
    data = bytearray(data)
    for position in range(40, 60):  # inside the packed LZMA stream, past the start header
        data[position] ^= 0x5A
    return bytes(data)


def _damaged_copy(data: bytes) -> bytes:
    data = bytearray(data)
    data[32 + 100] ^= 0xFF  # a byte of the stored member: its checksum fails
    return bytes(data)


def _lying_size(data: bytes) -> bytes:
    """The folder's unpacked size made 127 bytes, not what its stream holds (the header left
    uncompressed, its checksums made right again): a size the data does not keep."""
    head = bytearray(data)
    offset, size = int.from_bytes(head[12:20], "little"), int.from_bytes(head[20:28], "little")
    start = 32 + offset
    where = head.find(bytes([0x0C]), start, start + size)  # kCodersUnpackSize: the size follows
    assert where > 0
    head[where + 1] = 0x7F
    return with_header_fixed(bytes(head))


BIG = "x" * 5000
PACKAGES = [
    ("damaged LZMA stream", lambda: _damaged_stream(package_bytes(small_package(a=BIG * 4))),
     r"not a readable CityEngine rule package.*(damaged|checksum)"),
    ("checksum failure", lambda: _damaged_copy(package_bytes(small_package(**{
        "assets/zeros.bin": bytes(4000)}), copy=True)),
     r"the member '[^']+' is damaged \(its checksum does not match\)"),
    ("truncated", lambda: package_bytes(small_package(a=BIG))[:200],
     r"not a readable CityEngine rule package"),
    ("lying size", lambda: _lying_size(package_bytes(small_package(a=BIG), encoded_header=False)),
     r"not a readable CityEngine rule package"),
    ("folders 2 000 deep", lambda: package_bytes(small_package(**{"d/" * 2000 + "x.cga": "x"})),
     r"lies 2000 folders deep, more than 64 \(limit max_archive_depth = 64"),
    ("../ escape", lambda: package_bytes(small_package(**{"rules/../../evil.cga": "x"})),
     r"would be unpacked outside the package's folder"),
    ("absolute path", lambda: package_bytes(small_package(**{"/tmp/evil.cga": "x"})),
     r"would be unpacked outside the package's folder"),
    ("symbolic link", lambda: package_bytes(small_package(**{
        "rules/link.cga": ("symlink", "/etc/passwd")})),
     r"'rules/link.cga' is a link or a special file"),
    ("not 7z at all", lambda: b"Lot --> X.", r"not a 7z file"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("make", "pattern"),
    [(make, pattern) for _, make, pattern in PACKAGES],
    ids=[name for name, _, _ in PACKAGES],
)
def test_a_hostile_package_is_one_line_and_leaves_nothing(tmp_path, capsys, make, pattern):
    package = tmp_path / "hostile.rpk"
    package.write_bytes(make())
    out = tmp_path / "out.glb"
    _refused(capsys, ["build", str(package), "-o", str(out)], package, pattern)
    assert not out.exists()
    packages = tmp_path / "cache" / "packages"
    assert not packages.is_dir() or not list(packages.iterdir())
    assert not (tmp_path / "evil.cga").exists() and not (tmp_path / "cache" / "evil.cga").exists()


@pytest.mark.parametrize(
    ("limit", "members", "pattern"),
    [
        ({"max_file_bytes": 4096}, {"assets/zeros.bin": bytes(2**20)},
         r"unpacks to more than 65536 bytes \(16 x max_file_bytes\) \(limit max_file_bytes = 4096"),
        ({"max_archive_members": 5}, {f"assets/{k}": "" for k in range(6)},
         r"holds 8 members, more than 5 \(limit max_archive_members = 5"),
    ],
    ids=["bomb", "members"],
)  # fmt: skip
def test_a_package_over_a_limit_names_the_limit(tmp_path, capsys, limit, members, pattern):
    package = tmp_path / "big.rpk"
    package.write_bytes(package_bytes(small_package(**members)))
    out = tmp_path / "out.glb"
    with work_limits(**limit):
        _refused(capsys, ["build", str(package), "-o", str(out)], package, pattern)
    assert not out.exists()
    assert not list((tmp_path / "cache" / "packages").iterdir())


def test_a_small_valid_package_still_builds(tmp_path, capsys):
    package = tmp_path / "fine.rpk"
    package.write_bytes(package_bytes(small_package()))
    out = tmp_path / "out.glb"
    assert main(["build", str(package), "--lot", "4,3", "-o", str(out), "-q"]) == 0
    assert out.stat().st_size > 0


def _gzip_of_spaces(size: int) -> bytes:
    return gzip.compress(b'{"type": "FeatureCollection", "features": [' + b" " * size + b"]}")


LOT_FILES = [
    ("JSON 100 000 arrays deep", "deep.geojson",
     lambda: b'{"type": "FeatureCollection", "features": ' + b"[" * 100_000 + b"]" * 100_000
     + b"}", {}, r"the JSON nests too deeply \(100001 .*limit max_json_depth = 256"),
    ("objects 300 deep", "objects.geojson", lambda: b'{"a":' * 300 + b"1" + b"}" * 300, {},
     r"nests too deeply .*max_json_depth"),
    ("gzip bomb", "bomb.geojson.gz", lambda: _gzip_of_spaces(2**20), {"max_file_bytes": 65536},
     r"the gzipped file inflates to more than 65536 bytes \(limit max_file_bytes = 65536"),
    ("truncated gzip", "cut.geojson.gz",
     lambda: gzip.compress(geojson_bytes(feature_collection([square(0)])))[:30], {},
     r"not a whole gzip file"),
    ("file over the limit", "big.geojson", lambda: b" " * 70_000, {"max_file_bytes": 65536},
     r"the file has 70000 bytes, more than 65536 \(limit max_file_bytes"),
    ("not JSON", "bad.geojson", lambda: b'{"type": "FeatureCollection", "features": [}', {},
     r"invalid JSON"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("name", "make", "limit", "pattern"),
    [case[1:] for case in LOT_FILES],
    ids=[case[0] for case in LOT_FILES],
)
def test_a_hostile_lot_file_is_one_line_and_writes_nothing(
    tmp_path, capsys, name, make, limit, pattern
):
    lots = tmp_path / name
    lots.write_bytes(make())
    rule = tmp_path / "box.cga"
    rule.write_text(RULE)
    out = tmp_path / "out"
    with work_limits(**limit):
        _refused(capsys, ["city", str(lots), str(rule), "-o", str(out), "-q"], lots, pattern)
    assert not out.exists()


NAN_RING = [[math.nan, 0], [30, 0], [30, 10], [20, 10], [math.nan, 0]]  # GEOS: not closed
BAD_LOTS = [
    ("nan closing corner", {"type": "Polygon", "coordinates": [NAN_RING]},
     "a corner that is not two finite numbers"),
    ("inf corner", {"type": "Polygon", "coordinates": [
        [[40, math.inf], [50, 0], [50, 10], [40, 10], [40, math.inf]]]},
     "a corner that is not two finite numbers"),
    ("nan middle corner", {"type": "Polygon", "coordinates": [
        [[60, 0], [70, math.nan], [70, 10], [60, 10], [60, 0]]]},
     "a corner that is not two finite numbers"),
    ("no coordinates", {"type": "Polygon"}, "a polygon without coordinates"),  # fuzz lots 77 94
    ("coordinates as text", {"type": "Polygon", "coordinates": "x"},
     "a polygon without coordinates"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("geometry", "error"),
    [case[1:] for case in BAD_LOTS],
    ids=[case[0] for case in BAD_LOTS],
)
def test_a_lot_that_cannot_be_a_shape_is_a_row_and_the_others_are_written(
    tmp_path, geometry, error
):
    pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    from shapegen.city import read_lots
    from shapegen.city.outputs import write_tables
    from shapegen.city.work import new_record

    document = feature_collection([square(0)])
    document["features"].append(
        {"type": "Feature", "id": "bad", "properties": {}, "geometry": geometry}
    )
    lots = tmp_path / "lots.geojson"
    lots.write_bytes(geojson_bytes(document))
    city = read_lots(lots, crs="metres")
    assert [lot.problem for lot in city.lots] == [None, error]
    records = []
    for k, lot in enumerate(city.lots):
        record = new_record(lot.id, k)
        record.update(status="ok" if lot.problem is None else None, error=lot.problem)
        records.append(record)
    (tmp_path / "out").mkdir()
    written = write_tables(tmp_path / "out", city, records, scene=False)
    rows = pq.read_table(written["parquet"]).to_pylist()
    assert [row["id"] for row in rows] == ["lot0", "bad"]
    assert rows[0]["geometry"] is not None and rows[0]["error"] is None
    assert rows[1]["geometry"] is None and rows[1]["error"] == error
    features = json.loads((tmp_path / "out" / "results.geojson").read_text())["features"]
    assert features[0]["geometry"] == document["features"][0]["geometry"]
    assert features[1]["properties"]["error"] == error
    if "finite" in error:  # NaN is not JSON: no shape rather than nulls for numbers
        assert city.lots[1].geometry is None and features[1]["geometry"] is None
