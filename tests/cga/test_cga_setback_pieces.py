"""setback's pieces as CityEngine's runtime gives them, against PyPRT's measured figures
(tests/data/prt_setback.json, made by tools/prt_setback.py): the edges a branch selects joined
into one face (a ring with a hole for ``all``), the first branch taking the corners it shares
with a later one, a face's holes kept in the piece around them, the remainder; each ring with
PyPRT's corners in PyPRT's order, from the same first corner."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from prt_cases import branch_rule, case_id, encoder_rings, model_on_lot

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {"test_pyprt_s_setback_pieces": ("op:setback",)}

MEASURED = json.loads((Path(__file__).parents[1] / "data" / "prt_setback.json").read_text())
FIGURES = ("nFaces", "nHoles", "nVertices", "area")


# Where a hole of the courtyard cuts the remainder in two, the ring around the remainder
# starts on the hole's first corner in PyPRT and on the set-back line of the first edge in
# shapegen, and one remainder piece starts on another corner: the same corners in the same
# turn, another first one. Every other ring starts where PyPRT's does.
OTHER_START = {
    ("courtyard", f"setback(3) {{ {branches} }}")
    for branches in ("all: | remainder:", "all:", "all=")
}


def _rings(vertices, indices, counts) -> list:
    """Each face (or hole) as its corners in order, rounded to 0.1 mm."""
    return [
        [tuple(round(c, 4) + 0.0 for c in p) for p in ring]
        for ring in encoder_rings(vertices, indices, counts)
    ]


def _turned(ring: list) -> list:
    """``ring`` started on its smallest corner: the same ring whatever its first corner."""
    first = ring.index(min(ring))
    return ring[first:] + ring[:first]


@pytest.mark.parametrize("case", MEASURED["cases"], ids=case_id)
def test_pyprt_s_setback_pieces(tmp_path, case):
    lot = MEASURED["lots"][case["lot"]]
    model = model_on_lot(tmp_path / "setback.cga", branch_rule(case["rule"], FIGURES), lot)
    # CityEngine warns where an array of distances has not one per face edge, holes' too
    warnings = [e.split("setback(): ")[1] for e in case["errors"]]
    assert [e.split("setback(): ")[1] for e in model.get_cga_errors()] == warnings
    report = model.get_report()
    for k in range(len(re.findall(r"[:=]", case["rule"]))):
        expected = case[f"b{k}"]
        assert report.get(f"b{k}.nFaces_n", 0) == expected["shapes"], f"b{k} shapes"
        for name in FIGURES:
            if expected[name] is not None:
                got = report[f"b{k}.{name}_sum"]
                assert got == pytest.approx(expected[name], abs=1e-6), f"b{k}.{name}"
    assert len(model.get_vertices()) // 3 == case["encoder_vertices"]
    assert sorted(model.get_faces()) == sorted(case["encoder_faces"])
    if "points" in case:
        flat = [c for p in case["points"] for c in p]
        ours = _rings(model.get_vertices(), model.get_indices(), model.get_faces())
        theirs = _rings(flat, case["indices"], case["encoder_faces"])
        if (case["lot"], case["rule"]) in OTHER_START:
            ours, theirs = [_turned(r) for r in ours], [_turned(r) for r in theirs]
        assert sorted(ours) == sorted(theirs)


# op_setback: "The array must be in face-edge order, i.e. the first element is the distance of
# the first edge of the first face, the second element is the distance of the second edge of
# the first face, and so on."
def test_an_array_of_distances_runs_over_the_faces_in_order():
    from shapegen import parse_grammar

    front_then_back = "[1, 0, 0, 0,  0, 0, 0, 0,  2, 0, 0, 0,  0, 0, 0, 0]"
    text = (
        "@StartRule\nLot --> extrude(4) comp(f) { side = Sides }\n"
        f'Sides --> setback({front_then_back}) {{ all = report("a", geometry.area) G. }}'
    )
    model = parse_grammar(text, "r.cga").build(lot=(12.0, 8.0))
    # the sides' first edges are their bottom ones: 12 m of the front by 1 m, 12 m of the back
    # by 2 m (the first four values on every face would give 12 + 8 + 12 + 8)
    assert model.metadata["reports"]["a"] == pytest.approx(12 * 1 + 12 * 2)
    assert not [w for w in model.metadata.get("warnings", ()) if "array size" in w]
    short = text.replace(front_then_back, "[1, 0, 0]")
    model = parse_grammar(short, "r.cga").build(lot=(12.0, 8.0))
    assert any("array size smaller" in w for w in model.metadata["warnings"])
