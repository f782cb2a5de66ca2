"""How the Inspector shows each attr: CityEngine's annotations (the cga_annotations reference).

- ``@Range(min, max, stepsize=, restricted=)``: a slider stepping by ``stepsize`` (when > 0,
  from ``min``); ``restricted=false`` lets a typed number lie outside the range (a ``@Free``
  attr's range is the search's bounds, so it stays restricted). ``@Range("a", "b")`` of
  strings (CityEngine's older form) is a drop-down of those strings.
- ``@Enum(v1, v2, ..., restricted=)`` or ``@Enum(valuesAttr=name)``: a drop-down of the values
  (numbers or strings; ``valuesAttr`` names an array attr, read at its current value);
  ``restricted`` (the default) refuses any other value.
- ``@Hidden``: not shown (the API still lists it and takes values for it).
- ``@Group("level 1", ..., "level n", order)``: the Inspector's sections. As CityEngine's, it
  sets the group of this attr *and the ones after it* in its file until the next ``@Group``
  (a ``@Group`` without names leaves the group); ``order`` sorts the groups. The attrs of an
  import (``lib.height``) are in a section of the import (``lib``), their groups within it.
  ``@Order(n)`` sorts the attrs within their group; without one an attr comes after those
  with one, in file order.
- ``@Description``: the help text (a tooltip); ``@DisplayName``: the name shown.
- ``@Color``: a colour picker for a string attr ``"#rrggbb"``.
- ``@File`` / ``@File("ext", ...)`` / ``@Directory``: a choice among the files (or folders)
  next to the rule file and in its project's ``assets`` folder, named as the rules name them.
- ``@Angle``, ``@Percent``, ``@Distance`` on a number: its unit in the Inspector (degrees,
  percent, metres: shapegen's models are in metres). ``@Angle`` without a ``@Range`` has an
  unrestricted slider over [0, 360], ``@Percent`` one over [0, 1] shown as 0 to 100 %, whose
  value is typed in percent (CityEngine's Inspector does the same); the value in the rules and
  the API stays the real one (0.1 for 10 %).
- a boolean attr: a check box.

Annotation arguments are constants, folded with
:func:`~shapegen.grammar.constant_folding.constant_value`; one that cannot be folded is
ignored, as CityEngine's Inspector ignores what it cannot read.
"""

from __future__ import annotations

__all__ = [
    "UNIT_RANGES",
    "AttrHints",
    "asset_choices",
    "attr_hints",
    "inspector_sections",
]

import os
import weakref
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from shapegen.grammar import ast
from shapegen.grammar.constant_folding import UNKNOWN, constant_value, is_number

_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: The most asset files (or folders) offered for one ``@File`` attr: a project is browsed, not
#: a disk.
MAX_ASSET_CHOICES = 500
_MAX_ASSET_DEPTH = 6  # folders below the project's assets folder
_MAX_RULE_FOLDER_DEPTH = 2  # folders below the rule's own (it may lie in a large folder)
_MAX_VISITED = 20_000  # entries looked at per folder searched
#: The unit annotations CityEngine's Inspector honours, by the unit they give a number.
UNITS = {"Angle": "angle", "Percent": "percent", "Distance": "distance"}
#: The slider's range of a unit without a ``@Range`` (unrestricted: any value may be typed).
UNIT_RANGES = {"angle": (0.0, 360.0), "percent": (0.0, 1.0)}


@dataclass(frozen=True)
class AttrHints:
    """What the annotations of one attr ask of the Inspector.

    ``kind`` is ``number``, ``bool``, ``string``, ``color`` (``@Color``), ``file``
    (``@File``, ``@MaterialFile``), ``directory`` (``@Directory``) or ``array`` (shown, not
    edited). ``step`` is the ``@Range`` stepsize (None without one); ``choices`` the values
    of an ``@Enum`` or a ``@Range`` of strings (None without), ``values_attr`` the attr an
    ``@Enum(valuesAttr=...)`` reads them from; ``group`` the section's names, outermost first;
    ``unit`` that of ``@Angle``, ``@Percent`` or ``@Distance`` (``angle``, ``percent``,
    ``distance``; None without).
    """

    kind: str
    step: float | None = None
    restricted: bool = True
    choices: tuple | None = None
    values_attr: str | None = None
    extensions: tuple[str, ...] = ()
    group: tuple[str, ...] = ()
    group_order: float | None = None
    order: float | None = None
    description: str = ""
    display_name: str = ""
    hidden: bool = False
    unit: str | None = None


