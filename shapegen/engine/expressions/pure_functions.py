"""CGA builtins that depend only on their arguments: maths, conversions, strings, string lists
(``"a;b;c;"``, celib's list functions) and colours; files are answered against the rule file's
project folder (see :func:`project_files`).

:data:`PURE_FUNCTIONS` maps a name to a Python function of the evaluated arguments; it raises
``ValueError`` with a message for the user. The maths follow IEEE arithmetic, as CityEngine's
runtime does: ``sqrt(-1)`` is nan (func_sqrt says so), as are ``ln(-1)`` and ``asin(2)``; ``ln(0)``
is -inf and ``exp(1000)`` inf (rule files write ``const nan = ln(-1)``). Functions that need
the shape or the random generator (``rand``, ``p``, ``fileRandom``, ``listRandom``, occlusion,
``geometry.*``) are compiled in :mod:`shapegen.engine.expressions.compiler`.
"""

from __future__ import annotations

__all__ = ["NULL_STRING", "PARTIAL_FUNCTIONS", "PURE_FUNCTIONS"]

import colorsys
import fnmatch
import math
import re
from collections.abc import Callable

import numpy as np

from shapegen.engine.expressions.arrays import (
    ARRAY_FUNCTIONS,
    Array,
    format_value,
    string_truth,
    type_name,
)

#: CGA's NULL string (func_isnull): U+E000.
NULL_STRING = "\ue000"


def _ieee(function: Callable[..., object]) -> Callable[..., float]:
    """``function`` (a numpy ufunc) on floats, with IEEE's nan and infinities for results
    outside its domain or range."""

    def call(*x: float) -> float:
        with np.errstate(all="ignore"):
            return float(function(*x))

    return call


def _degrees(function: Callable[[float], float]) -> Callable[[float], float]:
    return _ieee(lambda x: function(np.radians(x)))


def _inverse_degrees(function: Callable[..., float]) -> Callable[..., float]:
    return _ieee(lambda *x: np.degrees(function(*x)))


def _numbers(name: str, function: Callable[..., float]) -> Callable[..., float]:
    """A numeric function; element-wise over an array (``floor([1.5, 2.5])``)."""

    def call(*values):
        if len(values) == 1 and isinstance(values[0], Array):
            array = values[0]
            return Array(tuple(call(v) for v in array.values), array.rows, array.columns)
        for value in values:
            if type(value) is not float:
                raise ValueError(f"{name}() needs numbers, got {_kind(value)}")
        try:
            return float(function(*values))
        except (ValueError, OverflowError, ZeroDivisionError):
            shown = ", ".join(_show(v) for v in values)
            raise ValueError(f"{name}({shown}) is not defined") from None

    return call


def _kind(value: object) -> str:
    return "a " + type_name(value)


def _show(value: object) -> str:
    return format_value(value)


def _strings(name: str, count: int, *numbers: int) -> Callable:
    """Check that the first ``count`` arguments are strings and those at ``numbers`` numbers."""

    def check(function):
        def call(*values):
            for k, value in enumerate(values):
                want = float if k in numbers else str
                if k < count or k in numbers:
                    if type(value) is not want:
                        word = "a number" if want is float else "a string"
                        raise ValueError(
                            f"{name}() needs {word} as argument {k + 1}, got {_kind(value)}"
                        )
            return function(*values)

        return call

    return check


def _rint(x: float) -> float:
    return float(np.floor(x + 0.5))


def _min_max(name: str, pick: Callable) -> Callable:
    def call(a, b):
        if type(a) is not type(b) or type(a) not in (float, str):
            raise ValueError(f"{name}() needs two numbers or two strings")
        return pick(a, b)

    return call


def _clamp(x, low, high):
    if not (type(x) is type(low) is type(high)) or type(x) not in (float, str):
        raise ValueError("clamp() needs three numbers or three strings")
    return min(max(x, low), high)


def _find(text: str, match: str, n: float) -> float:
    position = -1
    for _ in range(int(n) + 1):
        position = text.find(match, position + 1)
        if position < 0 or not match:
            return -1.0
    return float(position)


