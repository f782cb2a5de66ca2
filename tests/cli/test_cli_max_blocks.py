"""``shapegen analyze --max-blocks N``: models over the default block limit are read when asked."""

from __future__ import annotations

import json

import pytest

from shapegen import Block, Model
from shapegen.cli import main
from shapegen.export.blocks_json import model_to_dict


def _tower(path, count: int):
    model = Model([Block.box([0, k, 0], [1, k + 1, 1], id=f"b{k}") for k in range(count)])
    document = model_to_dict(model)
    for entry in document["blocks"]:  # vertices only, as other programs write them
        del entry["faces"]
    path.write_text(json.dumps(document))
    return path


def test_a_model_over_the_limit_is_read_with_max_blocks(tmp_path, capsys):
    model = _tower(tmp_path / "tower.json", 3)
    report = tmp_path / "report.json"
    assert main(["analyze", str(model), "--max-blocks", "3", "--report", str(report), "-q"]) == 0
    assert json.loads(report.read_text())["blocks"] == 3
    assert json.loads(report.read_text())["feasible"] is True


def test_a_model_over_the_given_limit_is_refused_in_one_line(tmp_path, capsys):
    model = _tower(tmp_path / "tower.json", 3)
    assert main(["analyze", str(model), "--max-blocks", "2"]) == 2
    error = capsys.readouterr().err.strip()
    assert "3 blocks, more than 2" in error and "\n" not in error
    # the way to raise it is the command's own option, not a library call
    assert "raise it with --max-blocks N" in error and "work_limits" not in error


def test_any_file_of_as_many_blocks_as_allowed_is_read_at_the_default(tmp_path, capsys):
    from shapegen.cli.analyze import BYTES_PER_BLOCK
    from shapegen.limits import work_limits

    model = _tower(tmp_path / "tower.json", 3)
    size = model.stat().st_size
    # a file-size limit under this small file: the block limit allows BYTES_PER_BLOCK a block
    with work_limits(max_blocks=5, max_file_bytes=size // 2):
        assert main(["analyze", str(model), "-q"]) == 0
        # padded past 5 x BYTES_PER_BLOCK, it is refused with the option that raises it
        model.write_text(model.read_text() + " " * (5 * BYTES_PER_BLOCK))
        assert main(["analyze", str(model)]) == 2
    error = capsys.readouterr().err.strip()
    assert f"bytes, more than {5 * BYTES_PER_BLOCK}" in error, error
    assert "--max-blocks N" in error and "\n" not in error


@pytest.mark.parametrize("value", ["0", "-5", "many", "2.5"])
def test_max_blocks_must_be_a_whole_number(tmp_path, capsys, value):
    model = _tower(tmp_path / "tower.json", 1)
    assert main(["analyze", str(model), "--max-blocks", value]) == 2
    assert "--max-blocks: must be a whole number >= 1" in capsys.readouterr().err