def attr_hints(grammar) -> dict[str, AttrHints]:
    """``name -> AttrHints`` for every attr of ``grammar`` (a loaded
    :class:`~shapegen.engine.grammar_api.Grammar`), in file order; computed once per grammar."""
    known = _CACHE.get(grammar)
    if known is None:
        known = _CACHE[grammar] = _attr_hints(grammar)
    return known


def _attr_hints(grammar) -> dict[str, AttrHints]:
    nodes: Mapping[str, ast.Attribute] = grammar.program.attr_nodes
    definitions = {**{c.name: c for c in grammar.ast.consts}, **nodes}
    defaults = grammar.attrs
    hints = {}
    group: tuple[str, ...] = ()
    group_order: float | None = None
    file: tuple[str, ...] = ()
    for name, node in nodes.items():
        fold = _Folder(definitions)
        # an imported attr (lib.height) shows in a section of its import, as in CityEngine's
        # Inspector; a @Group holds within its own file
        prefix = tuple(name.split(".")[:-1])
        if prefix != file:
            file, group, group_order = prefix, (), None
        annotation = node.annotation("Group")
        if annotation is not None:  # CityEngine's: the group of this attr and the next ones
            group, group_order = fold.group(annotation)
        hints[name] = AttrHints(
            kind=_kind(defaults[name], node),
            **fold.choices(node),
            group=prefix + group,
            group_order=group_order if group else None,
            order=fold.number(node.annotation("Order"), 0),
            description=fold.text(node.annotation("Description")),
            display_name=fold.text(node.annotation("DisplayName")),
            hidden=node.has_annotation("Hidden"),
            unit=_unit(defaults[name], node),
        )
    return hints


def _kind(default: object, node: ast.Attribute) -> str:
    if isinstance(default, bool):
        return "bool"
    if isinstance(default, int | float):
        return "number"
    if not isinstance(default, str):
        return "array"
    if node.has_annotation("Color"):
        return "color"
    if node.has_annotation("File") or node.has_annotation("MaterialFile"):
        return "file"
    if node.has_annotation("Directory"):
        return "directory"
    return "string"


def _unit(default: object, node: ast.Attribute) -> str | None:
    if isinstance(default, bool) or not isinstance(default, int | float):
        return None  # CityEngine's units are for numbers (of an array too: shown, not edited)
    return next((unit for name, unit in UNITS.items() if node.has_annotation(name)), None)


class _Folder:
    """Folds annotation arguments to constants (:data:`UNKNOWN` when they are not)."""

    def __init__(self, definitions: Mapping[str, object]):
        self.definitions = definitions

    def value(self, expression: ast.Expression | None):
        if expression is None:
            return UNKNOWN
        return constant_value(expression, dict(self.definitions))

    def number(self, annotation: ast.Annotation | None, position: int) -> float | None:
        if annotation is None or position >= len(annotation.args):
            return None
        value = self.value(annotation.args[position])
        return float(value) if is_number(value) else None

    def text(self, annotation: ast.Annotation | None) -> str:
        if annotation is None or not annotation.args:
            return ""
        value = self.value(annotation.args[0])
        return value if isinstance(value, str) else ""

    def flag(self, annotation: ast.Annotation, keyword: str, default: bool) -> bool:
        for given in annotation.keywords:
            if given.name == keyword:
                value = self.value(given.value)
                return value if isinstance(value, bool) else default
        return default

    def group(self, annotation: ast.Annotation) -> tuple[tuple[str, ...], float | None]:
        names, order = [], None
        for argument in annotation.args:
            value = self.value(argument)
            if isinstance(value, str):
                names.append(value)
            elif is_number(value):
                order = float(value)  # the last argument: the group's place among groups
        return tuple(names), order if names else None

    def choices(self, node: ast.Attribute) -> dict:
        """``step``, ``restricted``, ``choices``, ``values_attr``, ``extensions``."""
        found: dict = {}
        enum = node.annotation("Enum")
        ranged = node.annotation("Range")
        files = node.annotation("File")
        if ranged is not None:
            found["restricted"] = self.flag(ranged, "restricted", True)
            step = self.value(ranged.argument("stepsize", 2))
            if is_number(step) and step > 0:
                found["step"] = float(step)
            values = [self.value(a) for a in ranged.args]
            if values and all(isinstance(v, str) for v in values):
                found["choices"] = tuple(values)  # CityEngine's older @Range("a", "b")
        if enum is not None:
            found["restricted"] = self.flag(enum, "restricted", True)
            source = next((k.value for k in enum.keywords if k.name == "valuesAttr"), None)
            if isinstance(source, ast.Name):
                found["values_attr"] = source.name
            else:
                values = [self.value(a) for a in enum.args]
                values = [float(v) if is_number(v) else v for v in values]
                found["choices"] = tuple(v for v in values if isinstance(v, str) or is_number(v))
        if files is not None:
            extensions = [self.value(a) for a in files.args]
            found["extensions"] = tuple(
                e.lower().lstrip(".") for e in extensions if isinstance(e, str) and e
            )
        return found


