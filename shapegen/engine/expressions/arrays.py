"""CGA arrays: the value type and the array builtins (arrayTypes.html, func_*.html).

An array is a table of floats, booleans or strings, stored row by row: ``[1, 2, 3]`` is one row
of three columns, ``[1; 2]`` two rows of one column. Indices start at 0; a one-row or one-column
array takes one index (``a[1]``), any array two (``a[row, column]``). An index outside the array
gives the default of the array's type (0, false or ""), as func_index says ("Invalid indexing");
an array of indices gives an array of the indices' shape.
"""

from __future__ import annotations

__all__ = [
    "ARRAY_FUNCTIONS",
    "Array",
    "array_from",
    "concatenated",
    "format_array",
    "format_value",
    "index_array",
    "string_truth",
    "type_name",
]

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from shapegen.tolerances import REPEAT_SLACK


@dataclass(frozen=True)
class Array:
    """A CGA array: ``values`` row by row, ``rows`` x ``columns``; ``element`` is the type of an
    empty array's elements (``floatArray()``, a missing table), which its indexing needs."""

    values: tuple
    rows: int
    columns: int
    element: type | None = field(default=None, compare=False)

    @property
    def size(self) -> int:
        return len(self.values)

    def element_type(self) -> type | None:
        return type(self.values[0]) if self.values else self.element


_DEFAULTS = {float: 0.0, bool: False, str: ""}


def array_from(rows: list[list]) -> Array:
    """An array from its rows; every row the same length and every element the same type."""
    widths = {len(row) for row in rows}
    if len(widths) > 1:
        raise ValueError("the rows of an array must have the same number of elements")
    values = tuple(value for row in rows for value in row)
    types = {type(value) for value in values}
    if len(types) > 1:
        raise ValueError("an array holds values of one type (numbers, booleans or strings)")
    if any(isinstance(value, Array) for value in values):
        raise ValueError("an array cannot hold arrays")
    return Array(values, len(rows) if values else 0, widths.pop() if values else 0)


def concatenated(rows: list[list[object]]) -> Array:
    """An array literal (func_array): each row of the literal is its items side by side, the
    rows one above the other; an item is a value (one element) or an array (its block of rows
    and columns: ``[a, b; b, a]``); empty arrays add nothing. All elements are of one type."""
    blocks = []
    element = None
    for items in rows:
        parts = []
        for item in items:
            if isinstance(item, Array):
                kind = item.element_type()
                if element is not None and kind is not None and kind is not element:
                    raise ValueError(
                        "an array holds values of one type (numbers, booleans or strings)"
                    )
                element = element or kind
                if item.size:
                    parts.append(item)
            else:
                parts.append(Array((item,), 1, 1))
        if not parts:
            continue
        heights = {part.rows for part in parts}
        if len(heights) > 1:
            raise ValueError("the arrays side by side in a row must have the same number of rows")
        height = heights.pop()
        values = tuple(
            value
            for r in range(height)
            for part in parts
            for value in part.values[r * part.columns : (r + 1) * part.columns]
        )
        blocks.append(Array(values, height, sum(part.columns for part in parts)))
    if not blocks:
        return Array((), 0, 0, element)
    if len({block.columns for block in blocks}) > 1:
        raise ValueError("the rows of an array must have the same number of elements")
    values = tuple(value for block in blocks for value in block.values)
    if any(isinstance(value, Array) for value in values):
        raise ValueError("an array cannot hold arrays")
    types = {type(value) for value in values}
    if len(types) > 1 or (element is not None and types != {element}):
        raise ValueError("an array holds values of one type (numbers, booleans or strings)")
    return Array(values, sum(block.rows for block in blocks), blocks[0].columns)


def format_array(array: Array, format_value: Callable[[object], str]) -> str:
    """CGA's text of an array, as its ``print`` shows it (func_array, func_colon, func_readTable):
    a row as ``(3)[1,2,3]``; more rows as ``(2x3)`` then one line per row, each column right-aligned
    three spaces wider than its widest element."""
    cells = [format_value(v) for v in array.values]
    if array.rows <= 1:
        return f"({len(cells)})[{','.join(cells)}]"
    columns = array.columns
    widths = [3 + max(len(cell) for cell in cells[c::columns]) for c in range(columns)]
    lines = [
        "".join(
            cell.rjust(width)
            for cell, width in zip(cells[r * columns : (r + 1) * columns], widths, strict=True)
        )
        for r in range(array.rows)
    ]
    return "\n".join([f"({array.rows}x{columns})", *lines])


