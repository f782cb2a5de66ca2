"""How the Inspector lays out a grammar's attrs: its sections, and the files a ``@File`` attr
may name.

What each attr's annotations say (its kind, ``@Range`` step and restriction, ``@Enum`` choices,
``@Group`` carried to the attrs after it, ``@Order``, ``@Hidden``, units) is read once, for
every front end, in the attribute catalogue (:mod:`shapegen.engine.attr_catalogue`); this
module turns those facts into the page's sections (:func:`inspector_sections`) and lists the
asset files (folders) next to the rule file and in its project's ``assets`` folder that a
``@File`` (``@Directory``) attr may name (:func:`asset_choices`), named as the rules name them.
As in CityEngine's Inspector: ``@Angle`` without a ``@Range`` has an unrestricted slider over
[0, 360], ``@Percent`` one over [0, 1] shown as 0 to 100 %, whose value is typed in percent;
the value in the rules and the API stays the real one (0.1 for 10 %). A boolean attr is a
check box.
"""

from __future__ import annotations

__all__ = ["asset_choices", "inspector_sections"]

import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from shapegen.engine.attr_catalogue import AttrEntry

#: The most asset files (or folders) offered for one ``@File`` attr: a project is browsed, not
#: a disk.
MAX_ASSET_CHOICES = 500
_MAX_ASSET_DEPTH = 6  # folders below the project's assets folder
_MAX_RULE_FOLDER_DEPTH = 2  # folders below the rule's own (it may lie in a large folder)
_MAX_VISITED = 20_000  # entries looked at per folder searched


def inspector_sections(catalogue: Mapping[str, AttrEntry]) -> list[dict]:
    """The Inspector's sections of a grammar's ``catalogue`` in the order shown: ``{"group":
    [names], "attrs": [attr names]}``, depth first, a group's own attrs before its subgroups;
    hidden attrs left out.

    Ungrouped attrs come first; groups are sorted by their order (a group without one after
    those with one, in the order first met), attrs within a group by ``@Order`` then file
    order. A group's order is the one its ``@Group`` gave, at its own (innermost) level.
    """
    position = {name: k for k, name in enumerate(catalogue)}
    tree: dict = {"attrs": [], "groups": {}, "order": None, "seen": -1}
    for name, entry in catalogue.items():
        if entry.hidden:
            continue
        branch = tree
        for depth, level in enumerate(entry.group):
            child = branch["groups"].get(level)
            if child is None:
                child = {"attrs": [], "groups": {}, "order": None, "seen": position[name]}
                branch["groups"][level] = child
            if depth == len(entry.group) - 1 and child["order"] is None:
                child["order"] = entry.group_order
            branch = child
        branch["attrs"].append(name)

    def by_order(order: float | None, seen: int) -> tuple:
        return (order is None, order if order is not None else 0.0, seen)

    sections: list[dict] = []

    def visit(branch: dict, path: tuple[str, ...]) -> None:
        attrs = sorted(branch["attrs"], key=lambda n: by_order(catalogue[n].order, position[n]))
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
