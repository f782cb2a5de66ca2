"""Plain JSON values for reports: the one converter of numbers and numpy values."""

from __future__ import annotations

__all__ = ["finite_or_none", "json_ready"]

import math


def finite_or_none(value: object) -> float | None:
    """``value`` as a float, or None when it is not finite (JSON has no inf or nan)."""
    if value is None:
        return None
    number = float(value)
    return number if math.isfinite(number) else None


def json_ready(value: object) -> object:
    """Plain JSON values: numpy scalars and arrays unwrapped, non-finite numbers as null,
    enums as their value, anything else as its text."""
    if isinstance(value, dict):
        return {str(k): json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v) for v in value]
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return json_ready(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(getattr(value, "value", value))
