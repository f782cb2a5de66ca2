"""The model written is the model reported: every command that writes a model or a report is run
with --optimize, --fix, --free and --margin, and what it wrote is judged again from the files.

Also the three faults that showed two pipelines (--fix dropped from the written model, bridge
options silently ignored, a bridge report that disagreed with itself), each as a user runs it.
"""

import json
from pathlib import Path

import numpy as np
import pytest

import shapegen
from shapegen.cli import main
from shapegen.readers.models import read_model
from shapegen.statics import analyze
from shapegen.structures import Design, make_structure

STACK = """
@Free @Range(0.0, 0.6)
attr base = 0.1
@Free @Range(0.0, 0.6)
attr shift = 0.0
@StartRule @Lot(1, 1)
Lot --> extrude(2) split(y) { 1 : Bottom | 1 : Top }
Bottom --> s(base + 0.5, '1, '1) Stone
Top --> t(0.3 - shift, 0, 0) Stone
"""


def _build(tmp_path: Path, *arguments: str) -> tuple[dict, Path]:
    report, model = tmp_path / "r.json", tmp_path / "m.json"
    code = main(["build", *arguments, "--quiet", "-o", str(model), "--report", str(report)])
    assert code == 0
    return json.loads(report.read_text()), model


def _rebuilt_equals_written(grammar_name: str, report: dict, model_path: Path) -> None:
    """Building the grammar with the report's attrs gives exactly the blocks written."""
    grammar = shapegen.load_grammar(grammar_name)
    rebuilt = grammar.build(attrs=report["attrs"], seed=report["seed"], lot=report["lot"])
    written = read_model(model_path)
    assert len(rebuilt.blocks) == len(written.blocks) == report["blocks"]
    for a, b in zip(rebuilt.blocks, written.blocks, strict=True):
        np.testing.assert_allclose(a.vertices, b.vertices, atol=1e-9)


def test_fix_is_honoured_in_the_written_model(tmp_path):
    """The issue's first example: `--optimize --fix column_width=1.2` wrote column_width 0.3."""
    report, model_path = _build(
        tmp_path, "arch_columns.grammar", "--optimize", "--fix", "column_width=1.2"
    )
    assert report["attrs"]["column_width"] == 1.2
    assert report["optimization"]["fixed"] == {"column_width": 1.2}
    written = analyze(read_model(model_path))
    assert written.feasible == report["analysis"]["feasible"] == report["analysis"]["stands"]
    assert written.infeasibility_normalized == pytest.approx(
        report["analysis"]["infeasibility_normalized"], abs=1e-12
    )
    _rebuilt_equals_written("arch_columns.grammar", report, model_path)


@pytest.mark.parametrize(
    "options",
    [
        ["--free", "base", "--fix", "shift=0.05"],
        ["--free", "base,shift", "--objective", "closest"],
        ["--margin", "0.2"],
        ["--gradient", "forward", "--fix", "base=0.45"],
    ],
)
def test_every_written_model_is_the_reported_one(tmp_path, options):
    grammar = tmp_path / "stack.grammar"
    grammar.write_text(STACK)
    report, model_path = _build(tmp_path, str(grammar), "--optimize", *options)
    written = analyze(read_model(model_path))
    assert written.feasible == report["analysis"]["stands"]
    assert written.infeasibility_normalized == pytest.approx(
        report["analysis"]["infeasibility_normalized"], abs=1e-12
    )
    for name, value in report["optimization"]["fixed"].items():
        assert report["attrs"][name] == value
    for name, spec in report["optimization"]["parameters"].items():
        assert report["attrs"][name] == pytest.approx(spec["final"])
    _rebuilt_equals_written(str(grammar), report, model_path)
    if "--margin" in options:  # the reserve was searched for and is reported
        assert report["optimization"]["margin"] == 0.2
        shrunk = analyze(read_model(model_path), kern=0.8)
        assert shrunk.feasible


def test_bridge_options_are_honoured_or_refused(tmp_path, capsys):
    """The issue's second example: `--margin 0.5 --objective closest --gradient forward` on the
    bridge exited 0 with margin 0.0 in the report."""
    report, model_path = _build(
        tmp_path,
        "suspension_bridge.grammar",
        "--optimize",
        "--set",
        "max_cable_diameter=0.8",
        "--margin",
        "0.1",
        "--objective",
        "closest",
        "--gradient",
        "forward",
    )
    optimization, analysis = report["optimization"], report["analysis"]
    assert optimization["margin"] == 0.1
    assert optimization["objective"] == "closest" and optimization["gradient"] == "forward"
    assert optimization["structure"] == analysis["structure"] == "cable"
    assert analysis["cable_diameter"] <= 0.9 * 0.8 + 1e-9  # the reserve holds
    # The written model records its structure: analyze judges it as the report did.
    written = read_model(model_path)
    again = make_structure(written.metadata["structure"]["name"]).assess(Design.of_model(written))
    assert again.section["cable_diameter"] == pytest.approx(analysis["cable_diameter"])
    assert main(["analyze", str(model_path), "--quiet", "--report", str(tmp_path / "a.json")]) == 0
    assert json.loads((tmp_path / "a.json").read_text())["stands"] == analysis["stands"]
    _rebuilt_equals_written("suspension_bridge.grammar", report, model_path)
    # What means nothing for cables is refused with one line, never dropped.
    for refused, message in (
        (["--optimize", "--gradient", "adjoint"], "gives no gradient"),
        (["--analyze", "--friction", "0.5"], "applies to block statics"),
        (["--optimize", "--kern", "0.5"], "applies to block statics"),
    ):
        assert main(["build", "suspension_bridge.grammar", "--quiet", *refused]) == 2
        err = capsys.readouterr().err
        assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_bridge_report_agrees_with_itself_and_the_geometry(tmp_path):
    """The issue's third example: one report said towers = 3 in one place and 4 in another."""
    report, model_path = _build(
        tmp_path,
        "suspension_bridge.grammar",
        "--analyze",
        "--set",
        "length=3000.6",
        "--set",
        "main_span=1000.2",
        "--set",
        "towers=0",
        "--set",
        "min_span=100",
        "--set",
        "sag=125",
    )
    model = read_model(model_path)
    legs = {round(float(b.centroid[0]), 3) for b in model.blocks if "tower leg" in b.tags}
    towers = report["reports"]["towers"]
    assert towers == report["reports"]["main_spans"] + 1 == len(legs)
    side_span = report["reports"]["side_span"]
    assert report["analysis"]["side_span"] == pytest.approx(side_span)
    assert 3000.6 == pytest.approx(2 * side_span + (towers - 1) * 1000.2)


