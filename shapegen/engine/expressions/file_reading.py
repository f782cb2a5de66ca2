"""The functions that read a file of the rule's project, found by the asset search
(:mod:`shapegen.engine.project.asset_files`).

``readStringTable(path)`` and ``readFloatTable(path)`` (func_readTable): a CSV file as a 2D
array, its delimiter detected (commas, semicolons, tabs or spaces), ASCII, UTF-8 or UTF-16 (by
its byte-order mark), unprintable control characters read as ``?``. ``readFloatTable`` is the
string table with each cell read as a number (``nan`` where it is not one). A file that is
missing or unreadable gives an empty table and a warning of the build, as CityEngine's runtime
does ("error, using empty table").

``readTextFile(path)`` (func_readTextFile): the file's text ("" and a warning when it cannot be
read).

``assetInfo(path, sx|sy|sz|tx|ty|tz)`` (func_assetInfo): the size of the asset's bounding box
along an axis, or the coordinate of its lowest corner (``tx`` is its smallest x), in the asset's
own coordinates. An asset that is missing or unreadable gives 0 and a warning (``i()`` of such
an asset inserts a box filling the scope).

``imageInfo(path, sx|sy)`` (func_imageInfo): an image's width or height in pixels (Pillow reads
it); 0 and a warning when it cannot be read.

``readMaterial(path)`` (func_readMaterial): a material file as the 2D string array of material
attributes that ``setMaterial()`` takes, one ``name, value`` pair a row. A Wavefront ``.mtl``
file's first material is read (``Kd``, ``Ka``, ``Ks``, ``Ns``, ``d``, ``Tr`` and the ``map_*``
textures, relative to the file's folder); CityEngine's own ``.cgamat`` format is not documented
and is refused with one line. A file that is missing gives an empty array and a warning, so
``setMaterial()`` of it changes nothing.

``assetMetadata(path, key, default)`` (func_assetMetadata): the metadata "potentially included in
the geometry asset", which OBJ, PLY and STL files do not carry: ``default``. Metadata of glTF
assets (their ``extras``) is not read: an error names it rather than a guess at which extras
CityEngine reads."""

from __future__ import annotations

__all__ = ["PARTIAL_FUNCTIONS", "read_table", "reading_functions"]

import csv
import math
import re
from pathlib import Path

from shapegen.engine.derivation.state import format_chain
from shapegen.engine.expressions.arrays import Array
from shapegen.engine.expressions.asset_choice import PARTIAL_FUNCTIONS as CHOOSER_NOTES
from shapegen.engine.expressions.asset_choice import asset_choosers
from shapegen.engine.project.asset_files import find_asset, load_asset
from shapegen.errors import GeometryError
from shapegen.limits import current_limits, limit_hint

#: File functions that differ from the reference, in a few words.
PARTIAL_FUNCTIONS: dict[str, str] = {
    "assetMetadata": "OBJ, PLY and STL carry none (the default); glTF assets are refused",
    "readMaterial": "a .mtl file's first material; CityEngine's .cgamat files are refused",
    **CHOOSER_NOTES,
}

_CONTROL = re.compile(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]")
_EMPTY_STRINGS = Array((), 0, 0, str)
_EMPTY_FLOATS = Array((), 0, 0, float)


def read_table(path: Path) -> list[list[str]]:
    """The rows of the CSV file at ``path`` (ragged rows padded with empty cells)."""
    limit = current_limits().max_file_bytes
    if path.stat().st_size > limit:
        raise ValueError(f"it has more than {limit} bytes " + limit_hint("max_file_bytes"))
    raw = path.read_bytes()
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        text = raw.decode("utf-16")
    else:
        text = raw.decode("utf-8-sig", errors="replace")
    text = _CONTROL.sub("?", text)
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        return []
    try:
        dialect = csv.Sniffer().sniff("\n".join(lines[:20]), delimiters=",;\t ")
        delimiter = dialect.delimiter
    except csv.Error:
        delimiter = ","
    rows = [[cell.strip() for cell in row] for row in csv.reader(lines, delimiter=delimiter)]
    width = max(len(row) for row in rows)
    return [row + [""] * (width - len(row)) for row in rows]


