"""Where CityEngine's asset search finds a file named in a rule (cga_assetSearch): next to the
rule file, then in each folder above it that holds a ``rules`` or ``assets`` folder (the project
of an extracted rule package), as ``<project>/PATH`` and ``<project>/assets/PATH``; CityEngine's
project-absolute ``/Project/assets/x.obj`` works too. Used by ``i()``, ``assetInfo()`` and the
table readers.

Asset files are read into a :class:`~shapegen.geometry.mesh.Mesh` in their own coordinates (y
up): OBJ by shapegen's reader (polygons kept whole), FBX with ufbx (faces whole, in metres;
an optional dependency), glTF, COLLADA, PLY and STL with trimesh,
and cleaned as CityEngine's runtime cleans an asset (:mod:`shapegen.geometry.asset_cleanup`:
its vertices kept as listed, edges and faces of no extent removed, unused vertices dropped);
a file is read once and kept while it is unchanged."""

from __future__ import annotations

__all__ = ["assets_held", "find_asset", "load_asset"]

import contextlib
import contextvars
import functools
import os
import re
from collections import OrderedDict
from pathlib import Path

import numpy as np

from shapegen.errors import GeometryError, InputFormatError
from shapegen.geometry.asset_cleanup import cleaned_polygons
from shapegen.geometry.mesh import Mesh
from shapegen.limits import current_limits, limit_hint
from shapegen.readers.archives import package_cache, unpacked_package
from shapegen.readers.fbx import fbx_polygons
from shapegen.readers.obj import obj_polygons

_CACHE_SIZE = 64
_cache: OrderedDict[tuple, Mesh] = OrderedDict()

# Within one derivation (:func:`assets_held`): what each name was found to be and each file read
# as, so that the 500 i() of a building look at the disk once per name, not once per shape.
_held: contextvars.ContextVar[dict | None] = contextvars.ContextVar("assets_held", default=None)


@contextlib.contextmanager
def assets_held():
    """Within: each asset name is looked up and each asset file read (or its change checked)
    once. A derivation holds them so, as CityEngine reads a rule package's assets once per
    generation; a file changed during one derivation is seen by the next."""
    token = _held.set({})
    try:
        yield
    finally:
        _held.reset(token)


def _search_roots(rule_file: str | None) -> tuple[Path, ...]:
    if not rule_file or rule_file.startswith("<"):
        return (Path.cwd(),)
    return _project_roots(rule_file, os.getcwd())


@functools.lru_cache(maxsize=64)
def _project_roots(rule_file: str, working_folder: str) -> tuple[Path, ...]:
    """The folders searched for a rule file's assets, worked out once per rule file (an
    ``i()`` in a repeat asks for them at every shape: resolving the path and looking for
    ``rules`` and ``assets`` folders up to the root took 0.1 ms each time)."""
    folder = Path(working_folder, rule_file).resolve().parent
    roots = [folder]
    for parent in [folder, *folder.parents]:
        if (parent / "rules").is_dir() or (parent / "assets").is_dir():
            roots += [parent, parent / "assets"]
    return tuple(dict.fromkeys(roots))


def find_asset(name: str, rule_file: str | None) -> Path | None:
    """The file ``name`` names for a rule written in ``rule_file``, or None."""
    held = _held.get()
    if held is None:
        return _found(name, rule_file)
    key = ("find", name, rule_file)
    if key not in held:
        held[key] = _found(name, rule_file)
    return held[key]


def _found(name: str, rule_file: str | None) -> Path | None:
    working_folder = os.getcwd()
    package = None
    if rule_file and not rule_file.startswith("<"):
        package = _package_of(rule_file, working_folder, str(package_cache()))
    for path in _candidates(name, rule_file, working_folder):
        if path.is_file() and (package is None or _inside(path, package)):
            return path
    return None


def _inside(path: Path, package: Path) -> bool:
    """:func:`~shapegen.readers.archives.within` for a package folder already resolved: the
    asset's path resolved (links followed) at every look, the folder's once per rule file."""
    try:
        return path.resolve().is_relative_to(package)
    except (OSError, RuntimeError):
        return False


