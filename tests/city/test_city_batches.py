"""Batches: the workers write their lots' records and buildings, the parent only schedules and
merges; a run resumes from the batches written, a failing lot is one row of its batch, and an
fsspec URL (memory://) is an output like a folder."""

from __future__ import annotations

import csv
import io
import json
import uuid

import numpy as np
import pytest

import shapegen
from shapegen.city import city_from_polygons, run_city
from shapegen.city.batches import read_building
from shapegen.city.executors import Batcher
from shapegen.city.store import CityStore, open_store
from shapegen.city.work import LotTask
from shapegen.errors import OptionError
from shapegen.geometry.mesh import Mesh

RULE = "Lot --> extrude(10) Mass\n"


@pytest.fixture(scope="module")
def grammar(tmp_path_factory):
    path = tmp_path_factory.mktemp("rule") / "one_extrusion.cga"
    path.write_text(RULE)
    return shapegen.load_grammar(path)


def _city(count: int, properties=None):
    polygons = [[(20.0 * k, 0.0), (20.0 * k + 12, 0.0), (20.0 * k + 12, 8.0), (20.0 * k, 8.0)]
                for k in range(count)]  # fmt: skip
    return city_from_polygons(polygons, properties=properties, crs="metres")


def _memory() -> str:
    return f"memory://shapegen-test-{uuid.uuid4().hex[:8]}"


def _batch_files(store: CityStore) -> list[str]:
    return store.list("lots", ".json")


def test_lots_run_in_batches_of_the_size_given_each_batch_two_files(grammar, tmp_path):
    run = run_city(_city(5), grammar, tmp_path, workers=1, batch_size=2, analyze=False)
    assert [r["status"] for r in run.records] == ["ok"] * 5
    store = open_store(tmp_path)
    records = _batch_files(store)
    assert len(records) == 3 and len(store.list("lots", ".blocks")) == 3  # 2 + 2 + 1 lots
    sizes = sorted(len(json.loads(store.read(name))["records"]) for name in records)
    assert sizes == [1, 2, 2]
    assert all(r["stands"] is None and r["structure"] is None for r in run.records)
    model, colors, _ = read_building(store, run.records[3])
    (block,) = model.blocks
    east, north = run.city.origin  # x east, z north down: lot 4 is x 60..72, north 0..8
    assert np.allclose(block.vertices.min(axis=0), [60 - east, 0, north - 8], atol=1e-9)
    assert np.ptp(block.vertices[:, 1]) == pytest.approx(10.0) and colors.shape == (1, 4)


def test_the_parent_writes_no_file_of_a_lot(grammar, tmp_path, monkeypatch):
    written = []
    original = CityStore.write

    def logged(self, relative, data):
        written.append(relative)
        return original(self, relative, data)

    monkeypatch.setattr(CityStore, "write", logged)
    run = run_city(_city(6), grammar, tmp_path, workers=2, batch_size=2, analyze=False)
    assert run.built == 6 and len(_batch_files(open_store(tmp_path))) == 3
    assert not [name for name in written if name.startswith("lots/")], written
    assert {"run.json", "results.csv", "results.geojson", "city.glb"} <= set(written)


def test_a_failing_lot_is_one_row_of_its_batch(grammar):
    path = grammar.path.with_name("with_height.cga")
    path.write_text("attr height = 10\nLot --> extrude(height) Mass\n")
    tall = shapegen.load_grammar(path)
    properties = [{"height": 4}, {"height": [1, 2]}, {"height": 6}]  # a list: not an attr value
    url = _memory()
    run = run_city(_city(3, properties), tall, url, batch_size=3, analyze=False)
    assert [r["status"] for r in run.records] == ["ok", "error", "ok"]
    assert "is a list" in run.records[1]["error"]
    (batch,) = _batch_files(run.store)
    assert [r["id"] for r in json.loads(run.store.read(batch))["records"]] == ["#1", "#2", "#3"]
    heights = [np.ptp(read_building(run.store, run.records[k])[0].blocks[0].vertices[:, 1])
               for k in (0, 2)]  # fmt: skip
    assert heights == pytest.approx([4.0, 6.0])