def _number(cell: str) -> float:
    try:
        value = float(cell)
    except ValueError:
        return math.nan
    return value


def _table(rule_file: str | None, as_floats: bool):
    name = "readFloatTable" if as_floats else "readStringTable"

    def read(state, path: object) -> Array:
        if type(path) is not str:
            raise ValueError("needs a file path (a string)")
        found = find_asset(path, rule_file)
        problem = "not found"
        if found is not None:
            try:
                rows = read_table(found)
            except (OSError, ValueError) as exc:
                problem = f"cannot be read: {exc}"
            else:
                cells = [_number(c) if as_floats else c for row in rows for c in row]
                return Array(tuple(cells), len(rows), len(rows[0]) if rows else 0)
        _warn(state, f"{name}({path!r}): the file {problem}; an empty table is used, as "
                     "CityEngine does")  # fmt: skip
        return _EMPTY_FLOATS if as_floats else _EMPTY_STRINGS

    return read


_ASSET_INFO = {"sx": (0, False), "sy": (1, False), "sz": (2, False),
               "tx": (0, True), "ty": (1, True), "tz": (2, True)}  # fmt: skip
_BUILTIN_CUBES = ("builtin:cube", "builtin:cube:notex")


def _warn(state, text: str) -> None:
    state.run.warn(f"{text} (rules: {format_chain(state.rule_path)})")


def _asset_info(rule_file: str | None):
    def info(state, path: object, selector: object = None, *extra) -> float:
        if type(path) is not str:
            raise ValueError("needs an asset path (a string)")
        if extra or selector not in _ASSET_INFO:
            raise ValueError("takes an asset path and one of sx, sy, sz, tx, ty, tz")
        axis, corner = _ASSET_INFO[selector]
        if path in _BUILTIN_CUBES:
            return 0.0 if corner else 1.0
        found = find_asset(path, rule_file)
        if found is None:
            _warn(state, f"assetInfo({path!r}, {selector}): the asset is not found; 0 is used")
            return 0.0
        try:
            low, high = load_asset(found).bounds()
        except (OSError, GeometryError) as exc:
            _warn(state, f"assetInfo({path!r}, {selector}): {exc}; 0 is used")
            return 0.0
        return float(low[axis] if corner else high[axis] - low[axis])

    return info


def _text_file(rule_file: str | None):
    def read(state, path: object) -> str:
        if type(path) is not str:
            raise ValueError("needs a file path (a string)")
        found = find_asset(path, rule_file)
        problem = "not found"
        if found is not None:
            limit = current_limits().max_file_bytes
            try:
                if found.stat().st_size > limit:
                    raise ValueError(
                        f"it has more than {limit} bytes " + limit_hint("max_file_bytes")
                    )
                return found.read_bytes().decode("utf-8-sig", errors="replace")
            except (OSError, ValueError) as exc:
                problem = f"cannot be read: {exc}"
        _warn(state, f'readTextFile({path!r}): the file {problem}; "" is used')
        return ""

    return read


def _image_info(rule_file: str | None):
    def info(state, path: object, selector: object = None) -> float:
        if type(path) is not str:
            raise ValueError("needs an image path (a string)")
        if selector not in ("sx", "sy"):
            raise ValueError("takes an image path and sx (width) or sy (height)")
        found = find_asset(path, rule_file)
        problem = "is not found"
        if found is not None:
            from PIL import Image, UnidentifiedImageError

            try:
                with Image.open(found) as image:
                    width, height = image.size
                return float(width if selector == "sx" else height)
            except (OSError, UnidentifiedImageError, ValueError) as exc:
                problem = f"cannot be read ({exc})"
        _warn(state, f"imageInfo({path!r}, {selector}): the image {problem}; 0 is used")
        return 0.0

    return info


