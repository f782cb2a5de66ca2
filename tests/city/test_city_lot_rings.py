"""The plain polygons of a city read together give the lots the one-feature path gives: rings
(to the bit), problems and ids, for features of every kind mixed together."""

from __future__ import annotations

import json

import numpy as np
import pytest

from shapegen.city import city_lots, read_lots

SQUARE = [[13.25, 53.55], [13.2501, 53.55], [13.2501, 53.5501], [13.25, 53.5501], [13.25, 53.55]]


def _feature(coordinates, kind="Polygon", **properties):
    geometry = {"type": kind, "coordinates": coordinates}
    return {"type": "Feature", "properties": properties, "geometry": geometry}


def _shifted(ring, dx):
    return [[x + dx, y] for x, y in ring]


FEATURES = [
    _feature([SQUARE]),  # plain, counter-clockwise
    _feature([SQUARE[::-1]]),  # clockwise: turned, its first corner kept first
    _feature([_shifted(SQUARE, 0.001)[:2] + [[13.2511, 53.55000000001]] + SQUARE[2:4]]),  # merge
    _feature([SQUARE, _shifted(SQUARE, 0.0)[:4]]),  # a hole
    _feature([[SQUARE]], "MultiPolygon"),  # one part
    _feature([[[13.25, 53.55], [13.2501, 53.5501], [13.2501, 53.55], [13.25, 53.5501]]]),  # crosses
    _feature([[[13.25, 53.55], [13.2500000001, 53.55], [13.2500000001, 53.5500000001]]]),  # tiny
    _feature([[[13.26, 53.56, 12.0], [13.2601, 53.56, 12.0], [13.2601, 53.5601, 12.0]]]),  # heights
    _feature([[[13.26, 53.56], [13.2601, 53.56], [True, 53.5601]]]),  # a boolean corner
    _feature([[[13.27, 53.56], [13.2701, 53.56]]]),  # two corners
    _feature([_shifted(SQUARE, 0.002)], building="yes"),
]


@pytest.mark.parametrize("crs", [None, "lonlat", "EPSG:4326"])
def test_plain_polygons_read_together_as_one_by_one(tmp_path, monkeypatch, crs):
    path = tmp_path / "lots.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": FEATURES}))
    together = read_lots(path, crs=crs)
    # the one-feature path for every feature: no plain polygon read in bulk
    monkeypatch.setattr(city_lots, "_Corners", lambda features: _NoPlain(features), raising=True)
    one_by_one = read_lots(path, crs=crs)
    assert len(together.lots) == len(one_by_one.lots) == len(FEATURES)
    assert together.origin == one_by_one.origin
    for a, b in zip(together.lots, one_by_one.lots, strict=True):
        assert (a.id, a.problem, a.properties) == (b.id, b.problem, b.properties)
        assert (a.geometry is None) == (b.geometry is None)
        np.testing.assert_array_equal(a.ring, b.ring)
    problems = [lot.problem for lot in together.lots]
    assert problems[0] is None and problems[1] is None and problems[-1] is None
    assert sum(p is not None for p in problems) >= 4


class _NoPlain:
    def __init__(self, features):
        from shapegen.readers import geojson

        self.plain = np.zeros(len(features), dtype=bool)
        self.points = np.zeros((0, 2))
        self.offsets = np.zeros(1, dtype=np.int64)
        self.all = np.concatenate([geojson.positions(f["geometry"]) for f in features])
