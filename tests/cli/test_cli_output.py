"""What ``build`` and ``analyze`` print: the files written, one line each; what a model holds,
counted by kind; why nothing can be judged; and output that a pipe gets unwrapped and uncut."""

from __future__ import annotations

import re

import pytest

from shapegen.cli import main
from shapegen.cli.display import judged_blocks_line

FACES_CGA = """\
version "2023.0"
@StartRule
Lot --> extrude(5) comp(f) { all : Wall }
Wall --> color("#cc8844")
"""

# a building only on a lot wider than 30 m: nothing on the default 10 x 10 m lot
WIDE_ONLY = """\
attr minimum_width = 30
@StartRule
Lot --> case scope.sx > minimum_width : extrude(3) i("box")
        else : NIL
"""


def test_build_names_each_file_it_wrote(tmp_path, capsys):
    model, report = tmp_path / "arch.glb", tmp_path / "arch.json"
    argv = ["build", "arch_columns", "-o", str(model), "--report", str(report)]
    assert main(argv) == 0
    lines = capsys.readouterr().out.splitlines()
    for path in (model, report):
        (line,) = [x for x in lines if x.startswith(f"wrote {path} (")]
        size = path.stat().st_size
        shown = re.fullmatch(rf"wrote {re.escape(str(path))} \((\S+) (bytes|kB|MB)\)", line)
        assert shown, line
        scale = {"bytes": 1, "kB": 1e3, "MB": 1e6}[shown[2]]
        assert float(shown[1]) * scale == pytest.approx(size, rel=5e-3)
    assert main([*argv, "-q"]) == 0 and capsys.readouterr().out == ""


def test_a_model_of_faces_says_what_it_holds_and_why_nothing_is_judged(tmp_path, capsys):
    rule = tmp_path / "faces.cga"
    rule.write_text(FACES_CGA, encoding="utf-8")
    assert main(["build", str(rule)]) == 0
    out = capsys.readouterr().out
    assert re.search(r"^blocks +0 *$", out, re.M)
    assert re.search(r"^surfaces +6 drawn, not solid: 6 a face \(no volume\) *$", out, re.M)
    assert "nothing to judge: the model holds 6 surfaces and no solid" in out


@pytest.mark.parametrize(
    ("extra", "where"),
    [
        ([], "the default lot of 10 x 10 m"),
        (["--lot", "20,12"], "the lot of 20 x 12 m given with --lot"),
    ],
)
def test_a_rule_that_makes_nothing_on_its_lot_says_so_and_how_to_try_another(
    tmp_path, capsys, extra, where
):
    rule = tmp_path / "wide.grammar"
    rule.write_text(WIDE_ONLY, encoding="utf-8")
    assert main(["build", str(rule), *extra]) == 0
    out = capsys.readouterr().out
    assert f"the rule made nothing on {where}" in out and "--lot WIDTH,DEPTH" in out
    assert main(["build", str(rule), "--lot", "40,40"]) == 0
    assert "made nothing" not in capsys.readouterr().out  # a wider lot has its building


def test_piped_output_is_not_wrapped_and_a_long_path_is_not_cut(tmp_path, capsys):
    folder = tmp_path / ("a_folder_with_a_long_name_" * 4)
    folder.mkdir()
    rule = folder / "a_rule_with_a_long_name_too.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) i("box")\n', encoding="utf-8")
    assert len(str(rule)) > 120
    assert main(["build", str(rule), "--analyze"]) == 0
    out = capsys.readouterr().out  # not a terminal: no width to wrap at
    assert "…" not in out
    assert re.search(rf"^grammar +{re.escape(str(rule))} *$", out, re.M)
    assert re.search(rf"^model +{re.escape(str(rule))} *$", out, re.M)


def test_the_search_line_is_one_line_when_piped(capsys):
    assert main(["build", "arch_columns", "--optimize", "--max-iter", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    (line,) = [x for x in lines if " iterations, " in x]
    assert re.fullmatch(r".*; SLSQP, 1 iterations, \d+ evaluations, \S+ s", line), line


def test_the_blocks_judged_agree_with_the_stand_ins():
    # the parthenon's figures on its default lot: 69 blocks of its own, 502 standing in
    analysis = {"blocks": 69, "stand_ins": {"leaves": 126, "blocks": 502}}
    assert judged_blocks_line(analysis) == "571: the model's 69 and 502 standing in for 126 leaves"
    assert judged_blocks_line({"blocks": 23}) == "23"
