"""comp(e)'s roof-edge selectors (op_comp "Roof Edges") on roofs with closed-form edges: a hip
roof on a w x d rectangle at angle a has 4 eaves (the perimeter), 4 hips of length
sqrt(2 (d/2)^2 + (d/2 tan a)^2) and a ridge of w - d; an L of two 6 m wings has one valley, from
the inner corner up to the skeleton (length sqrt(2 * 3^2 + (3 tan a)^2)). Hips, valleys and
ridges run upwards."""

from __future__ import annotations

import math

import pytest

import shapegen
from shapegen.errors import GrammarError

RULE = """@StartRule
Lot --> extrude(3) comp(f) { top : Roof }
Roof --> roofHip(30) comp(e) { eave : E | hip : H | valley : V | ridge : R }
E --> report("eave", scope.sx) X.
H --> report("hip", scope.sx) Rise
V --> report("valley", scope.sx) Rise
Rise --> report("rise", convert(y, scope, world, pos, scope.sx, 0, 0) - scope.elevation) X.
R --> report("ridge", scope.sx) X.
"""
TAN = math.tan(math.radians(30))


def _reports(tmp_path, lot):
    path = tmp_path / "roof.cga"
    path.write_text(RULE)
    reports = shapegen.load_grammar(path).build(lot=lot).metadata["reports"]
    return {k: v if isinstance(v, list) else [v] for k, v in reports.items()}


def test_hip_roof_on_a_rectangle(tmp_path):
    r = _reports(tmp_path, (12, 8))
    assert len(r["eave"]) == 4 and sum(r["eave"]) == pytest.approx(40)
    assert r["hip"] == pytest.approx([math.sqrt(2 * 4**2 + (4 * TAN) ** 2)] * 4)
    assert r["ridge"] == pytest.approx([4.0])
    assert "valley" not in r
    assert min(r["rise"]) > 0  # hips run upwards


def test_hip_roof_on_an_l_has_one_valley(tmp_path):
    lot = [(0, 14), (6, 14), (6, 6), (12, 6), (12, 0), (0, 0)]  # counter-clockwise from above
    r = _reports(tmp_path, lot)
    assert len(r["eave"]) == 6 and sum(r["eave"]) == pytest.approx(52)
    assert r["valley"] == pytest.approx([math.sqrt(2 * 3**2 + (3 * TAN) ** 2)])
    assert len(r["hip"]) == 5
    assert min(r["rise"]) > 0


def test_roof_edge_selectors_belong_to_comp_e(tmp_path):
    path = tmp_path / "bad.cga"
    path.write_text("@StartRule\nLot --> extrude(3) comp(f) { ridge : X }\n")
    with pytest.raises(GrammarError, match="needs comp\\(e\\)"):
        shapegen.load_grammar(path)
