"""Running a city: each lot's verdict is the pipeline's on that lot, failures are rows, a rerun
resumes, and local processes and a Dask cluster give the same city."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import shapegen
from shapegen import pipeline
from shapegen.city import city_from_polygons, lot_seed, read_lots, run_city
from shapegen.errors import InputFormatError

DOCS = Path(__file__).resolve().parents[2] / "docs" / "data"
HOUSE = DOCS / "house.grammar"
EXTRUSION = (
    Path(__file__).resolve().parents[1]
    / "data/cga-corpus/examples_data_extrusion_rule__1c38c522/rules/extrusion_rule.cga"
)
# Lots in metres: (corners, properties). House walls are 0.6 m: a jetty past 0.3 m needs tension.
LOTS = [
    ([(0, 0), (12, 0), (12, 8), (0, 8)], {"jetty": 0.1}),
    ([(20, 0), (28, 0), (28, 9), (20, 9)], {"jetty": 0.4, "storeys": 2}),
    ([(40, 0), (49, 3), (46, 12), (37, 9)], {"storeys": 3}),  # turned 18 degrees
    ([(60, 0), (72, 0), (70, 9), (61, 8)], {}),  # a trapezoid
    ([(80, 0), (90, 0), (90, 10), (80, 10)], {"storeys": "three"}),  # fails: not a number
    ([(100, 0), (101, 0), (100, 0)], {}),  # fails: two corners
]
VARYING = ("seconds", "peak_rss_mib", "building")  # what may differ between runs of one city


def _city():
    return city_from_polygons(
        [ring for ring, _ in LOTS], properties=[props for _, props in LOTS], crs="metres"
    )


def _same(record: dict) -> dict:
    return {key: value for key, value in record.items() if key not in VARYING}


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("city")
    grammar = shapegen.load_grammar(HOUSE)
    events = []
    run = run_city(_city(), grammar, folder, workers=2, progress=events.append)
    return folder, grammar, run, events


def test_each_lot_is_judged_as_the_pipeline_judges_it_alone(small_run):
    _, grammar, run, _ = small_run
    statuses = [record["status"] for record in run.records]
    assert statuses == ["ok", "ok", "ok", "ok", "error", "error"]
    origin = np.array(run.city.origin)
    for record, (ring, props) in zip(run.records[:4], LOTS, strict=False):
        lot = [(x - origin[0], -(y - origin[1])) for x, y in ring]  # east +x, north -z
        seed = lot_seed(record["id"])
        alone = pipeline.design(grammar, attrs=props, seed=seed, lot=lot, assess=True)
        assert record["stands"] == alone.assessment.stands
        assert record["measure"] == pytest.approx(alone.assessment.measure, rel=1e-6, abs=1e-12)
        assert record["blocks"] == len(alone.model.blocks)
    assert [r["stands"] for r in run.records[:4]] == [True, False, True, True]
    assert run.records[1]["from_properties"] == ["jetty", "storeys"]
    assert run.records[3]["footprint"] == "polygon"
    assert "'storeys' is a number" in run.records[4]["error"]
    assert "distinct corner" in run.records[5]["error"]


def test_progress_counts_lots_and_failures(small_run):
    _, _, run, events = small_run
    # One call before any batch, then one per batch (of 4 lots at first, see Batcher).
    assert events[0].record is None and events[0].done == 0
    assert events[-1].done == events[-1].total == len(LOTS)
    assert events[-1].failed == 2 and run.failed == 2
    assert [e.done for e in events] == sorted(e.done for e in events)
    assert sum(len(e.records) for e in events) == len(LOTS)


def test_the_tables_and_the_city_hold_every_lot(small_run):
    folder, _, run, _ = small_run
    with open(folder / "results.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [row["id"] for row in rows] == [r["id"] for r in run.records]
    assert rows[1]["stands"] == "false" and float(rows[0]["measure"]) == run.records[0]["measure"]
    assert rows[0]["attr.jetty"] == "0.1" and rows[4]["error"]
    geo = json.loads((folder / "results.geojson").read_text())
    assert len(geo["features"]) == len(LOTS) and geo["shapegen"]["crs"] == "metres"
    import trimesh

    scene = trimesh.load(folder / "city.glb", force="scene")
    assert sorted(scene.graph.nodes_geometry) == sorted(r["id"] for r in run.records[:4])
    # The first house stands on its lot: x 0..12 east, z -8..0 (north is -z), about the origin.
    origin = np.array(run.city.origin)
    lo, hi = scene.geometry[run.records[0]["id"]].bounds
    assert np.allclose([lo[0], hi[0]], np.array([0, 12]) - origin[0] + [-0.1, 0.1], atol=1e-6)
    assert np.allclose([lo[2], hi[2]], -(np.array([8, 0]) - origin[1]) + [-0.1, 0.1], atol=1e-6)


def test_a_rerun_skips_what_is_done_and_gives_the_same_city(small_run):
    folder, grammar, run, _ = small_run
    again = run_city(_city(), grammar, folder, workers=2)
    assert again.resumed == len(LOTS)
    assert [_same(r) for r in again.records] == [_same(r) for r in run.records]


def test_a_folder_of_another_run_is_refused(small_run):
    folder, grammar, _, _ = small_run
    with pytest.raises(InputFormatError, match="holds a run with another seed"):
        run_city(_city(), grammar, folder, seed=5)


def test_a_lot_past_its_timeout_is_a_row(tmp_path):
    grammar = shapegen.load_grammar(HOUSE)
    city = city_from_polygons([LOTS[0][0]], crs="metres")
    run = run_city(city, grammar, tmp_path, workers=1, timeout=0.001)
    (record,) = run.records
    assert record["status"] == "timeout" and "--timeout" in record["error"]
    assert record["stands"] is None


@pytest.mark.slow
def test_the_district_is_the_same_on_local_processes_on_a_cluster_and_on_a_rerun(tmp_path):
    # Each run in batches of its own sizes, every batch's files written by the worker that ran
    # it (local processes, Dask workers): the merged records and the city are the same.
    distributed = pytest.importorskip("distributed")
    import trimesh

    grammar = shapegen.load_grammar(HOUSE)
    city = read_lots(DOCS / "district.geojson")
    local = run_city(city, grammar, tmp_path / "local")
    fresh = run_city(city, grammar, tmp_path / "fresh", workers=1, batch_size=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:  # fmt: skip
        remote = run_city(city, grammar, tmp_path / "cluster", scheduler=client, batch_size=4)
    assert remote.executor.startswith("the Dask cluster")
    expected = [_same(r) for r in local.records]
    assert [_same(r) for r in remote.records] == expected
    assert [_same(r) for r in fresh.records] == expected
    statuses = [r["status"] for r in local.records]
    assert statuses.count("error") == 2 and statuses.count("ok") == 28  # lot-29's courtyard
    assert 0 < sum(1 for r in local.records if r["stands"] is False) < 28
    assert len(list((tmp_path / "fresh" / "lots").glob("B-*.json"))) == len(city.lots)
    assert len(list((tmp_path / "cluster" / "lots").glob("B-*.json"))) == 8  # 30 lots by 4
    scenes = [
        trimesh.load(tmp_path / name / "city.glb", force="scene") for name in ("local", "cluster")
    ]
    assert sorted(scenes[0].geometry) == sorted(scenes[1].geometry)
    for lot_id, mesh in scenes[0].geometry.items():
        assert np.array_equal(mesh.vertices, scenes[1].geometry[lot_id].vertices)
    again = run_city(city, grammar, tmp_path / "cluster", workers=2)
    assert again.resumed == len(city.lots)


@pytest.mark.slow
def test_a_lot_stuck_in_one_long_solve_is_stopped_and_the_next_lot_still_runs(tmp_path):
    # A 3 km row of houses: about 16 000 stones, derived in about a second; its analysis (one
    # call that a lot cannot interrupt itself) takes much longer than the timeout, so the
    # worker is killed 2 s after it and replaced for the next lot.
    grammar = shapegen.load_grammar(HOUSE)
    city = city_from_polygons(
        [[(0, 0), (3000, 0), (3000, 8), (0, 8)], LOTS[0][0]],
        ids=["long", "short"],
        properties=[{"storeys": 1}, {}],
        crs="metres",
    )
    run = run_city(city, grammar, tmp_path, workers=1, timeout=3.0)
    long, short = run.records
    assert long["status"] == "timeout" and long["seconds"] >= 3.0
    assert short["status"] == "ok" and short["stands"] is True


def test_a_city_of_faces_draws_them_in_its_glb_and_picture(tmp_path):
    """Leaves the statics leave out (here a facade and roof made of faces) are the buildings a
    user sees: city.glb holds them (a valid glTF: no empty arrays, strides on shared views) and
    the picture draws them, as the model of one lot built alone holds them."""
    import struct

    import trimesh

    from shapegen.city.outputs import encode_city_picture

    rules = tmp_path / "faces.cga"
    rules.write_text(
        "Lot --> extrude(6) comp(f) { side : Wall | top : Roof }\nWall --> color(1,0,0)\n"
        "Roof --> color(0,0,1)\n"
    )
    grammar = shapegen.load_grammar(rules)
    city = city_from_polygons([ring for ring, _ in LOTS[:2]], crs="metres")
    run = run_city(city, grammar, tmp_path / "out", analyze=False, workers=1)
    assert [r["status"] for r in run.records] == ["ok", "ok"]
    assert [r["blocks"] for r in run.records] == [0, 0]
    content = (tmp_path / "out" / "city.glb").read_bytes()
    length = struct.unpack_from("<I", content, 12)[0]
    document = json.loads(content[20 : 20 + length])
    for view in document["bufferViews"][:2]:  # positions and colours, shared by the buildings
        assert view["byteStride"] in (12, 4)
    scene = trimesh.load(tmp_path / "out" / "city.glb", force="scene")
    assert sorted(scene.graph.nodes_geometry) == sorted(r["id"] for r in run.records)
    origin = np.array(run.city.origin)
    for record, (ring, _) in zip(run.records, LOTS[:2], strict=True):
        lot = [(x - origin[0], -(y - origin[1])) for x, y in ring]
        alone = pipeline.design(grammar, seed=lot_seed(record["id"]), lot=lot).model
        area = sum(trimesh.Trimesh(s.vertices, _fans(s.faces)).area for s in alone.surfaces)
        assert len(alone.surfaces) == 5 and not alone.blocks
        assert scene.geometry[record["id"]].area == pytest.approx(area, rel=1e-6)
    picture = encode_city_picture(tmp_path / "out", run.records)
    assert picture[:8] == b"\x89PNG\r\n\x1a\n"


def _fans(faces):
    return [(face[0], face[k], face[k + 1]) for face in faces for k in range(1, len(face) - 1)]


def test_a_city_of_extrusions_imports_no_library_it_does_not_use():
    """PyPRT's extrusion example over a few lots, derived and written as a city run does it (in
    one process: a memory:// output), loads no scipy: its import costs each process of a city
    run ~0.17 s (scipy.spatial), more than deriving a thousand such lots."""
    code = (
        "import sys, shapegen\n"
        "from shapegen.city import city_from_polygons, run_city\n"
        "lots = [[(20.0 * k, 0), (20.0 * k + 12, 0), (20.0 * k + 12, 8), (20.0 * k, 8)]"
        " for k in range(5)]\n"
        f"grammar = shapegen.load_grammar({str(EXTRUSION)!r})\n"
        "run = run_city(city_from_polygons(lots, crs='metres'), grammar, 'memory://extruded',"
        " analyze=False)\n"
        "print(run.built, sorted(m for m in ('scipy', 'matplotlib', 'trimesh')"
        " if m in sys.modules))"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "5 []"
