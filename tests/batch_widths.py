"""The city's lots derived at both widths, for the engine's tests: real footprints, and every
lot the batch derived compared with the same lot derived alone (leaf corners, faces, block or
solid, reports with their kinds and order, attrs)."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from shapegen.engine.batch import derive_lots
from shapegen.engine.batch.leaves import packed_leaves
from shapegen.engine.batch.lots import SOLID

DATA = Path(__file__).resolve().parent / "data"
RECTANGLES = ((0.0, 0.0), (30.5, 7.25), (-40.0, 100.0))  # 12 x 8 m lots at these corners


def footprints(count: int, tmp_path, rectangles=RECTANGLES) -> list[np.ndarray]:
    """The first ``count`` OSM footprints of the district as (x, z) lots, and rectangles."""
    from shapegen.city import read_lots
    from shapegen.city.work import city_lot

    with gzip.open(DATA / "osm" / "neubrandenburg.geojson.gz") as handle:
        document = json.load(handle)
    document["features"] = document["features"][:count]
    (tmp_path / "lots.geojson").write_text(json.dumps(document))
    rings = [city_lot(lot.ring) for lot in read_lots(tmp_path / "lots.geojson").lots[:count]]
    rings += [np.array([[x, -z], [x + 12, -z], [x + 12, -z - 8], [x, -z - 8]], float)
              for x, z in rectangles]  # fmt: skip
    return rings


def compare_widths(grammar, rings, seeds, tolerance_m: float = 1e-9):
    """Derive ``rings`` as one batch and each lot alone; assert that every lot the batch derived
    is the lot derived alone; the batch (its ``fallback`` says which lots it left)."""
    from shapegen.pipeline import design

    offsets = np.zeros(len(rings) + 1, dtype=np.int64)
    np.cumsum([len(r) for r in rings], out=offsets[1:])
    batch = derive_lots(grammar, np.concatenate(rings), offsets, seeds, [{}] * len(rings))
    assert sum(batch.reasons.values()) == int(batch.fallback.sum())  # each fallback counted
    derived = np.flatnonzero(~batch.fallback)
    if not len(derived):
        return batch
    leaves = packed_leaves(batch, derived)
    vertex_at = np.concatenate([[0], np.cumsum(leaves["vertex_counts"])])
    face_at = np.concatenate([[0], np.cumsum(leaves["face_counts"])])
    corner_at = np.concatenate([[0], np.cumsum(leaves["face_sizes"])])
    reports = batch.reports()
    for j, k in enumerate(derived.tolist()):
        lot = [tuple(p) for p in rings[k].tolist()]
        model = design(grammar, seed=seeds[k], lot=lot, assess=False).model
        solid = batch.kind[k] == SOLID
        assert (len(model.blocks), len(model.surfaces)) == ((0, 1) if solid else (1, 0)), k
        leaf = model.surfaces[0] if solid else model.blocks[0]
        vertices = leaves["vertices"][vertex_at[j] : vertex_at[j + 1]]
        assert vertices.shape == np.shape(leaf.vertices), k
        assert np.abs(vertices - leaf.vertices).max() <= tolerance_m, k
        sizes = leaves["face_sizes"][face_at[j] : face_at[j + 1]].tolist()
        flat = leaves["faces"][corner_at[face_at[j]] : corner_at[face_at[j + 1]]].tolist()
        faces, at = [], 0
        for size in sizes:
            faces.append(tuple(flat[at : at + size]))
            at += size
        assert tuple(faces) == tuple(leaf.faces), k
        expected = model.metadata["reports"]
        assert list(reports[k]) == list(expected), k  # the same keys in the same order
        for key, value in expected.items():
            got = reports[k][key]
            values = value if isinstance(value, list) else [value]
            gots = got if isinstance(value, list) else [got]
            assert len(gots) == len(values), (k, key)
            for a, b in zip(gots, values, strict=True):
                assert type(a) is type(b), (k, key)
                if isinstance(b, float) and not np.isnan(b):
                    assert a == pytest.approx(b, rel=1e-12, abs=1e-12), (k, key)
                elif not isinstance(b, float):
                    assert a == b, (k, key)
                else:
                    assert np.isnan(a), (k, key)
        attrs = model.metadata["attrs"]
        assert {name: batch.values[k][name] for name in attrs} == attrs, k
    return batch
