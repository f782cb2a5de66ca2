"""``shapegen simulate``: reports, pictures, grammar input and one-line errors."""

import json

import pytest
from PIL import Image

from shapegen.cli import main
from shapegen.export.blocks_json import write_blocks_json
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation.cases import harmonic_stack


@pytest.fixture
def stack_path(tmp_path):
    path = tmp_path / "stack.json"
    write_blocks_json(harmonic_stack(1.10, count=3), path)
    return path


def test_report_of_a_falling_stack(stack_path, tmp_path, capsys):
    report = tmp_path / "r.json"
    status = main(["simulate", str(stack_path), "--seconds", "2", "--report", str(report)])
    assert status == 0  # falling is a result, not an error
    document = json.loads(report.read_text())
    simulation = document["simulation"]
    assert simulation["verdict"] == "collapses"
    assert simulation["moved_blocks"] >= 1
    assert simulation["simulated_seconds"] == pytest.approx(2.0)
    assert len(simulation["per_block"]) == 3
    # The evidence: the top block fell by many times its 0.2 m thickness, fast.
    top = simulation["largest_movers"][0]
    assert top["id"] == "s2" and top["fell"] and top["relative_displacement"] > 1.0
    assert simulation["max_relative_displacement"] == top["relative_displacement"]
    assert simulation["peak_speed"] > 1.0  # m/s
    track = simulation["displacement_over_time"]
    assert len(track["time"]) == len(track["max_displacement"]) == 41  # 20 per second, and t = 0
    assert track["max_displacement"][-1] > track["max_displacement"][0]
    out = capsys.readouterr().out
    assert "collapses" in out and "fell" in out and "widths" in out and "peak" in out


def test_friction_and_remove_reach_the_run(stack_path, tmp_path):
    report = tmp_path / "r.json"
    argv = ["simulate", str(stack_path), "--seconds", "1", "--friction", "0.3", "-q"]
    assert main([*argv, "--remove", "s2", "--report", str(report)]) == 0
    simulation = json.loads(report.read_text())["simulation"]
    assert simulation["friction"] == 0.3
    assert simulation["removed"] == ["s2"]
    assert simulation["blocks"] == 2


def test_gif_and_frames(stack_path, tmp_path):
    gif, frames = tmp_path / "fall.gif", tmp_path / "frames"
    argv = ["simulate", str(stack_path), "--seconds", "1", "--fps", "4", "-q"]
    assert main([*argv, "-o", str(gif)]) == 0
    with Image.open(gif) as image:
        assert image.format == "GIF" and image.n_frames == 5  # t = 0, 0.25, 0.5, 0.75, 1
    assert main([*argv, "--frames", str(frames)]) == 0
    assert sorted(p.name for p in frames.iterdir())[0] == "frame_0000.png"
    assert len(list(frames.glob("*.png"))) == 5


def test_grammar_is_built_with_set_values(tmp_path):
    grammar = tmp_path / "pier.grammar"
    grammar.write_text(
        'version "2024.0"\n'
        "attr height = 1\n"
        "@StartRule\n@Lot(1, 1)\n"
        "Lot --> extrude(height) Pier\n"
        'Pier --> i("box")\n'
    )
    report = tmp_path / "r.json"
    argv = ["simulate", str(grammar), "--set", "height=2", "--seconds", "1"]
    assert main([*argv, "--report", str(report), "-q"]) == 0
    document = json.loads(report.read_text())
    assert document["build"]["attrs"]["height"] == 2
    assert document["simulation"]["verdict"] == "stands"


@pytest.mark.parametrize(
    "extra, message",
    [
        (["-o", "x.mp4"], ".gif"),
        (["--remove", "nothing"], "no block has the id or label 'nothing'"),
        (["--set", "a=1"], "apply only to a rule file"),
        (["--seconds", "-1"], "must be > 0"),
        (["--seconds", "0.4"], "settling window"),
        (["--report", "no/such/folder/r.json"], "does not exist"),
    ],
)
def test_user_mistakes_give_one_line(tmp_path, capsys, extra, message):
    path = tmp_path / "box.json"
    write_blocks_json(Model([Block.box([0, 0, 0], [1, 1, 1], id="b0")]), path)
    assert main(["simulate", str(path), *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(("extra", "margin"), [([], 0.1), (["--margin", "0"], 0.0)])
def test_optimize_keeps_a_safety_margin_unless_told_otherwise(tmp_path, extra, margin):
    # A design on the statics boundary has no reserve for the simulator's contact compliance, so
    # simulate --optimize searches with a 10 % margin by default, as build --optimize does.
    report = tmp_path / "r.json"
    argv = ["simulate", "arch_columns", "--optimize", "--seconds", "0.6", "-q"]
    assert main([*argv, *extra, "--report", str(report)]) == 0
    optimization = json.loads(report.read_text())["build"]["optimization"]
    assert optimization["feasible"]
    assert optimization["margin"] == pytest.approx(margin)
    assert (f"with a {margin:.0%} margin" in optimization["message"]) == (margin > 0)


def test_a_design_judged_by_its_cables_is_not_simulated_as_blocks(tmp_path, capsys):
    """Rigid blocks cannot hang from cables: the bridge would fall and be called collapsed."""
    from shapegen.cli import main

    report = tmp_path / "r.json"
    assert main(["simulate", "suspension_bridge.grammar", "--report", str(report)]) == 2
    err = capsys.readouterr().err
    assert "judged by the 'cable' structure" in err and err.count("\n") == 1
    assert not report.exists()