def _substring(text: str, start: float, end: float) -> str:
    start = max(int(start), 0)
    end = min(int(end), len(text))
    return text[start:end] if start < end else ""


def _count(text: str, match: str) -> float:
    return float(text.count(match)) if match else 0.0


def _get_prefix(text: str, match: str) -> str:
    position = text.find(match)
    return text[:position] if position >= 0 else ""


def _get_suffix(text: str, match: str) -> str:
    position = text.rfind(match)
    return text[position + len(match) :] if position >= 0 else ""


def _get_range(text: str, left: str, right: str) -> str:
    """celib getRange: from the end of the first ``left`` to the start of the last ``right``
    ("our city with " of "rule your city with cityengine", "y", "city"); "" when they overlap."""
    start, end = text.find(left), text.rfind(right)
    if start < 0 or end < 0 or end < start + len(left):
        return ""
    return text[start + len(left) : end]


def _split_string(text: str, delimiter: str) -> Array:
    """func_splitString: a 1D array of the parts; a delimiter starting with ``$`` is a regular
    expression; an empty one splits between every character and at both ends."""
    if delimiter.startswith("$"):
        try:
            parts = re.split(delimiter[1:], text)
        except re.error as exc:
            raise ValueError(f"bad regular expression {delimiter[1:]!r}: {exc}") from None
    else:
        parts = text.split(delimiter) if delimiter else ["", *text, ""]
    return Array(tuple(parts), 1, len(parts))


def _str(value: object) -> str:
    return _show(value)


def _float(value: object) -> object:
    if type(value) is float:  # the most common call: a number already
        return value
    if isinstance(value, Array):
        return ARRAY_FUNCTIONS["floatArray"](value)
    if type(value) is str:
        try:
            return float(value)
        except ValueError:
            return math.nan  # CGA: float("abc") is NaN
    return float(value)


def _bool(value: object) -> object:
    if isinstance(value, Array):
        return ARRAY_FUNCTIONS["boolArray"](value)
    if type(value) is str:
        return string_truth(value)
    return bool(value)


def _is_null(value: object) -> object:
    if isinstance(value, Array):
        return Array(tuple(_is_null(v) for v in value.values), value.rows, value.columns)
    if type(value) is float:
        return math.isnan(value)
    return value == NULL_STRING


# String lists: items each followed by ";" (celib) -------------------------------------------


def _items(text: str) -> list[str]:
    items = text.split(";")
    if items and items[-1] == "":
        items.pop()
    return items


def _joined(items: list[str]) -> str:
    return "".join(item + ";" for item in items)


def _list_matches(item: str, pattern: str) -> bool:
    if pattern.startswith("*") or pattern.endswith("*"):
        return fnmatch.fnmatchcase(item, pattern)
    return item == pattern


def _list_index(text: str, pattern: str) -> float:
    for k, item in enumerate(_items(text)):
        if _list_matches(item, pattern):
            return float(k)
    return -1.0


def _list_item(text: str, index: float) -> str:
    items = _items(text)
    position = int(index)
    return items[position] if 0 <= position < len(items) else ""


def _list_range(text: str, left: float, right: float) -> str:
    return _joined(_items(text)[max(int(left), 0) : max(int(right), 0)])


# Colours -----------------------------------------------------------------------------------


def _hex_parts(text: str) -> tuple[float, float, float, float]:
    if type(text) is not str or not text.startswith("#") or len(text) not in (7, 9):
        raise ValueError(f"a colour is written '#rrggbb' or '#rrggbboo', got {text!r}")
    try:
        parts = [int(text[k : k + 2], 16) / 255.0 for k in range(1, len(text), 2)]
    except ValueError:
        raise ValueError(f"a colour is written '#rrggbb' or '#rrggbboo', got {text!r}") from None
    return (*parts[:3], parts[3] if len(parts) == 4 else 1.0)


def _to_hex(*channels: float) -> str:
    return "#" + "".join(f"{round(min(max(c, 0.0), 1.0) * 255):02x}" for c in channels)


