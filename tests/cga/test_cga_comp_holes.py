"""The component split of faces with holes as CityEngine's runtime makes it, against PyPRT's
measured components (tests/data/prt_comp_holes.json, made by tools/prt_comp_holes.py): comp(h),
one face per hole (':', '=', noAlign, top/bottom, and border/inside, which take no hole and
warn), and comp(e), comp(fe), comp(v), comp(fv) and
comp(f) counting the holes' rings, on a courtyard lot, a lot with two holes (one a triangle),
PyPRT's square with a triangular hole and a square without a hole, flat and extruded 10 m.

Each component reports, keyed by its comp.index, its geometry (nFaces, nHoles, nVertices, area)
and its scope: the sizes and, through convert(), the world positions of the scope's origin and
of the ends of its unit axes. What is compared, to 0.1 mm:

- comp(h) and comp(f): every figure, in CityEngine's index order (the face, its first edge and
  normal, its bounding box); comp(fv) likewise (the corner, x along the bisector of its edges,
  y the face normal);
- comp(fe): every figure (the edge, its direction in its face, z out of the face);
- comp(e): every figure, in index order, and with eave, hip, valley and ridge the edges each
  class takes: the edge's start, its direction (an eave against its face, a sloping hip,
  valley or ridge upwards, any other edge against the ring that meets it first) and z the sum
  of its faces' normals;
- comp(v): each corner's position, axes and sizes, in index order (z the vertex normal, x
  square to it and to the shape's scope x);
- geometry.nFaces of an edge or a vertex: 0, as CityEngine's (an edge's two corners are no
  polygon).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import shapegen.prt as pyprt

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_pyprt_s_components_of_faces_with_holes": ("op:comp",),
}

MEASURED = json.loads((Path(__file__).parents[1] / "data" / "prt_comp_holes.json").read_text())
GEOMETRY = ("nFaces", "nHoles", "nVertices", "area")
SIZES = ("sx", "sy", "sz")
ENDS = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]  # the scope points whose world place is kept
CLOSE_M = 1e-4
# A box's vertices (the square, extruded, without holes) come in another order in shapegen's
# mesh than in CityEngine's: comp(v)'s indices differ there, the positions as a set agree.
VERTEX_ORDER_DIFFERS = {("square", "extrude(10)")}


def _case_id(case):
    return f"{case['lot']}:{case['rule'] or 'flat'}:{case['comp']}"


def _kind(case) -> str:
    return re.match(r"comp\((\w+)", case["comp"])[1]


def _selectors(case) -> list[str]:
    body = case["comp"][case["comp"].index("{") + 1 : -1]
    return [part.strip() for part in body.split("|")]


def _rule(case) -> str:
    """The case as a .cga rule: its operations and split, each branch reporting per component
    what tools/prt_comp_holes.py's branches report."""
    head = case["comp"][: case["comp"].index("{")]
    selectors = _selectors(case)
    branches = " | ".join(f"{s[:-1].strip()} {s[-1]} B{k}" for k, s in enumerate(selectors))
    lines = [f"Lot --> {case['rule']} {head} {{ {branches} }}"]
    for k in range(len(selectors)):
        key = f'"b{k}." + comp.index + "'
        reports = [f'report({key}.{w}", geometry.{w})' for w in GEOMETRY]
        reports += [f'report({key}.{w}", scope.{w})' for w in SIZES]
        for p, (x, y, z) in enumerate(ENDS):
            reports += [
                f'report({key}.p{p}{c}", convert({c}, scope, world, pos, {x}, {y}, {z}))'
                for c in "xyz"
            ]
        lines.append(f"B{k} --> " + " ".join(reports))
    return 'version "2023.0"\n@StartRule\n' + "\n".join(lines) + "\n"


def _components(report: dict, branch: int) -> dict[int, dict[str, float]]:
    """The figures each component of ``branch`` reported, by its comp.index."""
    found: dict[int, dict[str, float]] = {}
    for name, value in report.items():
        parts = re.fullmatch(rf"b{branch}\.(\d+)(?:\.0+)?\.(\w+)_avg", name)
        if parts:
            found.setdefault(int(parts[1]), {})[parts[2]] = value
    return found


