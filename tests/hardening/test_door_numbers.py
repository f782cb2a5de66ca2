"""Numbers past a float's range found by hand at the doors: each is one line, never a NaN that
reaches a verdict."""

from __future__ import annotations

import pytest

from shapegen.cli import main


@pytest.mark.parametrize("density", ["1e308", "1e306"])
def test_a_weight_past_a_floats_range_is_refused_not_judged(tmp_path, capsys, density):
    # 1e308 kg/m^3 x 300 m^3 x 9.81 is inf: the verdict was "does not stand", silently
    rule = tmp_path / "heavy.grammar"
    rule.write_text(
        f'@StartRule\nLot --> extrude(3) set(density, {density}) i("box")\n', encoding="utf-8"
    )
    report = tmp_path / "r.json"
    assert main(["build", str(rule), "--lot", "12,8", "--analyze", "--report", str(report)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "block 'b0': its weight" in err[0] and "not a finite number" in err[0]
    assert not report.exists()


def test_a_heavy_but_finite_block_is_judged(tmp_path, capsys):
    rule = tmp_path / "heavy.grammar"
    rule.write_text('@StartRule\nLot --> extrude(3) set(density, 1e200) i("box")\n')
    assert main(["build", str(rule), "--lot", "12,8", "--analyze"]) == 0
    out = capsys.readouterr().out
    assert "stands         yes" in out