def _hsv(text: str) -> tuple[float, float, float]:
    r, g, b, _ = _hex_parts(text)
    h, s, v = colorsys.rgb_to_hsv(r, g, b)
    return h * 360.0, s, v


def _from_hsv(h: float, s: float, v: float, *opacity: float) -> str:
    return _to_hex(*colorsys.hsv_to_rgb((h % 360.0) / 360.0, s, v), *opacity)


#: colorRamp's presets (celib/colorRamp.html): colour stops from 0 to 1.
_RAMPS: dict[str, tuple[str, ...]] = {
    "whiteToBlack": ("#ffffff", "#000000"),
    "greenToRed": ("#00ff00", "#ffff00", "#ff0000"),
    "yellowToRed": ("#ffff00", "#ff0000"),
    "redToBlue": ("#ff0000", "#ffffff", "#0000ff"),
    "orangeToBlue": ("#ff8000", "#ffffff", "#0080ff"),
    "brownToBlue": ("#a05000", "#ffffff", "#0050a0"),
    "spectrum": ("#ff0000", "#ffff00", "#00ff00", "#00ffff", "#0000ff", "#ff00ff"),
}


def _color_ramp(name: str, value: float) -> str:
    stops = _RAMPS.get(name)
    if stops is None:
        raise ValueError(f"colorRamp() knows the ramps {', '.join(_RAMPS)}; got {name!r}")
    t = min(max(value, 0.0), 1.0) * (len(stops) - 1)
    k = min(int(t), len(stops) - 2)
    a, b = _hex_parts(stops[k])[:3], _hex_parts(stops[k + 1])[:3]
    f = t - k
    return _to_hex(*(x + (y - x) * f for x, y in zip(a, b, strict=True)))


def _file_part(part: str) -> Callable[[str], str]:
    def call(path: str) -> str:
        if type(path) is not str:
            raise ValueError("a file path is a string")
        directory, _, name = path.rpartition("/")
        stem, dot, extension = name.rpartition(".")
        if part == "directory":
            return directory + "/" if directory else ""
        if part == "name":
            return name
        if part == "extension":  # celib fileExtension: "obj" of "assets/x.01.obj"
            return extension if dot else ""
        return stem if dot else name

    return call


