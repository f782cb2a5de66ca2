"""The ``shapegen`` command, in process through ``main(argv)`` and as a real subprocess."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from analysis_report import ANALYSIS_REPORT_KEYS

import shapegen
from shapegen import Block, Model
from shapegen.cli import main
from shapegen.export.blocks_json import model_to_dict, write_blocks_json

REPO = Path(__file__).resolve().parents[2]
ARCH = REPO / "docs" / "examples" / "arch.json"


def semicircular_arch(thickness_ratio: float, voussoirs: int = 24) -> Model:
    """Centreline radius 1 m, radial joints, springings on the ground."""
    angles = np.linspace(0.0, np.pi, voussoirs + 1)
    cos, sin = np.cos(angles), np.sin(angles)
    sin[[0, -1]] = 0.0
    inner, outer = 1 - thickness_ratio / 2, 1 + thickness_ratio / 2
    blocks = [
        Block.from_hull(
            [
                [r * cos[j], r * sin[j], z]
                for j in (k, k + 1)
                for r in (inner, outer)
                for z in (0, 1)
            ]
        )
        for k in range(voussoirs)
    ]
    return Model(blocks)


def write_json(path: Path, document) -> Path:
    path.write_text(json.dumps(document))
    return path


def one_box_document() -> dict:
    return model_to_dict(Model([Block.box([0, 0, 0], [1, 1, 1], id="b0")]))


# ------------------------------------------------------------------------------ analyze
@pytest.mark.parametrize(
    "thickness_ratio, stands",
    # A semicircular arch needs t/R >= 0.1075 (Milankovitch / Heyman); 24 voussoirs are close.
    [(0.16, True), (0.07, False)],
)
def test_analyze_arch_reports_and_writes(tmp_path, capsys, thickness_ratio, stands):
    model_path = tmp_path / "arch.json"
    write_blocks_json(semicircular_arch(thickness_ratio), model_path)
    report_path, glb_path = tmp_path / "report.json", tmp_path / "arch.glb"
    status = main(["analyze", str(model_path), "--report", str(report_path), "-o", str(glb_path)])
    assert status == 0  # standing or not, the run succeeded
    report = json.loads(report_path.read_text())
    assert ANALYSIS_REPORT_KEYS <= set(report), ANALYSIS_REPORT_KEYS - set(report)
    assert report["blocks"] == 24
    assert report["interfaces"] == 25  # 23 joints and 2 springings
    assert report["feasible"] is stands
    assert report["total_weight"] == pytest.approx(
        2400 * 9.81 * 24 * 0.5 * thickness_ratio * 2 * math.sin(math.pi / 24), rel=1e-9
    )  # 24 trapezoidal prisms: area (R_o^2 - R_i^2) sin(dθ)/2 = 2 t R sin(dθ)/2 per unit depth
    assert glb_path.read_bytes()[:4] == b"glTF"
    out = capsys.readouterr().out
    assert ("stands" in out) and (("yes" if stands else "no") in out)


def test_analyze_options_reach_the_statics(tmp_path):
    """A kern of 1/3 makes a thick arch that stands with full joints fail (t/R 0.16 < 0.3)."""
    model_path = tmp_path / "arch.json"
    write_blocks_json(semicircular_arch(0.16), model_path)
    report = tmp_path / "r.json"
    argv = ["analyze", str(model_path), "--kern", "0.3333", "--report", str(report), "-q"]
    assert main(argv) == 0
    assert json.loads(report.read_text())["feasible"] is False


def test_quiet_prints_nothing(tmp_path, capsys):
    path = write_json(tmp_path / "box.json", one_box_document())
    assert main(["analyze", str(path), "--quiet"]) == 0
    assert capsys.readouterr() == ("", "")


BAD_ANALYZE_INPUTS = [
    # (name, file content or None for a missing file, extra arguments, message fragment)
    ("missing", None, [], "cannot read"),
    ("invalid JSON", "{ not json", [], "invalid JSON"),
    ("binary file", "\udcff\udcfe{", [], "UTF-8"),
    ("no blocks", json.dumps({"format": "shapegen-blocks", "version": 1}), [], '"blocks"'),
    (
        "NaN vertex",
        json.dumps(one_box_document()).replace("[0.0, 0.0, 0.0]", "[NaN, 0.0, 0.0]", 1),
        [],
        "finite",
    ),
    (
        "infinite vertex",
        json.dumps(one_box_document()).replace("[1.0, 1.0, 1.0]", "[Infinity, 1.0, 1.0]", 1),
        [],
        "finite",
    ),
    ("wrong format", json.dumps({"format": "other", "blocks": []}), [], '"format"'),
    ("bad pyramid", json.dumps(one_box_document()), ["--pyramid", "5"], "--pyramid"),
    ("zero kern", json.dumps(one_box_document()), ["--kern", "0"], "--kern"),
    ("NaN friction", json.dumps(one_box_document()), ["--friction", "nan"], "--friction"),
    ("negative friction", json.dumps(one_box_document()), ["--friction", "-1"], "--friction"),
    ("bad output", json.dumps(one_box_document()), ["-o", "{dir}/out.step"], "out.step"),
    ("no output dir", json.dumps(one_box_document()), ["-o", "{dir}/none/out.glb"], "exist"),
    ("no report dir", json.dumps(one_box_document()), ["--report", "{dir}/none/r.json"], "exist"),
]


@pytest.mark.parametrize(
    "content, extra, message",
    [case[1:] for case in BAD_ANALYZE_INPUTS],
    ids=[case[0] for case in BAD_ANALYZE_INPUTS],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, content, extra, message):
    model_path = tmp_path / "model.json"
    if content is not None:
        model_path.write_bytes(content.encode("utf-8", "surrogateescape"))
    before = set(tmp_path.iterdir())
    args = [a.replace("{dir}", str(tmp_path)) for a in extra]
    status = main(["analyze", str(model_path), "--report", str(tmp_path / "r.json"), *args])
    captured = capsys.readouterr()
    assert status == 2
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("shapegen: error: ")
    assert message in lines[0]
    assert set(tmp_path.iterdir()) == before  # no report, no half-written output


def test_unknown_model_extension(tmp_path, capsys):
    path = tmp_path / "model.step"
    path.write_text("ISO-10303-21;")
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert ".json" in err and ".glb" in err and len(err.splitlines()) == 1


def test_unsupported_model_is_exit_2(tmp_path, capsys):
    """A block floating above the ground has no support: a StaticsError, not a traceback."""
    model = Model([Block.box([0, 1, 0], [1, 2, 1], id="floating")])
    path = tmp_path / "floating.json"
    write_blocks_json(model, path)
    assert main(["analyze", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("shapegen: error: ") and "floating" in err


@pytest.mark.parametrize("argv", [["--version"], ["analyze", "--help"], ["--help"]])
def test_version_and_help_exit_0(capsys, argv):
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert shapegen.__version__ in out if argv == ["--version"] else "usage: shapegen" in out


def test_no_command_is_a_usage_error(capsys):
    assert main([]) == 2
    assert capsys.readouterr().err.startswith("shapegen: error: ")


# ------------------------------------------------------------------------------ subprocess
def run(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "shapegen", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_subprocess_analyze_bundled_arch(tmp_path):
    result = run("analyze", str(ARCH), "--report", "r.json", "-o", "arch.glb", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert json.loads((tmp_path / "r.json").read_text())["feasible"] is True
    assert (tmp_path / "arch.glb").stat().st_size > 0
    assert "stands" in result.stdout


def test_subprocess_bad_input_has_no_traceback(tmp_path):
    result = run("analyze", "missing.json", "-o", "out.glb", cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.startswith("shapegen: error: missing.json")
    assert len(result.stderr.splitlines()) == 1
    assert "Traceback" not in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_console_script_version():
    script = Path(sys.executable).with_name("shapegen")
    if not script.exists():
        pytest.skip("the shapegen console script is not installed beside this interpreter")
    result = subprocess.run([str(script), "--version"], capture_output=True, text=True)
    assert result.returncode == 0 and result.stdout.strip() == f"shapegen {shapegen.__version__}"


# ------------------------------------------------------------------------------ --set values
@pytest.mark.parametrize(
    "text, expected",
    [
        ("h=3", ("h", 3)),
        ("h=2.5", ("h", 2.5)),
        ("h=-1e-3", ("h", -1e-3)),
        ("flag=true", ("flag", True)),
        ("flag=False", ("flag", False)),
        ("style=gothic", ("style", "gothic")),
        ("style='two words'", ("style", "two words")),
        (" h = 4 ", ("h", 4)),
    ],
)
def test_set_values(text, expected):
    from shapegen.cli.common_options import _assignment

    assert _assignment(text) == expected


@pytest.mark.parametrize("text", ["h", "=3", "h=nan", "h=inf"])
def test_bad_set_values(text):
    import argparse

    from shapegen.cli.common_options import _assignment

    with pytest.raises(argparse.ArgumentTypeError):
        _assignment(text)


# ------------------------------------------------------------------------------ build
WALL_GRAMMAR = """\
# A wall of square stones, one per metre of lot width
attr height = 3
@Free @Range(1, 5)
attr width = 2
@StartRule @Lot(4, 1)
Lot --> extrude(height) split(x) { ~1 : Stone }* report("courses", 1)
"""


@pytest.fixture
def wall_grammar(tmp_path) -> Path:
    path = tmp_path / "wall.grammar"
    path.write_text(WALL_GRAMMAR)
    return path


def test_build_writes_model_and_report(tmp_path, wall_grammar, capsys):
    out, report_path = tmp_path / "wall.json", tmp_path / "r.json"
    argv = ["build", str(wall_grammar), "--set", "height=2", "-o", str(out)]
    status = main([*argv, "--report", str(report_path), "--analyze"])
    assert status == 0, capsys.readouterr().err
    report = json.loads(report_path.read_text())
    # A 4 m x 1 m lot split into ~1 m pieces: 4 stones of 1 x 2 x 1 m.
    assert report["blocks"] == 4
    assert report["volume"] == pytest.approx(8.0)
    assert report["attrs"]["height"] == 2.0 and report["attrs"]["width"] == 2.0
    assert report["free_parameters"] == {"width": {"value": 2.0, "min": 1.0, "max": 5.0}}
    assert report["reports"] == {"courses": 1.0}
    assert (
        ANALYSIS_REPORT_KEYS <= set(report["analysis"]) and report["analysis"]["feasible"] is True
    )
    from shapegen.readers.models import read_model

    model = read_model(out)
    assert len(model.blocks) == 4
    np.testing.assert_allclose([b.volume for b in model.blocks], 2.0)


@pytest.mark.parametrize("lot, stones", [("6,1", 6), ("3.4, 3", 3)])
def test_build_lot_option(tmp_path, wall_grammar, lot, stones):
    report = tmp_path / "r.json"
    assert main(["build", str(wall_grammar), "--lot", lot, "--report", str(report), "-q"]) == 0
    assert json.loads(report.read_text())["blocks"] == stones


@pytest.mark.parametrize("suffix", [".glb", ".gltf", ".obj", ".ply", ".stl"])
def test_build_output_formats(tmp_path, wall_grammar, suffix):
    out = tmp_path / f"wall{suffix}"
    assert main(["build", str(wall_grammar), "-o", str(out), "-q"]) == 0
    assert out.stat().st_size > 0


BAD_BUILD_ARGS = [
    ("unknown attr", ["--set", "heigth=2"], "did you mean 'height'"),
    ("bad set", ["--set", "height"], "NAME=VALUE"),
    ("wrong attr type", ["--set", "height=tall"], "height"),
    ("bad lot", ["--lot", "4"], "--lot"),
    ("zero lot", ["--lot", "0,1"], "--lot"),
    ("bad seed", ["--seed", "x"], "--seed"),
    ("bad output", ["-o", "{dir}/wall.step"], "wall.step"),
]


@pytest.mark.parametrize(
    "extra, message", [case[1:] for case in BAD_BUILD_ARGS], ids=[c[0] for c in BAD_BUILD_ARGS]
)
def test_build_bad_arguments(tmp_path, wall_grammar, capsys, extra, message):
    args = [a.replace("{dir}", str(tmp_path)) for a in extra]
    before = set(tmp_path.iterdir())
    status = main(["build", str(wall_grammar), *args, "--report", str(tmp_path / "r.json")])
    err = capsys.readouterr().err
    assert status == 2
    assert len(err.splitlines()) == 1 and err.startswith("shapegen: error: ")
    assert message in err
    assert set(tmp_path.iterdir()) == before


def test_build_grammar_error_shows_the_source(tmp_path, capsys):
    path = tmp_path / "bad.grammar"
    path.write_text("attr h = 3\n@StartRule\nLot --> extrude(h) split(x) { ~1 : Stone\n")
    status = main(["build", str(path), "-o", str(tmp_path / "out.json")])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith(f"shapegen: error: {path}:3:")
    assert "Lot --> extrude(h)" in err and "^" in err and "Traceback" not in err
    assert not (tmp_path / "out.json").exists()


def test_build_missing_grammar(tmp_path, capsys):
    assert main(["build", str(tmp_path / "absent.grammar")]) == 2
    assert "absent.grammar" in capsys.readouterr().err


def test_rules_lists_bundled_files(capsys):
    from shapegen.engine.project.rules_path import bundled_rules

    assert main(["rules"]) == 0
    out = capsys.readouterr().out
    for name in bundled_rules():
        assert name in out


def test_rules_lists_each_file_with_its_whole_first_sentence():
    from shapegen.cli.rules import description
    from shapegen.engine.project.rules_path import bundled_rules, find_bundled_rule

    for name in bundled_rules():
        text = description(find_bundled_rule(name))
        assert text.endswith(".") and text.count('"') % 2 == 0, (name, text)
    arch = description(find_bundled_rule("arch_columns.grammar"))
    assert arch.endswith('"Procedural Modeling of Structurally-Sound Masonry Buildings" (2009).')


def test_a_set_value_outside_its_range_is_warned_about_and_used_as_given(tmp_path, capsys):
    report = tmp_path / "r.json"
    code = main(["build", "arch_columns.grammar", "--set", "arch_thickness=0.9", "--set",
                 "column_width=0.5", "--quiet", "--report", str(report)])  # fmt: skip
    assert code == 0
    err = capsys.readouterr().err
    assert err.count("warning") == 1
    assert "--set arch_thickness=0.9 is outside its @Range [0.1, 0.8]: built as given" in err
    assert json.loads(report.read_text())["attrs"]["arch_thickness"] == 0.9  # not clamped


def test_the_command_starts_without_the_heavy_libraries():
    """`shapegen --help` must come at once: importing the command loads neither scipy nor the
    grammar machinery (measured: 0.3 s for --help; scipy.spatial alone takes 0.4 s)."""
    code = (
        "import sys; from shapegen.cli import build_parser; build_parser(); "
        "print(sorted(m for m in ('scipy', 'lark', 'matplotlib', 'trimesh') if m in sys.modules))"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"
