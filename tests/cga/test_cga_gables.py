"""roofGable's gables where the straight skeleton ties, against PyPRT's measured models
(tests/data/prt_gables.json, made by tools/prt_gables.py): a square's ridge runs along its
first edge whatever its turn, first corner or winding; a near-square's and a rectangle's along
their longer edges, and a square's 1 mm out of square along its shorter; a kite, a rhombus and
a hexagon's pointed ends stay hipped; turned squares with corners rounded to the mm or cm
(angles no longer right) follow their tiny ridges; lots without a tie (trapezoids, a
parallelogram, L, T, U and plus shapes) keep their gables; the index argument gables edges
index and index + 2. Each model's corners (to 0.1 mm), figures and scope, its faces in edge
order (the gables are the triangles) and warnings. What PyPRT does otherwise (regular
polygons, an index there in some runs, a corner on an edge) is a strict xfail naming the
difference."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from prt_cases import assert_figures, corners_near, figures_rule, model_on_lot

MEASURED = json.loads((Path(__file__).parents[1] / "data" / "prt_gables.json").read_text())
FIGURES = ("nFaces", "area", "volume")  # reported by each case's rule
CORNER_M = 1e-4  # PyPRT's corners are recorded to 1e-6 m; shapegen's must be this close
OPEN = {"roofGable(30, 1, 0.5)"}  # an overhanging roof is open: shapegen's volume is 0
# PyPRT's own round-off in area and volume: one square turned by 30 degrees, its corners
# rounded to the mm, has a volume of 144.328028, 144.328041 or 144.328046 m^3 after its first
# corner (1.3e-5 m^3 apart)
FIGURE_REL = 1e-6

# PyPRT gables the regular polygons, whose hip faces all meet at the centre, by its own
# floating-point event order (the octagon's gables change with its first corner, the
# pentagon's with its first corner) and carries the ridge level from the centre to each gable,
# which leaves the slopes beside it non-planar; shapegen keeps them hipped.
REGULAR = ("pentagon", "hexagon", "octagon")
# PyPRT's index on a regular octagon fails in some runs and not in others, the same cases each
# time (the octagon along the axes, the one turned by 15 degrees on all edges but 5 and 7): it
# warns "applying offset failed, retrying without offset" and builds the roof without the index,
# gabled as above. The recorded run has no failure (its index gables edges index and index + 2,
# as shapegen's); a measurement that records the warning is a strict xfail.
INDEX_FAILED = "applying offset failed, retrying without offset"
# PyPRT drops a corner that lies on an edge: the square with a fifth corner gets the square's
# pyramid, the rectangle the rectangle's gable roof, each with one face over the two halves of
# the edge (nFaces 5); shapegen builds the same roofs with a face per edge (nFaces 6; the
# rectangle's ridge has one more corner, above the fifth corner)
ON_EDGE = ("square5", "rectangle5")


def _case_id(case):
    return f"{case['lot']}:{case['rule']}"


def _differs(case) -> str | None:
    lot = case["lot"]
    if "false," in case["rule"]:  # an index
        if any(INDEX_FAILED in e for e in case["errors"]):
            return "PyPRT's index failed on a regular octagon in this run and was dropped"
        return None
    if lot.startswith(REGULAR):
        return "PyPRT gables a regular polygon by its floating-point event order"
    if lot.startswith(ON_EDGE):
        return "PyPRT's roof has one face over an edge's two halves"
    return None


def _generate(tmp_path, case):
    text = figures_rule(case["rule"], FIGURES)
    return model_on_lot(tmp_path / "gable.cga", text, MEASURED["lots"][case["lot"]])


def _marked(cases):
    out = []
    for case in cases:
        reason = _differs(case)
        marks = [pytest.mark.xfail(reason=reason, strict=True)] if reason else []
        out.append(pytest.param(case, marks=marks, id=_case_id(case)))
    return out


@pytest.mark.parametrize("case", _marked(MEASURED["cases"]))
def test_pyprt_s_gable_roofs_where_the_skeleton_ties(tmp_path, case):
    model = _generate(tmp_path, case)
    said = [e.split("] ")[-1] for e in case["errors"]]
    assert [e.split(": ", 1)[-1] for e in model.get_cga_errors()] == said
    assert corners_near(model.get_vertices(), case["points"], CORNER_M)
    report = model.get_report()
    assert_figures(report, case, ["nFaces"])  # and the scope's sizes
    figures = [f for f in ("area", "volume") if not (f == "volume" and case["rule"] in OPEN)]
    for name in figures:
        assert report[f"{name}_avg"] == pytest.approx(case[name], rel=FIGURE_REL), name


@pytest.mark.parametrize("case", _marked(MEASURED["cases"]))
def test_the_gables_stand_on_pyprt_s_edges(tmp_path, case):
    # the PyEncoder's faces: the bottom, then one per edge in edge order; a gable is a
    # triangle on a quadrilateral lot, a slope at least a quadrilateral
    model = _generate(tmp_path, case)
    assert list(model.get_faces()) == case["encoder_faces"]
