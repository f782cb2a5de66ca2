"""The Python example in docs/statics.md runs and prints what its comments say."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "docs" / "statics.md"


def test_the_friction_example_prints_what_the_page_says():
    blocks = re.findall(r"```python\n(.*?)```", DOC.read_text(), re.DOTALL)
    assert blocks, "docs/statics.md has no Python example"
    for code in blocks:
        # the expected output: comment lines "# <printed line>   <explanation>" at the end
        expected = [
            re.split(r"\s{2,}", line[2:])[0]
            for line in code.splitlines()
            if re.match(r"# \d", line)
        ]
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(code, str(DOC), "exec"), {"__name__": "docs_example"})
        assert printed.getvalue().splitlines() == expected
