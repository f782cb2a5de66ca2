"""setbackToArea, shapeL, shapeU, shapeO and innerRectangle on faces with holes, as
CityEngine's runtime makes them (tests/data/prt_setback_holes.json, made by
tools/prt_setback_holes.py on a 12 x 8 m lot with a 4 x 2 m courtyard, the same lot started
on another corner, and 20 x 16 m blocks with an 8 x 6 m courtyard, an 8 x 6 m yard off the
middle and a square yard turned 45 degrees): each branch's shapes and their figures, the
encoder's vertices and faces, and each ring's corners."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from prt_cases import branch_rule, case_id, encoder_rings, model_on_lot

MEASURED = json.loads((Path(__file__).parents[1] / "data" / "prt_setback_holes.json").read_text())
FIGURES = ("nFaces", "nHoles", "nVertices", "area")
# setbackToArea's distance is CityEngine's search's: its remainder's area within about 0.002 m^2
# of the area asked (40.001141 for 40), shapegen's within 1e-9; the corners then differ by less
# than 0.1 mm.
AREA_M2 = 3e-3
CORNER_M = 1e-4
# Where the turned yard's corner lies on innerRectangle's cut, CityEngine's runtime moves it
# 1.6 mm into the remainder (7.0016, 8), so that the yard stays a hole of the remainder;
# shapegen keeps it on the cut: the remainder's area differs by 0.005 m^2.
NUDGED = {("diamond", f"innerRectangle({a}) {{ shape: | remainder: }}") for a in ("scope", "edge")}
NUDGE_M, NUDGE_M2 = 2e-3, 6e-3
# Set back around the turned yard, whose tips cut the remainder in two, CityEngine's strip has
# 5 more corners on its outline (in line with its edges) and an area of 237.0 m^2, which with
# the remainder's 40 falls 25 m^2 short of the face's 302: its strip is not a valid polygon.
# shapegen's strip is the face less the remainder (262 m^2, 4 + 10 corners); the remainder,
# two pieces of 40 m^2, is CityEngine's.
STRIP_NOT_VALID = {("diamond", "setbackToArea(40) { all: | remainder: }")}


def _rings(vertices, indices, counts) -> list:
    """Each face (or hole) as its corners in order, from its smallest corner (PyPRT's rings
    and shapegen's may start on different corners of the same turn)."""
    out = []
    for ring in encoder_rings(vertices, indices, counts):
        rounded = [tuple(round(c, 3) + 0.0 for c in p) for p in ring]
        first = rounded.index(min(rounded))
        out.append(ring[first:] + ring[:first])
    return sorted(out, key=lambda r: [tuple(round(c, 3) + 0.0 for c in p) for p in r])


@pytest.mark.parametrize("case", MEASURED["cases"], ids=case_id)
def test_pyprt_s_pieces_of_a_holed_face(tmp_path, case):
    lot = MEASURED["lots"][case["lot"]]
    model = model_on_lot(tmp_path / "pieces.cga", branch_rule(case["rule"], FIGURES), lot)
    assert model.get_cga_errors() == case["errors"]
    key = (case["lot"], case["rule"])
    area_m2, corner_m = (NUDGE_M2, NUDGE_M) if key in NUDGED else (AREA_M2, CORNER_M)
    report = model.get_report()
    for k in range(len(re.findall(r"[:=]", case["rule"]))):
        expected = case[f"b{k}"]
        assert report.get(f"b{k}.nFaces_n", 0) == expected["shapes"], f"b{k} shapes"
        if key in STRIP_NOT_VALID and k == 0:
            assert report["b0.area_sum"] + report["b1.area_sum"] == pytest.approx(20 * 16 - 18)
            continue
        for name in FIGURES:
            if expected[name] is not None:
                got = report[f"b{k}.{name}_sum"]
                assert got == pytest.approx(expected[name], abs=area_m2), f"b{k}.{name}"
    if key in STRIP_NOT_VALID:
        return
    assert len(model.get_vertices()) // 3 == case["encoder_vertices"]
    assert sorted(model.get_faces()) == sorted(case["encoder_faces"])
    flat = [c for p in case["points"] for c in p]
    ours = _rings(model.get_vertices(), model.get_indices(), model.get_faces())
    theirs = _rings(flat, case["indices"], case["encoder_faces"])
    assert [len(r) for r in ours] == [len(r) for r in theirs]
    for mine, prt in zip(ours, theirs, strict=True):
        flat_mine = [c for corner in mine for c in corner]
        assert flat_mine == pytest.approx([c for corner in prt for c in corner], abs=corner_m)
