"""Where an imported rule file is: CityEngine's paths resolved on the file system.

Relative to the importing file's folder, then to its project (the nearest folder above holding
``rules/``); ``/Project/rest`` is the project itself when named so, else a project beside it in
the workspace, else ``.ws/Project/rest`` (an extracted ``.rpk``), or what the project's
``.resolvemap.xml`` maps the path to. Last come the folders the user names
(``search_folders``: ``--rules-path DIR``, ``SHAPEGEN_RULES_PATH``, made into one
:class:`~shapegen.engine.project.rule_packages.RulesPath` by the loader), each searched as a
workspace (``/ESRI.lib/rules/x.cga`` as ``DIR/ESRI.lib/rules/x.cga``) and as a project
(``DIR/rules/x.cga``).
"""

from __future__ import annotations

__all__ = ["import_candidates", "project_folder"]

import functools
import xml.etree.ElementTree as ElementTree
from collections.abc import Sequence
from pathlib import Path


def project_folder(folder: Path) -> Path | None:
    """The nearest folder at or above ``folder`` that holds a ``rules/`` folder, or None."""
    folder = folder.resolve()
    for parent in (folder, *folder.parents):
        if (parent / "rules").is_dir():
            return parent
    return None


@functools.lru_cache(maxsize=64)
def _resolve_map(project: Path) -> dict[str, str]:
    """``key -> value`` of a package's ``.resolvemap.xml`` (empty without one)."""
    try:
        root = ElementTree.parse(project / ".resolvemap.xml").getroot()
    except (OSError, ElementTree.ParseError):
        return {}
    return {
        entry.get("key", ""): entry.get("value", "")
        for entry in root.iter("entry")
        if entry.get("key")
    }


def import_candidates(path: str, folder: Path, search_folders: Sequence[Path] = ()) -> list[Path]:
    """Where ``import "path"`` written in a file of ``folder`` may be, in search order, the
    user's ``search_folders`` last."""
    project = project_folder(folder)
    found: list[Path] = []
    if project is not None:
        mapped = _resolve_map(project).get(path)
        if mapped:
            found.append(project / mapped)
    if path.startswith("/"):
        name, _, rest = path.lstrip("/").partition("/")
        if project is not None and rest:
            if name == project.name:
                found.append(project / rest)
            found += [project.parent / name / rest, project / ".ws" / name / rest]
            found.append(project / rest)  # a package keeps no project name
        elif rest:
            found.append(folder / rest)
    else:
        found.append(folder / path)
        if project is not None:  # relative to the project, and to its rules folder
            found += [project / path, project / "rules" / path]
    relative = path.lstrip("/")
    name, _, rest = relative.partition("/")
    for extra in search_folders:
        found.append(extra / relative)  # a workspace: /ESRI.lib/rules/x.cga
        if path.startswith("/") and rest:
            found.append(extra / rest)  # the project itself: /ESRI.lib/rules/x.cga
        else:
            found.append(extra / "rules" / relative)  # a project's rules/
    return list(dict.fromkeys(found))