def test_an_interrupted_run_resumes_from_the_batches_written(grammar):
    url = _memory()
    city = _city(7)

    def stop_after_two_batches(event):
        if event.done >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_city(city, grammar, url, batch_size=2, progress=stop_after_two_batches)
    store = open_store(url)
    assert len(_batch_files(store)) == 2
    rows = list(csv.DictReader(io.StringIO(store.read("results.csv").decode())))
    assert len(rows) == 4  # the tables of what was done are written on the way out
    again = run_city(city, grammar, url, batch_size=2)
    assert again.resumed == 4 and again.built == 7 and len(_batch_files(store)) == 4
    # A lot whose corners changed runs again; the others are taken from their batches.
    moved = _city(7)
    moved.lots[6] = type(moved.lots[6])(moved.lots[6].id, moved.lots[6].ring + 1.0, {})
    third = run_city(moved, grammar, url, batch_size=2)
    assert third.resumed == 6 and third.built == 7


def test_an_fsspec_memory_url_holds_every_output(grammar):
    fsspec = pytest.importorskip("fsspec")
    trimesh = pytest.importorskip("trimesh")
    url = _memory()
    run = run_city(_city(3), grammar, url, analyze=True)
    assert run.executor == "this process" and [r["stands"] for r in run.records] == [True] * 3
    fs = fsspec.filesystem("memory")
    root = url.removeprefix("memory://")
    names = {path.rpartition("/")[2] for path in fs.find(root)}
    assert {"run.json", "results.csv", "results.geojson", "city.glb"} <= names
    assert not [name for name in names if name.endswith(".tmp")]
    scene = trimesh.load(io.BytesIO(fs.cat_file(f"{root}/city.glb")), file_type="glb")
    assert sorted(scene.geometry) == ["#1", "#2", "#3"]
    assert str(run.files["csv"]) == f"{url}/results.csv"


def test_memory_is_refused_for_a_cluster_and_an_unknown_protocol_is_one_line(grammar):
    with pytest.raises(OptionError, match="cannot write into this process's memory"):
        run_city(_city(1), grammar, _memory(), scheduler="tcp://127.0.0.1:1")
    with pytest.raises(OptionError, match="nosuch://x: cannot open it"):
        run_city(_city(1), grammar, "nosuch://x")


def test_batches_grow_to_half_a_second_and_shrink_towards_the_end():
    tasks = [LotTask(f"l{k}", ((0, 0), (1, 0), (1, 1))) for k in range(10_000)]
    batcher = Batcher(tasks, workers=2)
    assert len(batcher.next()) == 4  # until a lot's time is known
    batcher.observe([{"seconds": 0.001}] * 4)
    assert len(batcher.next()) == 500  # 0.5 s of 1 ms lots
    sizes = []
    while batcher:
        sizes.append(len(batcher.next()))
    assert sum(sizes) == 10_000 - 504 and sizes[-1] == 1
    assert sizes == sorted(sizes, reverse=True)  # a quarter of a worker's share at most
    fixed = Batcher(tasks[:7], workers=2, size=3)
    assert [len(fixed.next()) for _ in range(3)] == [3, 3, 1]


def test_a_building_that_is_not_convex_is_packed_as_derived_its_caps_in_triangles(grammar):
    # an L-shaped and a U-shaped footprint: each mass stays one solid (not cut into convex
    # blocks when nobody judges it); the city's packed building is that solid, its side walls
    # as quads and its two non-convex caps cut into triangles that cover them exactly
    shapes = [[(0, 0), (4, 0), (4, 2), (2, 2), (2, 4), (0, 4)],
              [(10, 0), (16, 0), (16, 4), (14, 4), (14, 1), (12, 1), (12, 4), (10, 4)]]  # fmt: skip
    city = city_from_polygons(shapes, crs="metres")
    run = run_city(city, grammar, _memory(), batch_size=2, analyze=False)
    assert [r["blocks"] for r in run.records] == [0, 0]
    for record, area in zip(run.records, (12.0, 18.0), strict=True):
        model, colors, _ = read_building(run.store, record)
        (solid,) = model.blocks
        sizes = sorted({len(face) for face in solid.faces})
        assert sizes == [3, 4] and colors.shape == (1, 4)
        mesh = Mesh(solid.vertices, solid.faces)
        assert mesh.is_closed and mesh.signed_volume() == pytest.approx(area * 10.0)
