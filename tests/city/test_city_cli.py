"""``shapegen city``: bad input gets one line and exit status 2; a small city runs end to end."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from shapegen.cli import main

HOUSE = Path(__file__).resolve().parents[2] / "docs" / "data" / "house.grammar"


def _lots(tmp_path: Path) -> Path:
    path = tmp_path / "lots.geojson"
    ring = [[0, 0], [12, 0], [12, 8], [0, 8], [0, 0]]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "id": "a", "properties": {"jetty": 0.2, "colour": "red"},
         "geometry": {"type": "Polygon", "coordinates": [ring]}}]}))  # fmt: skip
    return path


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["{notjson}", str(HOUSE)], "not a GeoJSON file"),
        (["{empty}", str(HOUSE)], "no polygons to use as lots"),
        (["{lots}", "no_such_rule.grammar"], "no grammar file"),
        (["{lots}", str(HOUSE), "--set", "no_such_attr=1"], "the grammar has no attr"),
        (["{lots}", str(HOUSE), "--lot", "3,4"], "--lot: a city's lots are the polygons"),
        (["{lots}", str(HOUSE), "--workers", "2", "--scheduler", "tcp://x:1"], "--workers"),
        (["{lots}", str(HOUSE), "--timeout", "0"], "must be > 0"),
        (["{lots}", str(HOUSE), "--fix", "jetty=0.1"], "only applies with --optimize"),
        (
            ["{lots}", str(HOUSE), "--optimize", "--fix", "jety=0.1"],
            "--fix jety: the grammar has no attr 'jety'; did you mean 'jetty'?",
        ),
    ],
)
def test_bad_input_is_one_line_and_status_2(tmp_path, capsys, argv, message):
    (tmp_path / "bad.json").write_text("{oops")
    (tmp_path / "empty.geojson").write_text('{"type": "FeatureCollection", "features": []}')
    names = {
        "notjson": str(tmp_path / "bad.json"),
        "empty": str(tmp_path / "empty.geojson"),
        "lots": str(_lots(tmp_path)),
    }
    argv = [a.format(**names) if a.startswith("{") else a for a in argv]
    status = main(["city", *argv, "-o", str(tmp_path / "out"), "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and message in err[0], err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_an_outdir_that_cannot_be_written_is_refused(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o500)
    status = main(["city", str(_lots(tmp_path)), str(HOUSE), "-o", str(locked / "out")])
    assert status == 2 and "not writable" in capsys.readouterr().err


def test_an_outdir_that_is_a_file_is_refused(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    status = main(["city", str(_lots(tmp_path)), str(HOUSE), "-o", str(tmp_path / "file")])
    assert status == 2 and "is not a folder" in capsys.readouterr().err


def test_a_small_city_runs_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["city", str(_lots(tmp_path)), str(HOUSE), "-o", str(out), "--workers", "1"]
    argv += ["--crs", "metres"]
    assert main([*argv, "--set", "storeys=3", "--picture", str(tmp_path / "city.png")]) == 0
    printed = capsys.readouterr().out
    assert "1 lots: 1 stand" in printed and "attrs set by the lots' properties: jetty" in printed
    (batch,) = (out / "lots").glob("B-*[0-9a-f].json")
    (record,) = json.loads(batch.read_text())["records"]
    assert record["status"] == "ok" and record["blocks"] > 0 and record["id"] == "a"
    assert (tmp_path / "city.png").read_bytes()[:4] == b"\x89PNG"
    for name in ("results.csv", "results.geojson", "city.glb", "run.json"):
        assert (out / name).is_file()
    assert not list(out.rglob("*.tmp"))


def _lots_with(tmp_path: Path, properties: list[dict]) -> Path:
    path = tmp_path / "lots.geojson"
    features = []
    for k, given in enumerate(properties):
        ring = [[20 * k, 0], [20 * k + 12, 0], [20 * k + 12, 8], [20 * k, 8], [20 * k, 0]]
        features.append({"type": "Feature", "id": f"lot-{k}", "properties": given,
                         "geometry": {"type": "Polygon", "coordinates": [ring]}})  # fmt: skip
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    return path


def test_a_city_whose_every_lot_failed_exits_1_with_one_line(tmp_path, capsys):
    lots = _lots_with(tmp_path, [{"storeys": "three"}, {"storeys": "four"}])
    argv = ["city", str(lots), str(HOUSE), "-o", str(tmp_path / "out"), "--workers", "1"]
    assert main([*argv, "--crs", "metres", "--no-analyze", "-q"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("shapegen: error: every lot failed (2 errors); first: lot-0: error:")
    assert "storeys" in err[0]
    assert (tmp_path / "out" / "results.csv").is_file()  # the rows say why, lot by lot


def test_a_city_with_some_lots_failed_exits_0_and_says_how_many(tmp_path, capsys):
    lots = _lots_with(tmp_path, [{"storeys": 1}, {"storeys": "four"}])
    argv = ["city", str(lots), str(HOUSE), "-o", str(tmp_path / "out"), "--workers", "1"]
    assert main([*argv, "--crs", "metres", "--no-analyze"]) == 0
    captured = capsys.readouterr()
    assert "2 lots: 1 built (not judged), 1 failed, 0 timed out" in captured.out
    assert "shapegen: warning: 1 of 2 lots failed (1 error): their rows' error column" in (
        captured.err
    )
