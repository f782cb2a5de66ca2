"""docs/primitives.md documents every built-in primitive, each of its parameters, and shows
pictures that exist."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from shapegen.primitives import get

DOC = Path(__file__).resolve().parents[2] / "docs" / "primitives.md"
BUILT_IN = [
    "box", "wall", "column", "arch", "bezier_arch", "capped_arch", "flying_buttress",
    "barrel_vault", "groin_vault", "dome",
]  # fmt: skip


def sections() -> dict[str, str]:
    text = DOC.read_text(encoding="utf-8")
    parts = re.split(r"^## (\S+)\s*$", text, flags=re.MULTILINE)
    return dict(zip(parts[1::2], parts[2::2], strict=True))


@pytest.mark.parametrize("name", BUILT_IN)
def test_every_parameter_is_documented(name):
    section = sections().get(name)
    assert section is not None, f"docs/primitives.md has no section '## {name}'"
    for parameter in get(name).parameters:
        assert f"`{parameter}`" in section, f"{name}: parameter {parameter!r} is not documented"
    assert f"images/primitives/{name}" in section


def test_every_picture_exists():
    text = DOC.read_text(encoding="utf-8")
    pictures = re.findall(r"\]\((images/primitives/[^)]+\.png)\)", text)
    assert len(pictures) >= len(BUILT_IN)
    for picture in pictures:
        assert (DOC.parent / picture).is_file(), picture
