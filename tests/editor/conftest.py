"""Shared fixtures of the editor tests (the grammar is in editor_stack.py)."""

import pytest
from editor_stack import STACK


@pytest.fixture
def stack_file(tmp_path):
    path = tmp_path / "stack.grammar"
    path.write_text(STACK, encoding="utf-8")
    return path
