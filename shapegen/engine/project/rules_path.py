"""Where the bundled rule files live, and how a bare file name finds them.

The bundled ``.grammar`` files are in the top-level ``rules/`` directory of the source tree;
``shapegen/rules`` is a link to it, so that a wheel carries them as package data
(``pyproject.toml`` lists ``rules/*.grammar``) and an installed package finds them inside itself.
The top-level directory is searched too, for a source checkout whose link was not kept.
"""

from __future__ import annotations

__all__ = ["bundled_rules", "bundled_rules_dirs", "find_bundled_rule"]

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent.parent


def bundled_rules_dirs() -> list[Path]:
    """The existing directories that hold bundled rule files, searched in this order."""
    candidates = [_PACKAGE / "rules", _PACKAGE.parent / "rules"]
    return [path for path in candidates if path.is_dir()]


def bundled_rules() -> list[str]:
    """File names of the bundled ``.grammar`` files, sorted (first directory wins on a clash)."""
    names: set[str] = set()
    for directory in bundled_rules_dirs():
        names.update(path.name for path in directory.glob("*.grammar") if path.is_file())
    return sorted(names)


def find_bundled_rule(name: str) -> Path | None:
    """The bundled file called ``name`` (``.grammar`` added if missing), or None."""
    if not name.endswith(".grammar"):
        name += ".grammar"
    for directory in bundled_rules_dirs():
        path = directory / name
        if path.is_file():
            return path
    return None
