"""``shapegen rules``: the bundled rule files and what each builds."""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run", "description"]

import argparse
import re
from pathlib import Path

HELP = "list the bundled rule files"
DESCRIPTION = (
    "List the bundled .grammar files with the first sentence of each one's opening comment."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""


def run(args: argparse.Namespace) -> int:
    from rich.table import Table
    from rich.text import Text

    from shapegen.cli import display
    from shapegen.engine.project.rules_path import bundled_rules, find_bundled_rule

    table = Table(box=None, show_header=True, header_style="bold", pad_edge=False)
    table.add_column("rule file", no_wrap=True)
    table.add_column("description")
    paths = [find_bundled_rule(name) for name in bundled_rules()]
    for path in paths:
        table.add_row(Text(path.name), Text(description(path)))
    console = display.console()
    if paths:
        console.print(table)
    else:
        console.print("no bundled rule files found")
    return 0


def description(path: Path) -> str:
    """The first sentence of the file's opening comment (``//``, ``#`` or ``/* */``), or ``""``;
    for a rule package (``.rpk``, an archive), its row in ``PACKAGES.md`` beside it."""
    if path.suffix.lower() == ".rpk":
        return _package_description(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError:
        return ""
    words: list[str] = []
    in_block = False
    for line in lines:
        stripped = line.strip()
        if not in_block and not words and (not stripped or stripped.startswith("version")):
            continue
        if stripped.startswith("/*"):
            in_block, stripped = True, stripped[2:]
        elif in_block or stripped.startswith(("//", "#")):
            stripped = stripped.lstrip("/#")
        else:
            break
        if "*/" in stripped:
            stripped, in_block = stripped.split("*/")[0], False
        if not stripped.strip():
            if words:
                break
            continue
        words.append(stripped.strip(" *"))
        text = " ".join(words)
        end = re.search(r"[.!?](\s|$)", text)
        if end:
            return text[: end.start() + 1]
        if not in_block and not line.strip().startswith(("//", "#")):
            break
    return " ".join(words)


def _package_description(package: Path) -> str:
    """The "what it builds" cell of the package's row in the ``PACKAGES.md`` table beside it
    (`` | `parthenon.rpk` | The Parthenon... | ... | ``), or ``""``."""
    try:
        lines = (package.parent / "PACKAGES.md").read_text(encoding="utf-8").splitlines()
    except OSError:
        return ""
    for line in lines:
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) >= 2 and cells[0] == f"`{package.name}`":
            return cells[1]
    return ""