@functools.lru_cache(maxsize=64)
def _package_of(rule_file: str, working_folder: str, cache: str) -> Path | None:
    """The unpacked package that holds ``rule_file``, worked out once per rule file (an
    ``i()`` in a repeat asks at every shape; resolving both paths took 0.3 ms each time)."""
    package = unpacked_package(Path(working_folder, rule_file))
    return None if package is None else package.resolve()


@functools.lru_cache(maxsize=1024)
def _candidates(name: str, rule_file: str | None, working_folder: str) -> tuple[Path, ...]:
    """The paths ``name`` may be, in search order (the files themselves are looked for at
    each call: they may come and go)."""
    relative = name.lstrip("/\\")
    candidates = [relative]
    if name.startswith("/"):  # CityEngine's project-absolute /Project/assets/x.obj
        candidates.append(relative.split("/", 1)[1] if "/" in relative else relative)
    return tuple(root / candidate for root in _search_roots(rule_file) for candidate in candidates)


def load_asset(path: Path) -> Mesh:
    """The mesh of an asset file (its own coordinates, y up), read once and kept."""
    held = _held.get()
    if held is None:
        return _loaded(path)
    key = ("load", path)
    mesh = held.get(key)
    if mesh is None:
        mesh = held[key] = _loaded(path)
    return mesh


def _loaded(path: Path) -> Mesh:
    status = path.stat()
    key = (str(path), status.st_mtime_ns, status.st_size)
    mesh = _cache.get(key)
    if mesh is not None:
        _cache.move_to_end(key)
        return mesh
    limit = current_limits().max_file_bytes
    if status.st_size > limit:
        raise GeometryError(
            f"asset {path} has {status.st_size} bytes, more than {limit} "
            + limit_hint("max_file_bytes")
        )
    try:
        if path.suffix.lower() == ".obj":
            text = path.read_text(encoding="utf-8", errors="replace")
            vertices, faces = obj_polygons(text, f"asset {path}")
        elif path.suffix.lower() == ".fbx":
            vertices, faces = fbx_polygons(path)
        else:
            vertices, faces = _read_triangles(path)
    except GeometryError:
        raise
    except InputFormatError as exc:
        raise GeometryError(str(exc)) from None
    except Exception as exc:  # any parser failure on a user's file
        text = str(exc).strip().splitlines()
        raise GeometryError(f"cannot read asset {path}: {text[0] if text else exc}") from None
    if not faces:
        raise GeometryError(f"asset {path} holds no face")
    if not np.all(np.isfinite(vertices)):
        raise GeometryError(f"asset {path}: vertex coordinates must be finite numbers")
    vertices, faces = cleaned_polygons(vertices, faces)
    if not faces:
        raise GeometryError(f"asset {path} holds no face with an area")
    mesh = Mesh(vertices, faces)
    _cache[key] = mesh
    while len(_cache) > _CACHE_SIZE:
        _cache.popitem(last=False)
    return mesh


def _read_triangles(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    """The triangles of a glTF, COLLADA, PLY or STL file (trimesh; COLLADA through pycollada),
    the scene flattened; a COLLADA file's ``up_axis`` turned to y up."""
    import trimesh

    loaded = trimesh.load(str(path), force="mesh", process=False)
    if not isinstance(loaded, trimesh.Trimesh):
        raise GeometryError(f"asset {path} holds no mesh")
    vertices = np.asarray(loaded.vertices, dtype=float)
    if path.suffix.lower() == ".dae":
        vertices = vertices @ _collada_up(path).T
    return vertices, np.asarray(loaded.faces).tolist()


#: COLLADA's up axes (its ``<asset><up_axis>``) turned to y up: Z_UP by -90 degrees about x
#: (as op_i's zUp), X_UP by 90 degrees about z.
_UP_AXES = {
    "Y_UP": np.eye(3),
    "Z_UP": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]),
    "X_UP": np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
}


def _collada_up(path: Path) -> np.ndarray:
    with open(path, encoding="utf-8", errors="replace") as handle:
        head = handle.read(1 << 16)  # the <asset> element comes first
    found = re.search(r"<up_axis>\s*([XYZ]_UP)\s*</up_axis>", head)
    return _UP_AXES[found.group(1) if found else "Y_UP"]