# Wavefront .mtl statements -> the material attributes they set (cga material attributes).
_MTL_COLOURS = {"kd": "color", "ka": "ambient", "ks": "specular"}
_MTL_MAPS = {"map_kd": "colormap", "map_d": "opacitymap", "map_bump": "bumpmap",
             "bump": "bumpmap", "norm": "normalmap", "map_ks": "specularmap"}  # fmt: skip


def read_mtl(path: Path) -> list[tuple[str, str]]:
    """The ``(attribute, value)`` pairs of the first material of the ``.mtl`` file ``path``."""
    pairs: list[tuple[str, str]] = []
    started = False
    for line in path.read_text("utf-8", errors="replace").splitlines():
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        key, rest = words[0].lower(), words[1:]
        if key == "newmtl":
            if started:
                break  # the first material only
            started = True
            pairs.append(("name", " ".join(rest)))
        elif key in _MTL_COLOURS and len(rest) >= 3:
            pairs += [(f"{_MTL_COLOURS[key]}.{c}", v) for c, v in zip("rgb", rest[:3], strict=True)]
        elif key == "ns" and rest:
            pairs.append(("shininess", rest[0]))
        elif key == "d" and rest:
            pairs.append(("opacity", rest[0]))
        elif key == "tr" and rest:  # transparency, the complement of d
            pairs.append(("opacity", repr(1.0 - float(rest[0]))))
        elif key in _MTL_MAPS and rest:
            pairs.append((_MTL_MAPS[key], str(path.parent / rest[-1])))
    return pairs


def _material_file(rule_file: str | None):
    def read(state, path: object) -> Array:
        if type(path) is not str:
            raise ValueError("needs a file path (a string)")
        found = find_asset(path, rule_file)
        if found is None:
            _warn(state, f"readMaterial({path!r}): the file is not found; an empty material is "
                         "used (setMaterial() of it changes nothing)")  # fmt: skip
            return _EMPTY_STRINGS
        if found.suffix.lower() != ".mtl":
            raise ValueError(f"{found.name}: shapegen reads .mtl material files, not "
                             f"{found.suffix or 'files without a suffix'}")  # fmt: skip
        try:
            pairs = read_mtl(found)
        except (OSError, ValueError) as exc:
            raise ValueError(f"{found.name} cannot be read: {exc}") from None
        pairs = [(k, v) for k, v in pairs if k != "name"]
        return Array(tuple(c for pair in pairs for c in pair), len(pairs), 2)

    return read


_NO_METADATA = (".obj", ".ply", ".stl")


def _asset_metadata(rule_file: str | None):
    def metadata(state, path: object, key: object, default: object) -> object:
        if type(path) is not str or type(key) is not str:
            raise ValueError("takes an asset path, a key (strings) and a default value")
        found = find_asset(path, rule_file)
        if found is None:
            _warn(state, f"assetMetadata({path!r}, {key!r}): the asset is not found; the "
                         "default is used")  # fmt: skip
            return default
        if found.suffix.lower() in _NO_METADATA:
            return default  # these formats carry no metadata
        raise ValueError(f"metadata of {found.suffix} assets is not read by shapegen")

    return metadata


def reading_functions(rule_file: str | None, matching=None) -> dict:
    """The builtins that need the shape being derived, for a rule written in ``rule_file``:
    ``name -> f(state, *values)``: the file-reading ones, the asset choosers
    (:mod:`~shapegen.engine.expressions.asset_choice`; ``matching(query)`` lists the project's
    files a search query names) and
    :data:`~shapegen.engine.expressions.shape_attributes.STATE_FUNCTIONS`."""
    from shapegen.engine.expressions.shape_attributes import STATE_FUNCTIONS

    return {
        **STATE_FUNCTIONS,
        **asset_choosers(rule_file, matching or (lambda query: [])),
        "readStringTable": _table(rule_file, False),
        "readFloatTable": _table(rule_file, True),
        "readTextFile": _text_file(rule_file),
        "assetInfo": _asset_info(rule_file),
        "imageInfo": _image_info(rule_file),
        "assetMetadata": _asset_metadata(rule_file),
        "readMaterial": _material_file(rule_file),
    }
