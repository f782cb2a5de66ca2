"""CityEngine rule packages (``.rpk``): a 7z archive of a rule's sources (``rules/*.cga``), the
files they import (``.ws/ESRI.lib/...``), its assets and its compiled rules (``.cgb``).

``load_grammar("building.rpk")`` and ``shapegen build building.rpk`` unpack the package once into
a cache folder (``$SHAPEGEN_CACHE``, else ``$XDG_CACHE_HOME/shapegen``, else
``~/.cache/shapegen``; one folder per package content) and load its start rule: the ``.cga``
whose compiled rule has no ``$`` in its name (``bin/candler.cgb`` -> ``rules/candler.cga``;
``envelope2002$facade.cgb`` is an import compiled for it). Imports and assets then resolve in
the unpacked package as in CityEngine. A package is unpacked as untrusted input
(:func:`shapegen.readers.archives.unpack_7z`): one whose members would land outside its folder,
that is too large, too deep or has too many members once unpacked, or that is not a whole 7z
archive is refused with one line naming it.
"""

from __future__ import annotations

__all__ = [
    "PACKAGE_SUFFIX",
    "RULES_PATH_VARIABLE",
    "RulesPath",
    "package_named",
    "start_rule_of_package",
]

import functools
import hashlib
import os
import re
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from shapegen.engine.project.rules_path import find_bundled_rule
from shapegen.errors import GrammarError
from shapegen.export.atomic import abandoned_entries, writer_name
from shapegen.readers.archives import package_cache, unpack_7z

PACKAGE_SUFFIX = ".rpk"


def _digest(path: Path) -> str:
    hasher = hashlib.sha256()
    with open(path, "rb") as handle:
        for chunk in iter(lambda: handle.read(1 << 20), b""):
            hasher.update(chunk)
    return hasher.hexdigest()[:20]


def _unpacked(package: Path) -> Path:
    """The folder the package is unpacked in (unpacked on first use, into a staging folder
    renamed into place once whole: a refused or interrupted package leaves nothing)."""
    try:
        folder = package_cache() / f"{package.stem}-{_digest(package)}"
    except OSError as exc:
        raise GrammarError(f"cannot read {str(package)!r}: {exc.strerror or exc}") from None
    if folder.is_dir():
        return folder
    try:
        folder.parent.mkdir(parents=True, exist_ok=True)
        _remove_abandoned_staging(folder.parent)
        staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".unpacking-{writer_name()}-"))
    except OSError as exc:
        raise GrammarError(
            f"{package}: cannot unpack it into {folder.parent}: {exc.strerror or exc} (set "
            "SHAPEGEN_CACHE to a writable folder)"
        ) from None
    try:
        unpack_7z(package, staging)
        os.replace(staging, folder)
    except OSError as exc:
        if folder.is_dir():  # another process unpacked it first
            return folder
        raise GrammarError(f"{package}: cannot unpack it: {exc.strerror or exc}") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return folder


_STAGING = re.compile(r"\.unpacking-(?P<host>[0-9a-f]{6})-(?P<pid>[0-9]+)-.+")


def _remove_abandoned_staging(cache: Path) -> None:
    """Remove the staging folders of unpackings whose process was killed (SIGKILL, a power
    cut: nothing of it ran to clean up), as :func:`~shapegen.export.atomic.remove_abandoned`
    does for files; another process's unpacking under way is left alone."""
    for entry in abandoned_entries(cache, _STAGING):
        shutil.rmtree(entry.path, ignore_errors=True)


def package_named(source: str) -> Path | None:
    """The rule package (``.rpk``) file ``source`` names (a path, or a bundled package's bare
    name such as ``parthenon.rpk``), resolved, or None when it names none (a rule file): the
    file the designer opened rather than its unpacked start rule."""
    path = Path(source)
    if path.suffix.lower() != PACKAGE_SUFFIX:
        return None
    if path.is_file():
        return path.resolve()
    if path.name == source:
        bundled = find_bundled_rule(source)
        if bundled is not None:
            return bundled.resolve()
    return None


def start_rule_of_package(package: Path) -> Path:
    """The start rule file of the rule package ``package``, unpacked."""
    folder = _unpacked(package)
    compiled = sorted(p.relative_to(folder) for p in folder.rglob("*.cgb") if "$" not in p.stem)
    candidates = []
    for rule in compiled:
        parts = rule.with_suffix(".cga").parts
        tail = parts[1:] if parts[0] in ("bin", "rules") else parts
        source = folder / "rules" / Path(*tail)
        if source.is_file():
            candidates.append(source)
    if len(candidates) == 1:
        return candidates[0]
    sources = sorted(str(p.relative_to(folder)) for p in folder.rglob("*.cga"))
    if not candidates and len(sources) == 1:
        return folder / sources[0]
    listing = ", ".join(sources) if sources else "none"
    raise GrammarError(
        f"{package}: cannot tell its start rule ({len(candidates)} compiled start rules; rule "
        f"files: {listing}); load one of them from {folder}"
    )


#: The environment variable that lists folders (or rule packages) to look imports up in, as
#: ``--rules-path`` does, separated by the platform's path separator (``:``, ``;`` on Windows).
RULES_PATH_VARIABLE = "SHAPEGEN_RULES_PATH"


@dataclass(frozen=True)
class RulesPath:
    """The folders imports are looked up in beyond a file's own project: the ``--rules-path``
    options given, then :data:`RULES_PATH_VARIABLE`'s entries; a rule package (``.rpk``) among
    them stands for its unpacked folder. Made (and its entries checked) once, at the edge: the
    command line makes it from its options, :func:`~shapegen.engine.grammar_api.load_grammar`
    from its ``rules_path`` argument; it is then passed down to the import resolution as it is.

    Raises
    ------
    GrammarError
        On construction (:meth:`of`), for an entry that is neither a folder nor a rule package.
    """

    folders: tuple[Path, ...] = ()

    @classmethod
    def of(cls, given=()) -> RulesPath:
        """``given`` (folders or packages, as ``--rules-path`` names them; a :class:`RulesPath`
        is taken as it is) then the variable's entries, the variable read now."""
        if isinstance(given, RulesPath):
            return given
        environment = os.environ.get(RULES_PATH_VARIABLE, "")
        return _checked_rules_path(tuple(str(e) for e in given), environment)

    def exported(self) -> str:
        """The folders as :data:`RULES_PATH_VARIABLE` lists them, for the processes this one
        starts (the city's workers, the page's scans)."""
        return os.pathsep.join(str(folder) for folder in self.folders)


@functools.lru_cache(maxsize=16)
def _checked_rules_path(given: tuple[str, ...], environment: str) -> RulesPath:
    """The entries checked once per process for one value of the options and the variable."""
    entries = [(e, "--rules-path") for e in given]
    entries += [(e, RULES_PATH_VARIABLE) for e in environment.split(os.pathsep) if e.strip()]
    folders = []
    for entry, origin in entries:
        path = Path(entry).expanduser()
        if path.is_dir():
            folders.append(path.resolve())
        elif path.is_file() and path.suffix.lower() == PACKAGE_SUFFIX:
            folders.append(_unpacked(path))
        else:
            raise GrammarError(
                f"{origin} {entry!r}: not a folder nor a rule package (.rpk) to look imports up in"
            )
    return RulesPath(tuple(dict.fromkeys(folders)))
