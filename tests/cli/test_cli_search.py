"""`shapegen build --optimize` and `shapegen landscape` as a user runs them."""

import json
from pathlib import Path

import pytest

from shapegen.cli import main

STACK = Path(__file__).parents[1] / "data" / "rules" / "stack.grammar"


@pytest.fixture
def stack(tmp_path):
    path = tmp_path / "stack.grammar"
    path.write_text(STACK.read_text())
    return path


def test_optimize_writes_a_standing_model_and_the_optimization_report(stack, tmp_path):
    report = tmp_path / "r.json"
    out = tmp_path / "m.json"
    code = main(["build", str(stack), "--optimize", "--quiet", "--report", str(report),
                 "-o", str(out)])  # fmt: skip
    assert code == 0
    data = json.loads(report.read_text())
    optimization = data["optimization"]
    assert optimization["feasible"] and data["analysis"]["feasible"]
    base = optimization["parameters"]["base"]
    assert base["initial"] == 0.1 and base["final"] >= 0.3 - 1e-6  # closed form: base >= 0.3
    assert data["attrs"]["base"] == pytest.approx(base["final"])
    for key in (
        "converged",
        "iterations",
        "evaluations",
        "method",
        "structure",
        "fixed",
        "seconds",
        "seconds_per_iteration",
        "initial_infeasibility",
        "final_infeasibility",
    ):
        assert key in optimization
    model = json.loads(out.read_text())
    widths = sorted(max(v[0] for v in b["vertices"]) - min(v[0] for v in b["vertices"])
                    for b in model["blocks"])  # fmt: skip
    assert widths[0] == pytest.approx(0.5 + base["final"])  # the optimized model was written


# On two blocks clarabel is the quickest back-end, which keeps the long searches (closest)
# short; the back-end plays no part in what a search finds (tests/search/test_search.py).
CLARABEL = ["--solver", "clarabel"]


def test_free_fix_and_closest(stack, tmp_path):
    report = tmp_path / "r.json"
    code = main(["build", str(stack), "--optimize", "--free", "base,shift", "--objective",
                 "closest", "--margin", "0", "--quiet", "--report", str(report),
                 *CLARABEL])  # fmt: skip
    assert code == 0
    parameters = json.loads(report.read_text())["optimization"]["parameters"]
    assert parameters["base"]["final"] == pytest.approx(0.2, abs=0.01)
    assert parameters["shift"]["final"] == pytest.approx(0.1, abs=0.01)
    code = main(["build", str(stack), "--optimize", "--free", "shift", "--fix", "base=0.25",
                 "--quiet", "--report", str(report), *CLARABEL])  # fmt: skip
    assert code == 0
    optimization = json.loads(report.read_text())["optimization"]
    assert list(optimization["parameters"]) == ["shift"]
    assert optimization["parameters"]["shift"]["final"] >= 0.05 - 1e-6


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--optimize", "--free", "bsae"], "did you mean 'base'"),
        (["--free", "base"], "--free only applies with --optimize"),
        (["--optimize", "--max-iter", "0"], "--max-iter: must be at least 1"),
        (["--margin", "0.1"], "--margin only applies with --optimize"),
        (["--gradient", "forward"], "--gradient only applies with --optimize"),
        (["--friction", "0.5"], "--friction: they apply with --analyze or --optimize"),
        (["--margin", "0.1", "--free", "base"], "--free, --margin only apply with --optimize"),
        (["--optimize", "--objective", "nearest"], "invalid choice"),
    ],
)
def test_search_mistakes_exit_2_with_one_line(stack, capsys, arguments, message):
    assert main(["build", str(stack), *arguments]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_landscape_writes_a_png_and_refuses_bad_requests(stack, tmp_path, capsys):
    picture = tmp_path / "land.png"
    assert main(["landscape", str(stack), "base", "shift", "--grid", "4", "-o", str(picture),
                 "--quiet"]) == 0  # fmt: skip
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["landscape", str(stack), "base", "base", "-o", str(picture)]) == 2
    assert main(["landscape", str(stack), "base", "shift", "-o", str(tmp_path / "x.jpg")]) == 2
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.parametrize(
    ("extra", "margin", "words"),
    [([], 0.1, "with a 10% margin"), (["--margin", "0"], 0.0, "(margin 0: no reserve)")],
)
def test_optimize_leaves_a_reserve_unless_asked_for_the_boundary(stack, tmp_path, extra, margin,
                                                                 words):  # fmt: skip
    # The joint spans x in [0.3, 0.5 + base]; shrunk about its middle to k = 1 - margin of its
    # length it still reaches the top block's centroid (x = 0.8) iff base >= (0.8-0.2k)/(1+k).
    report, model = tmp_path / "r.json", tmp_path / "m.json"
    code = main(["build", str(stack), "--optimize", "--objective", "closest", *extra, "--quiet",
                 "--report", str(report), "-o", str(model), *CLARABEL])  # fmt: skip
    assert code == 0
    optimization = json.loads(report.read_text())["optimization"]
    assert optimization["margin"] == margin and words in optimization["message"]
    k = 1 - margin
    assert optimization["parameters"]["base"]["final"] == pytest.approx(
        (0.8 - 0.2 * k) / (1 + k), abs=2e-3
    )
    # The design written stands when judged with its joints shrunk to 1 - margin (and, with the
    # reserve, with joints shrunk to 95% too: the check the boundary design fails).
    for kern, stands in [(0.95, True), (0.9, True)] if margin else [(0.95, False)]:
        assert main(["analyze", str(model), "--kern", str(kern), "-q", "--report",
                     str(report)]) == 0  # fmt: skip
        assert json.loads(report.read_text())["feasible"] is stands, kern


def test_values_outside_a_range_are_warned_about_once_each_and_never_clamped(stack, tmp_path,
                                                                             capsys):  # fmt: skip
    report = tmp_path / "r.json"
    code = main(["build", str(stack), "--optimize", "--free", "base", "--fix", "shift=0.9",
                 "--set", "base=0.8", "--quiet", "--report", str(report)])  # fmt: skip
    assert code == 0
    lines = capsys.readouterr().err.splitlines()
    assert lines == [
        "shapegen: warning: --set base=0.8 is outside its @Range [0, 0.6]: built as given (a"
        " range is a hint, as in CityEngine)",
        "shapegen: warning: --fix shift=0.9 is outside its @Range [0, 0.6]: built as given (a"
        " range is a hint, as in CityEngine)",
        "shapegen: warning: base = 0.8 is outside its @Range [0, 0.6]: the search starts from"
        " the nearest bound, 0.6",
    ]
    data = json.loads(report.read_text())
    assert data["attrs"]["shift"] == 0.9  # fixed: used as given
    assert data["optimization"]["parameters"]["base"]["initial"] == 0.6  # the search's start
