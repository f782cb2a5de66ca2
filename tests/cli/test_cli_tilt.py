"""`--tilt` and `--capacity` on `shapegen analyze`, `build --analyze` and `build --optimize`.

The pier of PIER is w wide, 1 m high and 0.8 m deep on the ground (mu 0.7, the 4-sided pyramid:
sliding at atan(0.7 / sqrt(2)) = 26.3 deg): it tips across its width at atan(w / 1) and across
its depth at atan(0.8) = 38.7 deg. So it stands on a table tilted by 20 deg across its width
when w >= tan(20 deg) = 0.364 m, and its worst direction is across its width (azimuth 0 or 180)
while w < 0.8.
"""

import json
import math

import pytest

from shapegen.cli import main
from shapegen.export.blocks_json import write_blocks_json
from shapegen.model.block import Block
from shapegen.model.model import Model

PIER = """
@Free @Range(0.1, 1.0)
attr w = 0.15
@StartRule @Lot(1, 0.8)
Lot --> extrude(1) s(w, '1, '1) Pier
"""
TAN_20 = math.tan(math.radians(20.0))


@pytest.fixture
def pier(tmp_path):
    path = tmp_path / "pier.grammar"
    path.write_text(PIER)
    return path


def pier_model(tmp_path, width: float):
    path = tmp_path / f"pier_{width}.json"
    write_blocks_json(Model([Block.box([0, 0, 0], [width, 1.0, 0.8], id="pier")]), path)
    return path


def run(argv, capsys):
    status = main([str(a) for a in argv])
    captured = capsys.readouterr()
    # the printout wraps long cells: compare its words
    return status, " ".join(captured.out.split()), captured.err


def test_analyze_tilted_towards_a_direction_and_the_worst(tmp_path, capsys):
    model, report = pier_model(tmp_path, 0.3), tmp_path / "r.json"
    # across the depth (azimuth 90) it holds at 20 deg; across its width it tips past 16.7 deg
    status, out, _ = run(["analyze", model, "--tilt", "20@90", "--report", report], capsys)
    assert status == 0 and json.loads(report.read_text())["stands"] is True
    assert "20 deg towards azimuth 90 deg" in out
    status, out, _ = run(["analyze", model, "--tilt", "20", "--report", report], capsys)
    data = json.loads(report.read_text())
    assert status == 0 and data["stands"] is False
    assert data["tilt"]["azimuth"] == "worst" and data["tilt"]["azimuth_deg"] in (0.0, 180.0)
    assert data["tilt"]["load_multiplier"] == pytest.approx(TAN_20)
    assert "(the worst direction)" in out
    status, _, _ = run(["analyze", model, "--tilt", "16@0", "--report", report], capsys)
    assert json.loads(report.read_text())["stands"] is True


def test_analyze_capacity_towards_azimuths_and_over_a_sweep(tmp_path, capsys):
    model, report = pier_model(tmp_path, 0.3), tmp_path / "r.json"
    status, out, _ = run(["analyze", model, "--capacity", "0,90", "--report", report], capsys)
    assert status == 0
    capacity = json.loads(report.read_text())["capacity"]
    across, along = capacity["directions"]
    assert across["azimuth_deg"] == 0.0 and along["azimuth_deg"] == 90.0
    assert across["tilt_deg"] == pytest.approx(math.degrees(math.atan(0.3)), abs=0.025)
    # along its 0.8 m depth it would tip at atan(0.8) = 38.66 deg: it slides first, at atan(mu)
    # with the default friction cone (atan(mu / sqrt 2) with --pyramid 4, a side facing the slope)
    assert along["tilt_deg"] == pytest.approx(math.degrees(math.atan(0.7)), abs=0.025)
    for entry in capacity["directions"]:
        assert entry["load_multiplier"] == pytest.approx(math.tan(math.radians(entry["tilt_deg"])))
    assert capacity["tilt_deg"] == across["tilt_deg"] and capacity["azimuth_deg"] == 0.0
    assert capacity["resolution_deg"] == 0.05 and capacity["sweep"] is False
    assert "lateral capacity" in out and "16.70 deg" in out
    # no azimuth: a sweep of 16 directions and the worst of them
    status, out, _ = run(["analyze", model, "--report", report, "--capacity"], capsys)
    capacity = json.loads(report.read_text())["capacity"]
    assert capacity["sweep"] is True and len(capacity["directions"]) >= 16
    assert capacity["tilt_deg"] == pytest.approx(math.degrees(math.atan(0.3)), abs=0.025)
    assert "the worst of" in out