#: Builtins of the evaluated arguments alone.
PURE_FUNCTIONS: dict[str, Callable[..., object]] = {
    "sin": _numbers("sin", _degrees(np.sin)),
    "cos": _numbers("cos", _degrees(np.cos)),
    "tan": _numbers("tan", _degrees(np.tan)),
    "asin": _numbers("asin", _inverse_degrees(np.arcsin)),
    "acos": _numbers("acos", _inverse_degrees(np.arccos)),
    "atan": _numbers("atan", _inverse_degrees(np.arctan)),
    "atan2": _numbers("atan2", _inverse_degrees(np.arctan2)),
    "sqrt": _numbers("sqrt", _ieee(np.sqrt)),
    "abs": _numbers("abs", abs),
    "floor": _numbers("floor", _ieee(np.floor)),
    "ceil": _numbers("ceil", _ieee(np.ceil)),
    "rint": _numbers("rint", _rint),
    "pow": _numbers("pow", _ieee(np.power)),
    "exp": _numbers("exp", _ieee(np.exp)),
    "ln": _numbers("ln", _ieee(np.log)),
    "log10": _numbers("log10", _ieee(np.log10)),
    "isinf": lambda x: math.isinf(x) if type(x) is float else False,
    "isnan": lambda x: math.isnan(x) if type(x) is float else False,
    "min": _min_max("min", min),
    "max": _min_max("max", max),
    "clamp": _clamp,
    "str": _str,
    "float": _float,
    "bool": _bool,
    "isNull": _is_null,
    "len": _strings("len", 1)(lambda text: float(len(text))),
    "count": _strings("count", 2)(_count),
    "find": _strings("find", 2, 2)(_find),
    "substring": _strings("substring", 1, 1, 2)(_substring),
    "splitString": _strings("splitString", 2)(_split_string),
    "findLast": _strings("findLast", 2)(lambda text, match: float(text.rfind(match))),
    "getPrefix": _strings("getPrefix", 2)(_get_prefix),
    "getSuffix": _strings("getSuffix", 2)(_get_suffix),
    "getRange": _strings("getRange", 3)(_get_range),
    "replace": _strings("replace", 3)(lambda text, old, new: text.replace(old, new)),
    "toUpperCase": _strings("toUpperCase", 1)(str.upper),
    "toLowerCase": _strings("toLowerCase", 1)(str.lower),
    # celib listAdd: listAdd("rule;your;", "city;") is "rule;your;city;" too
    "listAdd": _strings("listAdd", 2)(lambda text, item: _joined([*_items(text), *_items(item)])),
    "listClean": _strings("listClean", 1)(lambda text: _joined([i for i in _items(text) if i])),
    "listCount": _strings("listCount", 2)(
        lambda text, pattern: float(sum(_list_matches(i, pattern) for i in _items(text)))
    ),
    "listFirst": _strings("listFirst", 1)(lambda text: (_items(text) or [""])[0]),
    "listLast": _strings("listLast", 1)(lambda text: (_items(text) or [""])[-1]),
    "listIndex": _strings("listIndex", 2)(_list_index),
    "listItem": _strings("listItem", 1, 1)(_list_item),
    "listRange": _strings("listRange", 1, 1, 2)(_list_range),
    "listRemove": _strings("listRemove", 2)(
        lambda text, pattern: _joined(_remove_first(_items(text), pattern))
    ),
    "listRemoveAll": _strings("listRemoveAll", 2)(
        lambda text, pattern: _joined([i for i in _items(text) if not _list_matches(i, pattern)])
    ),
    "listRetainAll": _strings("listRetainAll", 2)(
        lambda text, pattern: _joined([i for i in _items(text) if _list_matches(i, pattern)])
    ),
    "listSize": _strings("listSize", 1)(lambda text: float(len(_items(text)))),
    "listTerminate": _strings("listTerminate", 1)(
        lambda text: text if not text or text.endswith(";") else text + ";"
    ),
    "listToArray": _strings("listToArray", 1)(
        lambda text: Array(tuple(_items(text)), 1 if _items(text) else 0, len(_items(text)))
    ),
    "listFromArray": lambda array: (
        _joined([_show(v) for v in array.values])
        if isinstance(array, Array)
        else _joined([_show(array)])
    ),
    "colorRGBToHex": lambda r, g, b: _to_hex(r, g, b),
    "colorRGBOToHex": lambda r, g, b, o: _to_hex(r, g, b, o),
    "colorHSVToHex": lambda h, s, v: _from_hsv(h, s, v),
    "colorHSVOToHex": lambda h, s, v, o: _from_hsv(h, s, v, o),
    "colorHexToR": lambda text: _hex_parts(text)[0],
    "colorHexToG": lambda text: _hex_parts(text)[1],
    "colorHexToB": lambda text: _hex_parts(text)[2],
    "colorHexToO": lambda text: _hex_parts(text)[3],
    "colorHexToH": lambda text: _hsv(text)[0],
    "colorHexToS": lambda text: _hsv(text)[1],
    "colorHexToV": lambda text: _hsv(text)[2],
    "colorRamp": _strings("colorRamp", 1, 1)(_color_ramp),
    "fileBasename": _file_part("basename"),
    "fileDirectory": _file_part("directory"),
    "fileExtension": _file_part("extension"),
    "fileName": _file_part("name"),
    **ARRAY_FUNCTIONS,
}
PURE_FUNCTIONS["isInf"] = PURE_FUNCTIONS["isinf"]

_SEARCH = "the file properties (Name:, Ext:...) are not read; paths start at the project"
#: Builtins here that differ from the reference, in a few words.
PARTIAL_FUNCTIONS: dict[str, str] = {"fileSearch": _SEARCH, "filesSearch": _SEARCH}
PURE_FUNCTIONS["isNaN"] = PURE_FUNCTIONS["isnan"]


def _remove_first(items: list[str], pattern: str) -> list[str]:
    for k, item in enumerate(items):
        if _list_matches(item, pattern):
            return items[:k] + items[k + 1 :]
    return items
