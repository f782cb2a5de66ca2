"""Checked values of a JSON model file: each refused in one line naming where it is.

The readers of shapegen-blocks documents (:mod:`shapegen.readers.blocks_json`,
:mod:`shapegen.readers.block_entries`, :mod:`shapegen.readers.surface_entries`) share these.
"""

from __future__ import annotations

__all__ = ["boolean", "number", "points", "require", "shown", "strings", "vector"]

import math

import numpy as np

from shapegen.errors import InputFormatError


def require(entry: dict, key: str, where: str):
    """``entry[key]``, refused when missing."""
    if key not in entry:
        raise InputFormatError(f'{where}: missing required key "{key}"')
    return entry[key]


def number(value: object, where: str) -> float:
    """A finite JSON number (not a boolean) as a float."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputFormatError(f"{where} must be a finite number, got {shown(value)}")
    try:
        result = float(value)
    except OverflowError:  # an int beyond float range, from a caller's own dict
        result = math.inf
    if not math.isfinite(result):
        raise InputFormatError(f"{where} must be a finite number, got {shown(value)}")
    return result


def shown(value: object) -> str:
    """A value for a message, cut short (a file may hold a 5 000-digit number)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**20:
        return f"an integer of {round(value.bit_length() * 0.30103)} digits"
    try:
        text = repr(value)
    except ValueError:  # holds an int too long to print
        return f"a {type(value).__name__} holding a number too long to print"
    return text if len(text) <= 60 else text[:57] + "..."


def boolean(value: object, where: str) -> bool:
    """A JSON true or false."""
    if not isinstance(value, bool):
        raise InputFormatError(f"{where} must be true or false, got {value!r}")
    return value


def strings(value: object, where: str) -> tuple[str, ...]:
    """A list of strings as a tuple."""
    if not isinstance(value, list) or not all(isinstance(s, str) for s in value):
        raise InputFormatError(f"{where} must be a list of strings")
    return tuple(value)


def vector(value: object, where: str) -> np.ndarray:
    """Three finite numbers as a ``(3,)`` array."""
    if not isinstance(value, list) or len(value) != 3:
        raise InputFormatError(f"{where} must be a list of 3 numbers")
    return np.array([number(v, where) for v in value])


def points(value: object, where: str) -> np.ndarray:
    """A non-empty list of [x, y, z] points as a ``(k, 3)`` array."""
    if not isinstance(value, list) or not value:
        raise InputFormatError(f"{where} must be a non-empty list of [x, y, z] points")
    return np.array([vector(p, where) for p in value])