def test_build_analyze_reports_the_capacity_in_the_analysis(pier, tmp_path, capsys):
    report = tmp_path / "r.json"
    argv = ["build", pier, "--set", "w=0.4", "--analyze", "--capacity=0", "--report", report]
    status, _, err = run(argv, capsys)
    assert status == 0, err
    analysis = json.loads(report.read_text())["analysis"]
    assert analysis["capacity"]["tilt_deg"] == pytest.approx(
        math.degrees(math.atan(0.4)), abs=0.025
    )
    assert "tilt" not in analysis  # judged upright


@pytest.mark.parametrize("tilt", ["20@0", "20"])
def test_optimize_finds_a_design_that_stands_tilted(pier, tmp_path, capsys, tilt):
    report = tmp_path / "r.json"
    argv = ["build", pier, "--optimize", "--tilt", tilt, "--margin", "0", "--capacity=0"]
    status, _, err = run([*argv, "--report", report, "-q"], capsys)
    assert status == 0, err
    data = json.loads(report.read_text())
    width = data["optimization"]["parameters"]["w"]["final"]
    assert data["optimization"]["feasible"] and data["analysis"]["stands"]
    assert TAN_20 - 1e-6 <= width < 0.8  # the closed form: w >= tan(20 deg)
    assert data["analysis"]["tilt"]["tilt_deg"] == 20.0
    assert data["analysis"]["capacity"]["tilt_deg"] >= 20.0 - 0.025
    # the same design upright: it stood before the search too, so the tilt did the work
    status, _, _ = run(["build", pier, "--analyze", "--tilt", tilt, "--report", report], capsys)
    assert json.loads(report.read_text())["analysis"]["stands"] is False


BAD = [
    (["--tilt", "nan"], "--tilt: tilt must be a number of degrees"),
    (["--tilt", "90"], "below 90"),
    (["--tilt", "120@0"], "below 90"),
    (["--tilt", "-5"], "at least 0"),
    (["--tilt", "10@north"], "'north'"),
    (["--tilt", "10@"], "not a number of degrees"),
    (["--tilt", "ten"], "DEG@AZIMUTH"),
    (["--capacity", "0,x"], "azimuths in degrees"),
    (["--capacity", "inf"], "finite"),
]


@pytest.mark.parametrize("extra, message", BAD, ids=[" ".join(b[0]) for b in BAD])
def test_bad_values_are_one_line_and_exit_2(tmp_path, capsys, extra, message):
    status, out, err = run(["analyze", pier_model(tmp_path, 0.3), *extra], capsys)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith("shapegen: error: ")
    assert message in err


def test_capacity_before_the_model_says_where_to_put_it(tmp_path, capsys):
    status, _, err = run(["analyze", "--capacity", pier_model(tmp_path, 0.3)], capsys)
    assert status == 2 and "--capacity after the model" in err


REFUSED = [
    (["build", "suspension_bridge.grammar", "--analyze", "--tilt", "5"], "--tilt applies to"),
    (["build", "suspension_bridge.grammar", "--analyze", "--capacity"], "--capacity applies"),
    (["build", "suspension_bridge.grammar", "--optimize", "--tilt", "5"], "'cable' structure"),
    (["build", "{pier}", "--tilt", "5"], "--tilt: they apply with --analyze or --optimize"),
    (["build", "{pier}", "--capacity"], "--capacity: it applies with --analyze or --optimize"),
]


@pytest.mark.parametrize("argv, message", REFUSED, ids=[" ".join(r[0][1:]) for r in REFUSED])
def test_an_option_that_cannot_apply_is_refused(pier, tmp_path, capsys, argv, message):
    argv = [str(pier) if a == "{pier}" else a for a in argv]
    status, out, err = run([*argv, "--report", tmp_path / "r.json"], capsys)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and message in err
    assert not (tmp_path / "r.json").exists()


def test_a_model_judged_by_its_cables_refuses_the_tilt(tmp_path, capsys):
    bridge = tmp_path / "bridge.json"
    status, _, err = run(["build", "suspension_bridge.grammar", "-o", bridge, "-q"], capsys)
    assert status == 0, err
    status, _, err = run(["analyze", bridge, "--tilt", "5", "--capacity"], capsys)
    assert status == 2
    assert "--tilt, --capacity apply to block statics" in err and "'cable'" in err


def test_loads_that_are_not_vertical_refuse_the_capacity(tmp_path, capsys):
    model = Model([Block.box([0, 0, 0], [0.5, 1.0, 0.8], id="pier")], gravity=[1.0, -9.81, 0.0])
    path = tmp_path / "leaning.json"
    write_blocks_json(model, path)
    status, _, err = run(["analyze", path, "--capacity"], capsys)
    assert status == 2 and "not along -y" in err and len(err.splitlines()) == 1
    status, _, err = run(["analyze", path, "--tilt", "5@0"], capsys)
    assert status == 0, err  # a tilt towards a given direction turns every load
