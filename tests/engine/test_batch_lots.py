"""Lots derived as one batch against the same lots derived one at a time: the same leaves
(corners to round-off, faces, block or solid), reports and attrs, on real footprints (most not
convex) and rectangles; what the batch does not implement falls back, counted."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from batch_widths import compare_widths, footprints

import shapegen
from shapegen.engine.batch import derive_lots
from shapegen.engine.batch.lots import BOX

DATA = Path(__file__).resolve().parents[1] / "data"
EXTRUSION = """version "2023.0"
attr parcelArea = 0
attr minBuildingHeight = 10
attr maxBuildingHeight = 30
attr buildingColor = "#FF00FF"
attr OBJECTID = 0
attr text = "salut"

@StartRule
Footprint -->
    set(parcelArea, geometry.area())
    BuildingCreation

BuildingCreation -->
    extrude(rand(minBuildingHeight, maxBuildingHeight))
    color(buildingColor)
    report("Building Height." + OBJECTID, geometry.volume() / parcelArea)
    report("Min Height." + OBJECTID, minBuildingHeight)
    report("Parcel Area." + OBJECTID, parcelArea)
    report("Text", text)
    ReportNext

ReportNext -->
    case text == "salut" && parcelArea > 300:
        report("Value", 1)
        report("Bool value", true)
    else:
        report("Value", 56)
        Chance

Chance -->
    30% : report("Kind", "tall") Tall.
    25% : report("Kind", "mid") Mid
    else : report("Kind", rand(2) + 1 > 2)

Mid -->
    40% : report("Mid", "a")
    40% : report("Mid", "b")
    else : report("Mid", rand())
"""


def _grammar(tmp_path, text: str):
    path = tmp_path / "rule.cga"
    path.write_text(text)
    return shapegen.load_grammar(path)


def _batch(grammar, rings, overrides=None):
    offsets = np.zeros(len(rings) + 1, dtype=np.int64)
    np.cumsum([len(r) for r in rings], out=offsets[1:])
    seeds = [1000 + 7 * k for k in range(len(rings))]
    given = overrides or [{}] * len(rings)
    return derive_lots(grammar, np.concatenate(rings), offsets, seeds, given), seeds


def test_batch_gives_what_one_lot_at_a_time_gives(tmp_path):
    grammar = _grammar(tmp_path, EXTRUSION)
    rings = footprints(150, tmp_path)
    seeds = [1000 + 7 * k for k in range(len(rings))]
    batch = compare_widths(grammar, rings, seeds)
    derived = np.flatnonzero(~batch.fallback)
    assert len(derived) >= 0.95 * len(rings)  # most lots go in the batch
    assert set(batch.kind[derived].tolist()) == {0, 1, 2}  # boxes, convex blocks, solids
    assert (batch.kind[derived] == BOX).sum() >= 3  # the rectangles


def test_lots_the_batch_cannot_derive_fall_back_counted(tmp_path):
    rings = footprints(40, tmp_path)
    # an operation the batch does not implement: every lot falls back, with the reason
    grammar = _grammar(tmp_path, "Lot --> extrude(10) comp(f) { top : Roof | side : Wall }")
    batch, _ = _batch(grammar, rings)
    assert batch.fallback.all() and batch.derived == 0
    assert sum(batch.reasons.values()) == len(rings)
    assert any("comp" in reason or "Comp" in reason for reason in batch.reasons)
    # a branch that some lots take: only those lots fall back
    text = (
        "Lot --> case geometry.area() > 300 : extrude(5) Big\n"
        "    else : extrude(3) comp(f) { top : R }"
    )
    batch, _ = _batch(_grammar(tmp_path, text), rings)
    big = batch.footprints.area > 300
    assert batch.fallback[~big & ~batch.footprints.doubtful].all()
    assert not batch.fallback[big & ~batch.footprints.doubtful].any()
    assert 0 < batch.derived < len(rings)
    # a footprint that runs clockwise, one that crosses itself: left to the one-at-a-time path
    square = np.array([[0.0, 0.0], [0.0, -5.0], [5.0, -5.0], [5.0, 0.0]])
    bowtie = np.array([[0.0, -3.0], [9.0, 0.0], [9.0, -9.0], [0.0, 0.0]])
    batch, _ = _batch(_grammar(tmp_path, EXTRUSION), [square, square[::-1], bowtie])
    assert batch.fallback.tolist() == [True, False, True]
    assert batch.reasons == {
        "a footprint that runs clockwise": 1,
        "a footprint that crosses itself": 1,
    }


def test_lot_properties_group_lots(tmp_path):
    from shapegen.pipeline import design

    grammar = _grammar(tmp_path, EXTRUSION)
    rings = footprints(30, tmp_path)
    tall, short = {"maxBuildingHeight": 80.0, "text": "other"}, {}
    given = [tall if k % 3 == 0 else short for k in range(len(rings))]
    batch, seeds = _batch(grammar, rings, given)
    reports = batch.reports()
    for k in np.flatnonzero(~batch.fallback).tolist()[:12]:
        lot = [tuple(p) for p in rings[k].tolist()]
        model = design(grammar, attrs=given[k], seed=seeds[k], lot=lot, assess=False).model
        assert reports[k].keys() == model.metadata["reports"].keys()
        height = model.metadata["reports"]["Building Height.0"]
        assert reports[k]["Building Height.0"] == pytest.approx(height, rel=1e-12)
