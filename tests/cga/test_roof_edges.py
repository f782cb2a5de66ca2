"""comp(e)'s roof-edge selectors (op_comp "Roof Edges") on roofs with closed-form edges: a hip
roof on a w x d rectangle at angle a has 4 eaves (the perimeter), 4 hips of length
sqrt(2 (d/2)^2 + (d/2 tan a)^2) and a ridge of w - d; an L of two 6 m wings has one valley, from
the inner corner up to the skeleton (length sqrt(2 * 3^2 + (3 tan a)^2)). Hips, valleys and
ridges run upwards.

And against CityEngine's runtime (tests/data/prt_roof_edges.json, made by
tools/prt_roof_edges.py): each measured edge of each class, its two ends to 0.1 mm and the way
it runs (an eave's always, a hip's, valley's or ridge's where its ends' heights differ, which
op_comp orients upwards), on flat lots, extrusions, a cube, tapers, envelopes, shed roofs at
the 10 degree bounds of shapegen.geometry.roof_edges, and roofs on an L, a trapezoid and
courtyards."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest
from prt_cases import model_on_lot

import shapegen
from shapegen.errors import GrammarError

MEASURED = json.loads((Path(__file__).parents[1] / "data" / "prt_roof_edges.json").read_text())
CLASSES = ("eave", "hip", "valley", "ridge")
CLOSE_M = 1e-4

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


def _measured_rule(operations: str, kind: str = "e", selectors=CLASSES) -> str:
    """The case as a .cga rule: its operations, then comp(``kind``) whose branches report each
    component's scope origin, the end of its unit x axis and its length, by comp.index."""
    calls = re.sub(r"@\w+\.", "", operations).replace(",", ", ").split(";")
    branches = " | ".join(f"{name} : B{k}" for k, name in enumerate(selectors))
    lines = [f"Lot --> {' '.join(calls)} comp({kind}) {{ {branches} }}"]
    for k in range(len(selectors)):
        key = f'"b{k}." + comp.index + "'
        reports = [f'report({key}.sx", scope.sx)']
        for p, x in enumerate((0, 1)):
            reports += [
                f'report({key}.p{p}{c}", convert({c}, scope, world, pos, {x}, 0, 0))' for c in "xyz"
            ]
        lines.append(f"B{k} --> " + " ".join(reports))
    return 'version "2023.0"\n@StartRule\n' + "\n".join(lines) + "\n"


def _edges(report: dict, branch: int) -> list[tuple[tuple, tuple]]:
    """Each edge the branch got, as its start and end."""
    found: dict[int, dict[str, float]] = {}
    for name, value in report.items():
        parts = re.fullmatch(rf"b{branch}\.(\d+)(?:\.0+)?\.(\w+)_avg", name)
        if parts:
            found.setdefault(int(parts[1]), {})[parts[2]] = value
    out = []
    for figures in found.values():
        start = tuple(figures[f"p0{c}"] for c in "xyz")
        x_end = tuple(figures[f"p1{c}"] for c in "xyz")
        end = tuple(o + figures["sx"] * (e - o) for o, e in zip(start, x_end, strict=True))
        out.append((start, end))
    return out


def _near(a, b) -> bool:
    return all(abs(p - q) <= CLOSE_M for p, q in zip(a, b, strict=True))


@pytest.mark.parametrize(
    "case",
    MEASURED["cases"],
    ids=[f"{c['lot']}:{c['operations'] or 'flat'}" for c in MEASURED["cases"]],
)
def test_pyprt_s_roof_edge_classes(tmp_path, case):
    model = model_on_lot(
        tmp_path / "edges.cga", _measured_rule(case["operations"]), MEASURED["lots"][case["lot"]]
    )
    assert model.get_cga_errors() == case["errors"]
    report = model.get_report()
    for k, name in enumerate(CLASSES):
        ours = _edges(report, k)
        assert len(ours) == len(case[name]), name
        for start, end in case[name]:
            match = [e for e in ours if {_near(e[0], start), _near(e[1], end)} == {True}]
            turned = [e for e in ours if _near(e[0], end) and _near(e[1], start)]
            assert match or turned, f"{name} {start} -> {end}"
            if name == "eave" or abs(start[1] - end[1]) > 1e-3:
                assert match, f"{name} {start} -> {end} runs the other way"


@pytest.mark.parametrize(
    "case",
    MEASURED["cases"],
    ids=[f"{c['lot']}:{c['operations'] or 'flat'}" for c in MEASURED["cases"]],
)
def test_pyprt_s_every_edge_and_corner(tmp_path, case):
    """comp(e) { all : } and comp(v) { all : }: as many edges and corners as PyPRT's, in the
    same places. A roof's bottom, slopes and walls are sheets that share no edge and no corner,
    so an edge or a corner where two meet is listed once for each (a gable roof on a rectangle:
    17 edges and 16 corners). The order and the way an edge runs under ``all`` are not
    compared."""
    lot = MEASURED["lots"][case["lot"]]
    rule = _measured_rule(case["operations"], "e", ["all"])
    edges = _edges(model_on_lot(tmp_path / "edges.cga", rule, lot).get_report(), 0)
    assert len(edges) == len(case["all_edges"])
    unmatched = list(edges)
    for start, end in case["all_edges"]:
        same = [e for e in unmatched if {_near(e[0], start), _near(e[1], end)} == {True}]
        same = same or [e for e in unmatched if _near(e[0], end) and _near(e[1], start)]
        assert same, f"{start} -> {end}"
        unmatched.remove(same[0])
    rule = _measured_rule(case["operations"], "v", ["all"])
    corners = [c for c, _ in _edges(model_on_lot(tmp_path / "v.cga", rule, lot).get_report(), 0)]
    assert len(corners) == len(case["all_corners"])
    for place in case["all_corners"]:
        same = [c for c in corners if _near(c, place)]
        assert same, place
        corners.remove(same[0])
