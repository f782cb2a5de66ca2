"""What the page exports besides the model: the design as a ``shapegen build`` command line and
its attrs as JSON, so that a design found on the page can be built again from the shell.

>>> command_line(Path("vault.grammar"), {"angle": 60.0, "stone": "granite"})
'shapegen build vault.grammar --set angle=60 --set stone=granite'
"""

from __future__ import annotations

__all__ = ["command_line", "set_argument"]

import math
import shlex
from collections.abc import Mapping, Sequence
from pathlib import Path

from shapegen.engine.project.rules_path import find_bundled_rule
from shapegen.model.lot import Lot


def set_argument(name: str, value: object) -> str:
    """``NAME=VALUE`` as ``--set`` reads it back to ``value``: a number in its shortest exact
    form, ``true``/``false``, a string quoted when it would read as a number or a boolean."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, int | float):
        number = float(value)
        text = str(int(number)) if number.is_integer() and abs(number) < 2**53 else repr(number)
    else:
        text = str(value)
        if _reads_as_other(text):
            text = f'"{text}"'  # --set strips one pair of quotes and keeps the rest a string
    return f"{name}={text}"


def _reads_as_other(text: str) -> bool:
    if text.lower() in ("true", "false") or (len(text) >= 2 and text[0] == text[-1] in "\"'"):
        return True
    try:
        float(text)
    except ValueError:
        return False
    return True


def command_line(
    path: Path | None,
    values: Mapping[str, object],
    *,
    seed: int = 0,
    lot: Lot | None = None,
    rules_path: Sequence[str] = (),
) -> str:
    """The ``shapegen build`` line that builds the design: the rule file (a bundled rule by its
    name, a file under the working folder relative to it), ``--rules-path`` for each folder
    of ``rules_path`` (where the imports were found), ``--seed`` and ``--lot`` when not the
    defaults, and one ``--set`` per value in ``values`` (the designer's, in their order)."""
    words = ["shapegen", "build", _rule_argument(path)]
    for folder in rules_path:
        words += ["--rules-path", _path_argument(Path(folder))]
    if seed:
        words += ["--seed", str(seed)]
    if lot is not None:
        words += ["--lot", _lot_argument(lot)]
    for name, value in values.items():
        words += ["--set", set_argument(name, value)]
    return " ".join(shlex.quote(word) for word in words)


def _rule_argument(path: Path | None) -> str:
    if path is None:
        return "FILE.grammar"
    bundled = find_bundled_rule(path.name)
    # resolved both: in a source checkout the bundled rules' folder is a link to rules/
    if bundled is not None and bundled.resolve() == path.resolve():
        return path.name
    return _path_argument(path)


def _path_argument(path: Path) -> str:
    """``path`` relative to the working folder when under it, else absolute."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:  # not under the working folder
        return str(path.resolve())


def _lot_argument(lot: Lot) -> str:
    def metres(value: float) -> str:
        value = float(value)
        return str(int(value)) if value.is_integer() and math.isfinite(value) else repr(value)

    if lot.size is not None:
        return f"{metres(lot.size[0])},{metres(lot.size[1])}"
    rings = [lot.corners, *lot.holes]  # "x,z x,z ... | x,z ...": the holes after a "|"
    return " | ".join(" ".join(f"{metres(x)},{metres(z)}" for x, z in ring) for ring in rings)
