"""The report says how many leaves the statics left out and why, in one line on the command
line; warnings of the derivation are listed."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.cli.display import left_out_line, print_build
from shapegen.geometry.mesh import Mesh
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
    # without an analysis the surfaces row counts them, by reason, on one line
    lines = [line for line in out.splitlines() if "drawn, not solid" in line]
    assert len(lines) == 1 and "2 drawn, not solid: 1 a face (no volume), 1 not convex" in lines[0]
    assert "warning: asset 'assets/door.obj' not found" in out


def test_a_written_model_keeps_its_surfaces_and_is_analyzed_again(tmp_path):
    """build writes the roof face as a surface; analyze of the written file gives the same
    verdict and reads the surface back."""
    import json

    from shapegen.cli import main
    from shapegen.readers.models import read_model

    grammar = tmp_path / "roofed.grammar"
    grammar.write_text("@StartRule\nLot --> extrude(3) [ comp(f) { top : Roof. } ] Box.\n")
    for suffix in (".json", ".glb"):
        model, first, second = (tmp_path / f"model{suffix}", tmp_path / f"r1{suffix}.json",
                                tmp_path / f"r2{suffix}.json")  # fmt: skip
        assert main(["build", str(grammar), "--lot", "12,8", "--analyze", "-q", "-o", str(model),
                     "--report", str(first)]) == 0  # fmt: skip
        back = read_model(model)
        assert len(back.blocks) == 1 and [s.reason for s in back.surfaces] == ["a face (no volume)"]
        assert Mesh(back.surfaces[0].vertices, back.surfaces[0].faces).area() == pytest.approx(96)
        assert main(["analyze", str(model), "-q", "--report", str(second)]) == 0
        built, analyzed = json.loads(first.read_text()), json.loads(second.read_text())
        assert built["left_out"]["by_reason"] == {"a face (no volume)": 1}
        assert analyzed["stands"] is built["analysis"]["stands"] is True
        assert analyzed["infeasibility"] == pytest.approx(
            built["analysis"]["infeasibility"], rel=1e-6, abs=1e-6
        )
