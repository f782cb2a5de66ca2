"""Numbers past a float's range found by hand at the doors: each is one line, never a NaN that
reaches a verdict."""

from __future__ import annotations

import json

import pytest

from shapegen.cli import main
from shapegen.export.model_io import write_model
from shapegen.model import Block, Model


@pytest.mark.parametrize("density", ["1e308", "1e200", "1000001"])
def test_a_density_past_the_densest_is_refused_not_judged(tmp_path, capsys, density):
    # 1e308 kg/m^3 x 300 m^3 x 9.81 is inf: the verdict was "does not stand", silently; 1e200
    # made the tension measure (N^2) overflow in a traceback
    rule = tmp_path / "heavy.grammar"
    rule.write_text(
        f'@StartRule\nLot --> extrude(3) set(density, {density}) i("box")\n', encoding="utf-8"
    )
    report = tmp_path / "r.json"
    assert main(["build", str(rule), "--lot", "12,8", "--analyze", "--report", str(report)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert "attr 'density' must be a number in [0, 1e+06] (kg/m^3)" in err[0]
    assert not report.exists()


def test_the_densest_block_is_judged(tmp_path, capsys):
    rule = tmp_path / "heavy.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) set(density, 1e6) i("box")\n')
    report = tmp_path / "r.json"
    assert main(["build", str(rule), "--lot", "12,8", "--analyze", "--report", str(report)]) == 0
    analysis = json.loads(report.read_text())["analysis"]
    assert analysis["stands"] is True
    assert analysis["total_weight"] == pytest.approx(1e6 * 288 * 9.81, rel=1e-9)


def test_a_model_file_block_past_the_densest_is_one_line(tmp_path, capsys):
    model = tmp_path / "m.json"
    write_model(Model([Block.box((0, 0, 0), (1, 1, 1))]), model)
    document = json.loads(model.read_text())
    document["blocks"][0]["density"] = 1e300
    model.write_text(json.dumps(document))
    assert main(["analyze", str(model)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "density must be a number in [0, 1e+06] kg/m^3" in err[0]
