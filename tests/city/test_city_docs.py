"""docs/city.md's Python example runs and prints what the page says."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "city.md"


def test_the_python_example_prints_what_the_page_says(tmp_path, monkeypatch):
    (block,) = re.findall(r"```python\n(.*?)```", PAGE.read_text(encoding="utf-8"), re.S)
    expected = [line[2:] for line in block.splitlines() if line.startswith("# [")]
    monkeypatch.chdir(tmp_path)  # the example writes city-out/ here and reads docs/ through:
    (tmp_path / "docs").symlink_to(REPO / "docs")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(block, str(PAGE), "exec"), {})
    lines = printed.getvalue().splitlines()
    assert lines[0] == expected[0]
    assert lines[1].startswith("30 lonlat (")
    assert (tmp_path / "city-out" / "results.csv").is_file()