def test_landscape_of_a_bridge_plots_the_cable_measure(tmp_path):
    picture = tmp_path / "bridge.png"
    code = main(["landscape", "suspension_bridge.grammar", "main_span", "sag", "--grid", "3",
                 "--no-path", "--quiet", "-o", str(picture)])  # fmt: skip
    assert code == 0 and picture.read_bytes()[:4] == b"\x89PNG"


def test_landscape_titles_its_plot_with_the_rule_name_not_a_path(tmp_path, monkeypatch):
    import shapegen.export.landscape_plot as landscape_plot

    titles = []
    plot = landscape_plot.plot_landscape
    monkeypatch.setattr(
        landscape_plot,
        "plot_landscape",
        lambda *args, title=None, **kw: (titles.append(title), plot(*args, title=title, **kw)),
    )
    deep = tmp_path / "a folder with a long name" / "and another one"
    deep.mkdir(parents=True)
    rule = deep / "stack.grammar"
    rule.write_text(STACK)
    picture = tmp_path / "l.png"
    code = main(["landscape", str(rule), "base", "shift", "--grid", "2", "--no-path", "--quiet",
                 "-o", str(picture)])  # fmt: skip
    assert code == 0 and picture.read_bytes()[:4] == b"\x89PNG"
    assert titles == ["stack.grammar: y/W²"]


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["build", "arch_columns.grammar", "-o", "{tmp}/x.json", "--report", "{tmp}/x.json"],
         "name the same file"),
        (["build", "arch_columns.grammar", "-o", "{tmp}/missing/x.json"], "does not exist"),
        (["build", "arch_columns.grammar", "-o", "{tmp}/folder.json"], "is a folder"),
        (["analyze", "cluny.grammar"], "use `shapegen build cluny.grammar --analyze`"),
        (["build", "clunny.grammar"], "did you mean 'cluny.grammar'"),
    ],
)  # fmt: skip
def test_output_and_input_mistakes_are_found_before_any_work(tmp_path, capsys, arguments, message):
    (tmp_path / "folder.json").mkdir()
    arguments = [a.replace("{tmp}", str(tmp_path)) for a in arguments]
    assert main(arguments) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not [path for path in tmp_path.glob("*.json") if path.is_file()]


def test_analyze_writes_the_model_it_judged(tmp_path):
    built, model_path = _build(tmp_path, "arch_columns.grammar", "--set", "arch_thickness=0.4")
    copy, report = tmp_path / "copy.json", tmp_path / "a.json"
    arguments = ["analyze", str(model_path), "--kern", "0.8", "-o", str(copy), "--report"]
    assert main([*arguments, str(report), "--quiet"]) == 0
    judged = json.loads(report.read_text())
    again = analyze(read_model(copy), kern=0.8)
    assert again.feasible == judged["stands"] == judged["feasible"]
    assert again.infeasibility_normalized == pytest.approx(
        judged["infeasibility_normalized"], abs=1e-12
    )
    assert len(read_model(copy).blocks) == built["blocks"]


def test_simulate_simulates_the_model_it_reports(tmp_path):
    pytest.importorskip("pybullet", reason="the simulator is the optional extra shapegen[sim]")
    report = tmp_path / "s.json"
    code = main(["simulate", "arch_columns.grammar", "--optimize", "--fix", "column_width=1.2",
                 "--seconds", "0.6", "--quiet", "--report", str(report)])  # fmt: skip
    assert code == 0
    data = json.loads(report.read_text())
    build = data["build"]
    assert build["attrs"]["column_width"] == 1.2
    assert build["optimization"]["fixed"] == {"column_width": 1.2}
    assert build["optimization"]["margin"] == 0.1  # simulate keeps a reserve by default
    rebuilt = shapegen.load_grammar("arch_columns.grammar").build(attrs=build["attrs"])
    assert len(rebuilt.blocks) == build["blocks"] == data["simulation"]["blocks"]


def test_a_missing_rule_file_gets_no_far_fetched_suggestion(capsys):
    assert main(["build", "missing.grammar"]) == 2
    err = capsys.readouterr().err
    assert "no grammar file 'missing.grammar'" in err and "did you mean" not in err
