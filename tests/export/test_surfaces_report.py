"""The report says how many leaves the statics left out and why, in one line on the command
line; warnings of the derivation are listed."""

from __future__ import annotations

import numpy as np

from shapegen.cli.display import left_out_line, print_build
from shapegen.model import Model
from shapegen.model.appearance import Surface
from shapegen.model.block import Block
from shapegen.pipeline import build_report, report_bytes

SQUARE = np.array([[0, 2, 0], [0, 2, 1], [1, 2, 1], [1, 2, 0]], float)


def _model() -> Model:
    model = Model([Block.box((0, 0, 0), (1, 1, 1)), Block.box((0, 1, 0), (1, 2, 1))])
    model.surfaces = [
        Surface(SQUARE, [(0, 1, 2, 3)], reason="a face (no volume)"),
        Surface(SQUARE + 1, [(0, 1, 2, 3)], reason="not convex"),
    ]
    return model


def test_build_report_counts_left_out_leaves_by_reason():
    model = _model()
    model.metadata["warnings"] = ["asset 'assets/door.obj' not found (rules: Lot -> Door)"]
    report = build_report(model)
    assert report["blocks"] == 2
    assert report["left_out"] == {
        "leaves": 2,
        "by_reason": {"a face (no volume)": 1, "not convex": 1},
    }
    assert report["warnings"] == ["asset 'assets/door.obj' not found (rules: Lot -> Door)"]
    assert b'"left_out"' in report_bytes(report)


def test_left_out_is_one_line():
    assert left_out_line(build_report(_model())["left_out"]) == (
        "2 leaves not judged by the statics: 1 a face (no volume), 1 not convex"
    )
    assert left_out_line(build_report(Model([]))["left_out"]) == ""


def test_print_build_shows_the_line_and_the_warnings(capsys):
    model = _model()
    model.metadata["warnings"] = ["asset 'assets/door.obj' not found"]
    report = {**build_report(model), "seconds": 0.1}
    print_build("house.cga", report)
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if "not judged" in line]
    assert len(lines) == 1 and "1 a face (no volume), 1 not convex" in lines[0]
    assert "warning: asset 'assets/door.obj' not found" in out