def _position(index: object, length: int) -> int:
    """The element ``index`` names, -1 when it is outside the array."""
    if type(index) is not float or not math.isfinite(index):
        raise ValueError(f"an array index must be a number, got {index!r}")
    position = int(math.floor(index))
    return position if 0 <= position < length else -1


def _default(array: Array) -> object:
    element = array.element_type()
    if element not in _DEFAULTS:
        raise ValueError("an empty array of unknown type cannot be indexed")
    return _DEFAULTS[element]


def index_array(array: Array, indices: list) -> object:
    """``array[i]`` or ``array[row, column]``; an index may be an array of indices (the result
    has its shape) or of booleans (a mask, always linear). Indices outside the array give the
    default of the array's type."""
    if not isinstance(array, Array):
        raise ValueError("only arrays can be indexed with [ ]")
    element = array.element_type()

    def at(position: int) -> object:
        return array.values[position] if position >= 0 else _default(array)

    if len(indices) == 1:
        (index,) = indices
        if not isinstance(index, Array):
            return at(_position(index, array.size))
        values = tuple(at(k) for k in _chosen(index, array.size))
        if index.element_type() is bool:  # logical indexing keeps the array's orientation
            if array.rows == 1 or not values:
                return Array(values, 1 if values else 0, len(values), element)
            return Array(values, len(values), 1, element)
        return Array(values, index.rows, index.columns, element)
    row, column = indices

    def positions(index: object, length: int) -> list[int]:
        return _chosen(index, length) if isinstance(index, Array) else [_position(index, length)]

    if not isinstance(row, Array) and not isinstance(column, Array):
        r, c = _position(row, array.rows), _position(column, array.columns)
        return at(r * array.columns + c if r >= 0 and c >= 0 else -1)
    rows, columns = positions(row, array.rows), positions(column, array.columns)
    values = tuple(
        at(r * array.columns + c if r >= 0 and c >= 0 else -1) for r in rows for c in columns
    )
    return Array(values, len(rows) if values else 0, len(columns) if values else 0, element)


def _chosen(index: Array, length: int) -> list[int]:
    """The positions an index array names (row-wise), -1 for those outside the array; a
    boolean array names the positions of its true values (those past the end are outside)."""
    if index.element_type() is bool:
        return [k if k < length else -1 for k, keep in enumerate(index.values) if keep]
    return [_position(value, length) for value in index.values]


def colon_range(start: float, step: float, stop: float) -> list[float]:
    """``start : step : stop`` (colon.html): the numbers from start towards stop."""
    if step == 0 or not all(math.isfinite(v) for v in (start, step, stop)):
        return []
    count = math.floor((stop - start) / step + REPEAT_SLACK) + 1
    if count > 10_000_000:
        raise ValueError(f"the range {start}:{step}:{stop} has too many elements")
    return [start + k * step for k in range(max(count, 0))]


def type_name(value: object) -> str:
    """The grammar's name for a value's type (for error messages)."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, float):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, Array):
        kind = type_name(value.values[0]) if value.values else "empty"
        return f"{kind} array"
    return type(value).__name__


def format_value(value: object) -> str:
    """A value as CGA prints it: ``3`` for 3.0, ``true`` for True, other numbers to 16
    significant digits (func_colon: ``[0 : 0.15 : 0.5]`` prints ``0.45`` though its last element
    is not 0.45, "due to an implicit rounding"; func_convert prints 16 digits)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isfinite(value) and value == int(value) and abs(value) < 1e15:
            return str(int(value))
        if math.isfinite(value):
            return f"{value:.16g}"
        return repr(value)
    if isinstance(value, Array):
        return format_array(value, format_value)
    return str(value)


def _typed(name: str, kind: type) -> Callable:
    def convert(value: object = None) -> Array:
        if value is None:
            return Array((), 0, 0, kind)
        if isinstance(value, Array):
            return Array(tuple(_convert(v, kind) for v in value.values), value.rows, value.columns)
        return Array((_convert(value, kind),), 1, 1)

    convert.__name__ = name
    return convert


def string_truth(text: str) -> bool:
    """func_bool of a string: false for "f", "false" and the numbers equal to 0 ("0", "0.0"),
    true for any other text (boolArray(["f", "schwiizer nati"]) is [false, true])."""
    word = text.strip().lower()
    if word in ("f", "false"):
        return False
    try:
        return float(word) != 0.0
    except ValueError:
        return True


