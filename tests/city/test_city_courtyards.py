"""Lots with courtyards: a city's Polygon with interior rings is built on a start shape with
those holes, as CityEngine builds it, measured against its runtime.

tests/data/city-courtyards/courtyards.geojson is a district of a town's survey grid: a
chamfered perimeter block around a courtyard, a one-part MultiPolygon with two light wells, a
plain house, two pavilions under one feature (a MultiPolygon of two parts: refused, a lot is
one polygon) and a yard drawn across its lot's outline. tests/data/prt_city_courtyards.json
holds what PyPRT 1.12 (CityEngine's runtime) makes of each lot with the corpus's
extrusion_rule, the height fixed at 15 m (tools/prt_city_courtyards.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from shapegen.cli import main

DATA = Path(__file__).resolve().parents[1] / "data"
LOTS = DATA / "city-courtyards" / "courtyards.geojson"
RULE = DATA / "cga-corpus" / "tests_data_extrusion_rule__e4df6667" / "rules" / "extrusion_rule.cga"
PRT = json.loads((DATA / "prt_city_courtyards.json").read_text())
HEIGHT = ["--set", f"minBuildingHeight={PRT['height_m']}"]
HEIGHT += ["--set", f"maxBuildingHeight={PRT['height_m']}"]
MM = 1e-3


@pytest.fixture(scope="module")
def city(tmp_path_factory):
    out = tmp_path_factory.mktemp("courtyards") / "out"
    argv = ["city", str(LOTS), str(RULE), "-o", str(out), *HEIGHT, "--no-analyze", "-q"]
    assert main([*argv, "--workers", "1"]) == 0
    frame = json.loads((out / "run.json").read_text())["frame"]
    records = {}
    for path in (out / "lots").glob("B-*.json"):
        for record in json.loads(path.read_text())["records"]:
            records[record["id"]] = record
    return out, np.array(frame["origin"]), records


def _prt_rings(lot: dict, origin: np.ndarray) -> list[np.ndarray]:
    """PyPRT's faces, each ring (holes their own) as ``(k, 3)`` points in the city's frame:
    (east - origin, up, -(north - origin))."""
    points = np.array(lot["points"]) - [origin[0], 0.0, -origin[1]]
    rings, at = [], 0
    for count in lot["faces"]:
        rings.append(points[lot["indices"][at : at + count]])
        at += count
    return rings


def _volume(rings) -> float:
    """The volume a closed set of rings bounds, m^3 (the divergence theorem over each ring's
    fan; a hole wound against its face takes its area off)."""
    total = 0.0
    for ring in rings:
        a, b, c = ring[0], ring[1:-1], ring[2:]
        total += float(np.einsum("ij,ij->", np.broadcast_to(a, b.shape), np.cross(b, c)))
    return total / 6.0


def _ring_key(ring: np.ndarray):
    """A ring as its corners (rounded to 0.1 mm, in any order) and its facing (Newell's
    normal, rounded), so that two lists of faces compare whatever their order and first
    corners."""
    normal = np.sum(np.cross(ring, np.roll(ring, -1, axis=0)), axis=0)
    normal = normal / np.linalg.norm(normal)
    corners = tuple(sorted(map(tuple, np.round(ring, 4).tolist())))
    return corners, tuple(np.round(normal, 6).tolist())


def _prt(lot_id: str) -> dict:
    return next(lot for lot in PRT["lots"] if lot["id"] == lot_id)


def test_courtyard_lots_are_built_and_the_others_rows_say_why(city):
    _, _, records = city
    assert {r["id"]: r["status"] for r in records.values()} == {
        "block-12": "ok", "block-13": "ok", "house-7": "ok", "pavilions": "error",
        "yard-across": "ok",
    }  # fmt: skip
    assert records["pavilions"]["error"] == "a MultiPolygon of 2 parts; a lot is one polygon"
    # a courtyard lot is derived one shape at a time, and said so
    for lot_id in ("block-12", "block-13"):
        assert records[lot_id]["derived"] == "shape"
        assert records[lot_id]["batch_fallback"] == "a lot with holes (a courtyard)"
        assert records[lot_id]["footprint"] == "polygon" and records[lot_id]["solids"] == 1
    # CityEngine's runtime removes a hole that is not inside the outline, with a warning
    assert any("outside its boundary (removed)" in e for e in _prt("yard-across")["errors"])
    assert records["yard-across"]["warnings"] == [
        "1 hole(s) outside the lot's outline removed (as CityEngine does)"
    ]


@pytest.mark.parametrize("lot_id", ["block-12", "block-13", "house-7", "yard-across"])
def test_each_building_file_holds_cityengines_model(city, lot_id):
    from shapegen.city.batches import read_building
    from shapegen.city.store import open_store

    out, origin, records = city
    model = read_building(open_store(out), records[lot_id])[0]
    rings = _prt_rings(_prt(lot_id), origin)
    expected = np.unique(np.round(np.vstack(rings), 4), axis=0)
    leaves = [*model.blocks, *model.surfaces]
    faces = [leaf.vertices[list(face)] for leaf in leaves for face in leaf.faces]
    found = np.unique(np.round(np.vstack([leaf.vertices for leaf in leaves]), 4), axis=0)
    assert found.shape == expected.shape and np.allclose(found, expected, atol=MM)
    assert _volume(faces) == pytest.approx(_volume(rings), rel=1e-9)


def test_the_city_gltf_holds_each_courtyard_as_cityengine_builds_it(city):
    import trimesh

    out, origin, _ = city
    scene = trimesh.load(out / "city.glb")
    meshes = {name: scene.geometry[name] for name in scene.graph.nodes_geometry}
    for lot_id in ("block-12", "block-13"):
        mesh = meshes[lot_id]
        assert mesh.is_watertight
        assert mesh.volume == pytest.approx(_volume(_prt_rings(_prt(lot_id), origin)), rel=1e-6)


def test_the_results_keep_the_courtyards_rings(city):
    out, _, _ = city
    features = {f["id"]: f for f in json.loads((out / "results.geojson").read_text())["features"]}
    assert len(features["block-12"]["geometry"]["coordinates"]) == 2
    assert len(features["block-13"]["geometry"]["coordinates"][0]) == 3
    import shapely

    table = pytest.importorskip("pyarrow.parquet").read_table(out / "results.parquet")
    shapes = dict(zip(table["id"].to_pylist(), shapely.from_wkb(table["geometry"].to_pylist()),
                      strict=True))  # fmt: skip
    assert len(shapes["block-12"].interiors) == 1
    assert shapes["block-13"].area == pytest.approx(30 * 20 - 6 * 6 - 6 * 8)


@pytest.mark.parametrize("lot_id", ["block-12", "block-13"])
def test_the_derived_faces_are_cityengines_faces_and_reports(lot_id):
    """One lot as a city worker derives it: the same polygons (holes their own rings, wound
    against their face) as PyPRT's encoder gives, and the rule's reports."""
    from shapegen.city.city_lots import read_lots
    from shapegen.city.work import CitySettings, LotTask, run_lot

    city = read_lots(LOTS)
    (lot,) = [lot for lot in city.lots if lot.id == lot_id]
    height = PRT["height_m"]
    settings = CitySettings(
        RULE.read_text(),
        str(RULE),
        analyze=False,
        attrs={"minBuildingHeight": height, "maxBuildingHeight": height},
    )
    task = LotTask(lot.id, lot.ring.tolist(), dict(lot.properties), "", lot.problem,
                   tuple(hole.tolist() for hole in lot.holes))  # fmt: skip
    record = run_lot(settings, task)
    assert record["status"] == "ok", record["error"]
    model = record["model"]
    (surface,) = model.surfaces
    rings = [surface.vertices[list(p)] for p in surface.polygons]
    expected = _prt_rings(_prt(lot_id), np.array(city.origin))
    assert sorted(map(_ring_key, rings)) == sorted(map(_ring_key, expected))
    prt_reports = {k[:-4]: v for k, v in _prt(lot_id)["report"].items() if k.endswith("_avg")}
    for name, value in model.metadata["reports"].items():
        assert value == pytest.approx(prt_reports[name]), name
