"""Where the bundled rule files live, and how a bare file name finds them.

The bundled rules are in the top-level ``rules/`` directory of the source tree: ``.grammar``
files, and CityEngine rule packages (``.rpk``) that the README's tour uses, each listed with
its source and licence in ``rules/PACKAGES.md``. ``shapegen/rules`` is a link to that directory,
so that a wheel carries them as package data (``pyproject.toml`` lists ``rules/*.grammar``,
``rules/*.rpk`` and the notices) and an installed package finds them inside itself. The
top-level directory is searched too, for a source checkout whose link was not kept.
"""

from __future__ import annotations

__all__ = ["BUNDLED_SUFFIXES", "bundled_rules", "bundled_rules_dirs", "find_bundled_rule"]

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent.parent

#: The kinds of bundled rule file, in the order a name without a suffix tries them.
BUNDLED_SUFFIXES = (".grammar", ".rpk")


def bundled_rules_dirs() -> list[Path]:
    """The existing directories that hold bundled rule files, searched in this order."""
    candidates = [_PACKAGE / "rules", _PACKAGE.parent / "rules"]
    return [path for path in candidates if path.is_dir()]


def bundled_rules() -> list[str]:
    """File names of the bundled rule files (``.grammar`` and ``.rpk``), sorted (first
    directory wins on a clash)."""
    names: set[str] = set()
    for directory in bundled_rules_dirs():
        for suffix in BUNDLED_SUFFIXES:
            names.update(path.name for path in directory.glob(f"*{suffix}") if path.is_file())
    return sorted(names)


def find_bundled_rule(name: str) -> Path | None:
    """The bundled file called ``name``, or None; a name without one of
    :data:`BUNDLED_SUFFIXES` tries ``.grammar``, then ``.rpk``
    (``cluny`` is ``cluny.grammar``, ``parthenon`` is ``parthenon.rpk``)."""
    if name.endswith(BUNDLED_SUFFIXES):
        names = [name]
    else:
        names = [name + suffix for suffix in BUNDLED_SUFFIXES]
    for candidate in names:
        for directory in bundled_rules_dirs():
            path = directory / candidate
            if path.is_file():
                return path
    return None