def _convert(value: object, kind: type) -> object:
    if kind is str:
        return format_value(value)
    if kind is bool:
        if type(value) is str:
            return string_truth(value)
        return bool(value)
    if type(value) is str:
        try:
            return float(value)
        except ValueError:
            return math.nan
    return float(value)


def _need_array(name: str, value: object) -> Array:
    if not isinstance(value, Array):
        raise ValueError(f"{name}() needs an array")
    return value


def _sum(array: object) -> object:
    array = _need_array("sum", array)
    if array.element_type() is str:
        return "".join(array.values)
    return float(sum(array.values))  # func_sum: a bool array's count of true elements


def _transpose(array: object) -> Array:
    array = _need_array("transpose", array)
    values = tuple(
        array.values[r * array.columns + c] for c in range(array.columns) for r in range(array.rows)
    )
    return Array(values, array.columns, array.rows)


def _sortable(name: str, array: object) -> Array:
    array = _need_array(name, array)
    if array.values and array.element_type() not in (float, str):
        raise ValueError(f"{name}() sorts numbers or strings, got a {type_name(array)}")
    return array


def _sort_indices(array: object) -> Array:
    """func_sortIndices: each row sorted on its own (stable), as indices into the whole array."""
    array = _sortable("sortIndices", array)
    columns, values = array.columns, array.values
    order = [
        float(r * columns + k)
        for r in range(array.rows)
        for k in sorted(range(columns), key=lambda k, r=r: values[r * columns + k])
    ]
    return Array(tuple(order), array.rows, array.columns, float)


def _sort_row_indices(array: object) -> Array:
    """func_sortRowIndices: the rows' indices in the order of the sorted rows (stable; rows
    compare element by element)."""
    array = _sortable("sortRowIndices", array)
    columns, values = array.columns, array.values
    order = sorted(range(array.rows), key=lambda r: values[r * columns : (r + 1) * columns])
    return Array(tuple(float(r) for r in order), 1, len(order), float)


def _find_first(array: object, value: object, epsilon: float = 0.0) -> float:
    if isinstance(array, str):  # the string form of the utility library
        return float(array.find(value)) if isinstance(value, str) else -1.0
    array = _need_array("findFirst", array)
    for k, element in enumerate(array.values):
        if type(element) is float and type(value) is float:
            if abs(element - value) <= epsilon:
                return float(k)
        elif element == value and type(element) is type(value):
            return float(k)
    return -1.0


def _set_elems(array: object, *rest: object) -> Array:
    array = _need_array("setElems", array)
    values = list(array.values)
    if len(rest) == 2:
        indices, new = rest
        positions = (
            _chosen(indices, array.size)
            if isinstance(indices, Array)
            else [_position(indices, array.size)]
        )
    else:
        rows, columns, new = rest
        row_list = (
            _chosen(rows, array.rows) if isinstance(rows, Array) else [_position(rows, array.rows)]
        )
        column_list = (
            _chosen(columns, array.columns)
            if isinstance(columns, Array)
            else [_position(columns, array.columns)]
        )
        positions = [r * array.columns + c for r in row_list for c in column_list]
    news = list(new.values) if isinstance(new, Array) else [new] * len(positions)
    if len(news) != len(positions):
        raise ValueError("setElems() needs one value per index, or one value for all")
    for position, value in zip(positions, news, strict=True):
        if array.values and type(value) is not array.element_type():
            raise ValueError("setElems() values must have the array's element type")
        values[position] = value
    return Array(tuple(values), array.rows, array.columns)


#: Array builtins: name -> function of the evaluated arguments.
ARRAY_FUNCTIONS: dict[str, Callable[..., object]] = {
    "size": lambda a: float(_need_array("size", a).size),
    "nRows": lambda a: float(_need_array("nRows", a).rows),
    "nColumns": lambda a: float(_need_array("nColumns", a).columns),
    "sum": _sum,
    "transpose": _transpose,
    "sortIndices": _sort_indices,
    "sortRowIndices": _sort_row_indices,
    "findFirst": _find_first,
    "setElems": _set_elems,
    "floatArray": _typed("floatArray", float),
    "boolArray": _typed("boolArray", bool),
    "stringArray": _typed("stringArray", str),
}