def inspector_sections(hints: Mapping[str, AttrHints]) -> list[dict]:
    """The Inspector's sections in the order shown: ``{"group": [names], "attrs": [attr
    names]}``, depth first, a group's own attrs before its subgroups; hidden attrs left out.

    Ungrouped attrs come first; groups are sorted by their order (a group without one after
    those with one, in the order first met), attrs within a group by ``@Order`` then file
    order. A group's order is the one its ``@Group`` gave, at its own (innermost) level.
    """
    position = {name: k for k, name in enumerate(hints)}
    tree: dict = {"attrs": [], "groups": {}, "order": None, "seen": -1}
    for name, hint in hints.items():
        if hint.hidden:
            continue
        branch = tree
        for depth, level in enumerate(hint.group):
            child = branch["groups"].get(level)
            if child is None:
                child = {"attrs": [], "groups": {}, "order": None, "seen": position[name]}
                branch["groups"][level] = child
            if depth == len(hint.group) - 1 and child["order"] is None:
                child["order"] = hint.group_order
            branch = child
        branch["attrs"].append(name)

    def by_order(order: float | None, seen: int) -> tuple:
        return (order is None, order if order is not None else 0.0, seen)

    sections: list[dict] = []

    def visit(branch: dict, path: tuple[str, ...]) -> None:
        attrs = sorted(branch["attrs"], key=lambda n: by_order(hints[n].order, position[n]))
        if attrs:
            sections.append({"group": list(path), "attrs": attrs})
        groups = sorted(
            branch["groups"].items(), key=lambda item: by_order(item[1]["order"], item[1]["seen"])
        )
        for level, child in groups:
            visit(child, (*path, level))

    visit(tree, ())
    return sections


def asset_choices(
    rule_file: Path | None, extensions: Iterable[str] = (), *, directories: bool = False
) -> list[str]:
    """The files (or, with ``directories``, the folders) a ``@File`` (``@Directory``) attr of
    ``rule_file`` may name, as the rules name them: relative to the rule's folder for those
    next to it, to the project's ``assets`` folder for those there (the asset search looks in
    both: :mod:`shapegen.engine.project.asset_files`). ``extensions`` (without dots, any case) keep
    only files of those types. Sorted; at most :data:`MAX_ASSET_CHOICES`.
    """
    if rule_file is None:
        return []
    wanted = {e.lower().lstrip(".") for e in extensions}
    folder = Path(rule_file).resolve().parent
    roots = [(folder, _MAX_RULE_FOLDER_DEPTH)]
    for parent in (folder, *folder.parents):
        if (parent / "rules").is_dir() or (parent / "assets").is_dir():
            if (parent / "assets").is_dir():
                roots.append((parent / "assets", _MAX_ASSET_DEPTH))
            break
    found: dict[str, None] = {}
    for root, depth in roots:
        for path in _walk(root, directories, depth):
            if len(found) >= MAX_ASSET_CHOICES:
                break
            if not directories and wanted and path.suffix.lower().lstrip(".") not in wanted:
                continue
            if not directories and path.suffix.lower() in (".cga", ".cgb", ".grammar"):
                continue  # the rules themselves are no assets
            found[path.relative_to(root).as_posix()] = None
    return sorted(found)


def _walk(root: Path, directories: bool, depth: int) -> Iterable[Path]:
    """Files (or folders) below ``root`` down to ``depth`` folders, hidden ones left out, and
    at most :data:`_MAX_VISITED` entries looked at."""
    base_depth = len(root.parts)
    visited = 0
    for current, folders, files in os.walk(root):
        here = Path(current)
        visited += len(folders) + len(files)
        if visited > _MAX_VISITED:
            return
        deeper = len(here.parts) - base_depth < depth
        folders[:] = sorted(f for f in folders if not f.startswith(".")) if deeper else []
        if directories:
            yield from (here / f for f in folders)
        else:
            yield from (here / f for f in sorted(files) if not f.startswith("."))
