"""A city run whose lots go in batches writes what the one-lot-at-a-time run writes: the same
records and buildings (corners to round-off, the same faces; a solid's caps cut into triangles
either way), and says how many lots each path derived and why."""

from __future__ import annotations

import gzip
import json
from collections import Counter
from pathlib import Path

import numpy as np

import shapegen
from shapegen.city import read_lots, run_city
from shapegen.city.batches import read_building

DATA = Path(__file__).resolve().parents[1] / "data"
RULE = """version "2023.0"
attr height = 12
attr kind = "house"
@StartRule
Lot --> set(height, height + rand(0, 8)) Mass
Mass --> extrude(height) color("#ccbbaa") report("h", height) report("area", geometry.area())
"""


def _city(tmp_path, count: int):
    with gzip.open(DATA / "osm" / "neubrandenburg.geojson.gz") as handle:
        document = json.load(handle)
    document["features"] = document["features"][:count]
    document["features"][3]["properties"]["height"] = 40  # a property sets an attr
    document["features"][5]["properties"]["height"] = [1, 2]  # one the lot's row refuses
    (tmp_path / "lots.geojson").write_text(json.dumps(document))
    return read_lots(tmp_path / "lots.geojson")


def test_batch_and_one_lot_at_a_time_write_the_same_city(tmp_path, monkeypatch):
    import shapegen.city.batch_derive as batch_derive

    rule = tmp_path / "mass.cga"
    rule.write_text(RULE)
    grammar = shapegen.load_grammar(rule)
    city = _city(tmp_path, 60)
    batched = run_city(city, grammar, "memory://batched", analyze=False)
    monkeypatch.setattr(batch_derive, "derive_batch", lambda settings, tasks: None)
    single = run_city(city, grammar, "memory://single", analyze=False)
    how = batched.derivation
    assert how["batch"] >= 55 and how["batch"] + how["shape"] == len(city.lots)
    assert sum(how["reasons"].values()) == how["shape"]
    assert single.derivation == {"batch": 0, "shape": len(city.lots), "reasons": {}}
    kinds = Counter()
    cache_a, cache_b = {}, {}
    for a, b in zip(batched.records, single.records, strict=True):
        skip = {"seconds", "peak_rss_mib", "derived", "batch_fallback", "building"}
        for key in set(a) - skip:
            if key == "lot" and a[key] is not None:
                np.testing.assert_allclose(a[key], b[key], rtol=1e-12)
            else:
                assert a[key] == b[key], (a["id"], key)
        built_a = read_building(batched.store, a, cache_a)
        built_b = read_building(single.store, b, cache_b)
        assert (built_a is None) == (built_b is None) == (a["status"] != "ok")
        if built_a is None:
            continue
        (model_a, colors_a, _), (model_b, colors_b, _) = built_a, built_b
        np.testing.assert_array_equal(colors_a, colors_b)
        assert len(model_a.blocks) == len(model_b.blocks) == 1
        block_a, block_b = model_a.blocks[0], model_b.blocks[0]
        np.testing.assert_allclose(block_a.vertices, block_b.vertices, rtol=0, atol=1e-9)
        if a["solids"]:  # the caps in triangles: the same area each way, the sides the same
            kinds["solid"] += 1
            assert sorted(f for f in block_a.faces if len(f) == 4) == sorted(
                f for f in block_b.faces if len(f) == 4
            )
            assert len(block_a.faces) == len(block_b.faces)
        else:
            kinds["block"] += 1
            assert block_a.faces == block_b.faces
    assert kinds["solid"] >= 10 and kinds["block"] >= 10
    bad = [r for r in batched.records if r["status"] != "ok"]
    assert [r["id"] for r in bad] == [city.lots[5].id]  # the list property: its row says why
    assert batched.records[3]["from_properties"] == ["height"]