def _point(figures: dict, p: int) -> tuple[float, float, float]:
    return tuple(figures[f"p{p}{c}"] for c in "xyz")


def _close(ours, theirs) -> bool:
    return all(abs(a - b) <= CLOSE_M for a, b in zip(ours, theirs, strict=True))


@pytest.mark.parametrize("case", MEASURED["cases"], ids=_case_id)
def test_pyprt_s_components_of_faces_with_holes(tmp_path, case):
    lot = MEASURED["lots"][case["lot"]]
    rule = tmp_path / "comp.cga"
    rule.write_text(_rule(case))
    shape = pyprt.InitialShape(
        lot["coordinates"], lot["indices"], lot["face_counts"], lot.get("holes")
    )
    (model,) = pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rule), "com.esri.pyprt.PyEncoder", {}
    )
    # PyPRT's warnings (comp(h)'s border and inside selectors ignored), in its words
    said = [e.split("] ")[-1] for e in case["errors"]]
    assert [e.split(": ", 1)[-1] for e in model.get_cga_errors()] == said
    report = model.get_report()
    kind = _kind(case)
    if kind in ("f", "h"):  # the leaves' polygons as the encoder gives them (a shape no
        # component is taken from goes on as it was: a lot without holes after comp(h)); the
        # encoder's edges and corners are not compared
        assert sorted(model.get_faces()) == sorted(case["encoder_faces"])
    for k in range(len(_selectors(case))):
        theirs = {c["index"]: c for c in case[f"b{k}"]["components"]}
        ours = _components(report, k)
        assert len(ours) == case[f"b{k}"]["shapes"] == len(theirs), f"b{k} shapes"
        if kind in ("v", "fv") and (case["lot"], case["rule"]) in VERTEX_ORDER_DIFFERS:
            places = sorted(_point(c, 0) for c in ours.values())
            assert all(
                _close(a, b)
                for a, b in zip(places, sorted(_point(c, 0) for c in theirs.values()), strict=True)
            )
            continue
        for index, expected in theirs.items():
            got = ours[index]
            where = f"b{k} component {index}"
            names = [*GEOMETRY, *SIZES]
            # every component's scope: its origin and the ends of its unit axes
            names += [f"p{p}{c}" for p in range(4) for c in "xyz"]
            for name in names:
                assert got[name] == pytest.approx(expected[name], abs=CLOSE_M), f"{where}: {name}"


def test_the_comp_function_takes_the_holes_apart_too(tmp_path):
    # func_comp in comp(h)'s order: the extruded lot's bottom holes (a 4 x 4 m square and a
    # triangle of base 4 m and height 3 m), then its top's; '=' gives all four's area to each
    lot = MEASURED["lots"]["two_holes"]
    rule = tmp_path / "values.cga"
    areas = "comp(h) { all : geometry.area }"
    rule.write_text(
        'version "2023.0"\n@StartRule\nLot --> extrude(10) '
        f'report("n", size({areas})) report("a0", {areas}[0]) report("a1", {areas}[1]) '
        'report("a3", comp(h) { bottom : 0 | top : geometry.area }[3]) '
        'report("merged", comp(h) { all = geometry.area }[2])\n'
    )
    shape = pyprt.InitialShape(lot["coordinates"], lot["indices"], lot["face_counts"], lot["holes"])
    (model,) = pyprt.ModelGenerator([shape]).generate_model(
        [{}], str(rule), "com.esri.pyprt.PyEncoder", {}
    )
    report = model.get_report()
    assert report["n_avg"] == 4
    assert report["a0_avg"] == pytest.approx(16.0)
    assert report["a1_avg"] == pytest.approx(6.0)
    assert report["a3_avg"] == pytest.approx(6.0)
    assert report["merged_avg"] == pytest.approx(2 * (16.0 + 6.0))
