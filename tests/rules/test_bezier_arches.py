"""rules/bezier_arches.grammar: three Bezier arches stacked in an arcade (seed Figure 12).

Truth values from the rule's layout: per storey an arch of 9 voussoirs and two piers of
3 courses (1.5 m of 0.5 m courses) below the springing and 4 courses (2 m) beside the arch,
and one capping course over the lot's whole width: 3 x (9 + 2 x 7) + 1 = 70 blocks. The
arcade is symmetric about its mid-plane, and swapping an arch's control points as
``(c1x, c2x) -> (1 - c2x, 1 - c1x)`` mirrors that arch, so a design and its mirror image need
the same tension.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from shapegen.cli import main
from shapegen.statics import analyze

RULES = Path(__file__).resolve().parents[2] / "rules"
GRAMMAR = RULES / "bezier_arches.grammar"
STOREYS = (1, 2, 3)


def test_three_arches_piers_in_courses_and_a_cap(grammar):
    attrs = grammar.attrs
    model = grammar.build()
    # Each pier stretch is split into courses of about course_height (CityEngine's ~ sizes).
    lower = round(attrs["springing_height"] / attrs["course_height"])
    upper = round((attrs["storey_height"] - attrs["springing_height"]) / attrs["course_height"])
    assert (lower, upper) == (1, 1)  # the tall stones of the file's values
    assert sum("arch" in b.tags for b in model.blocks) == 3 * 9
    assert sum("pier" in b.tags for b in model.blocks) == 3 * 2 * (lower + upper)
    assert sum("cap" in b.tags for b in model.blocks) == 1
    assert len(model.blocks) == 27 + 12 + 1
    thin = grammar.build(attrs={"course_height": 0.5}).blocks
    assert sum("pier" in b.tags for b in thin) == 3 * 2 * (3 + 4)


def test_the_cap_spans_the_lot_on_top_of_the_storeys(grammar):
    attrs = grammar.attrs
    (cap,) = [b for b in grammar.build().blocks if "cap" in b.tags]
    top = 3 * attrs["storey_height"]
    width = 4.0  # the lot
    assert cap.vertices.min(axis=0)[:2] == pytest.approx([0.0, top], abs=1e-9)
    assert cap.vertices.max(axis=0)[:2] == pytest.approx(
        [width, top + attrs["cap_height"]], abs=1e-9
    )


def test_six_free_control_point_positions(grammar):
    assert sorted(grammar.free_parameters) == sorted(f"c{i}x_{n}" for i in (1, 2) for n in STOREYS)


def test_arches_spring_from_the_pier_ledges(grammar):
    model = grammar.build()
    attrs = grammar.attrs
    ledge = attrs["pier_width"] - attrs["arch_thickness"]
    width = 4.0  # the lot
    arch_points = np.vstack([b.vertices for b in model.blocks if "arch" in b.tags])
    assert arch_points[:, 0].min() == pytest.approx(ledge, abs=1e-9)
    assert arch_points[:, 0].max() == pytest.approx(width - ledge, abs=1e-9)


def test_mirrored_arches_need_the_same_tension(grammar):
    attrs = grammar.attrs
    mirrored = {}
    for n in STOREYS:
        mirrored[f"c1x_{n}"] = 1 - attrs[f"c2x_{n}"]
        mirrored[f"c2x_{n}"] = 1 - attrs[f"c1x_{n}"]
    y = analyze(grammar.build()).infeasibility_normalized
    y_mirror = analyze(grammar.build(attrs=mirrored)).infeasibility_normalized
    assert y > 0
    assert y_mirror == pytest.approx(y, rel=1e-3)


def test_default_needs_tension(grammar):
    assert not analyze(grammar.build()).feasible


@pytest.mark.slow
def test_build_optimize_stands_within_bounds(grammar, tmp_path):
    report = tmp_path / "report.json"
    assert main(["build", str(GRAMMAR), "--optimize", "--quiet", "--report", str(report)]) == 0
    optimization = json.loads(report.read_text())["optimization"]
    assert optimization["feasible"]
    values = {}
    for name, p in optimization["parameters"].items():
        assert p["min"] <= p["final"] <= p["max"], name
        values[name] = p["final"]
    assert analyze(grammar.build(attrs=values)).feasible
