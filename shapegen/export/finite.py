"""The writers' side of the boundary for numbers: no inf or NaN is written.

Every model writer (:func:`~shapegen.export.model_io.encode_model`) and the pictures check the
model with :func:`check_writable_numbers` before making any byte, so a model with a coordinate
that is not a finite number is refused in one line and nothing is written. The formats that
store float32 numbers (glTF, PLY, STL) also refuse a coordinate that float32 cannot hold,
which would become inf in the file.
"""

from __future__ import annotations

__all__ = ["FLOAT32_MAX", "check_writable_numbers"]

import math
import sys

import numpy as np

from shapegen.errors import GeometryError
from shapegen.model.model import Model

FLOAT32_MAX = float(np.finfo(np.float32).max)
"""The largest number a float32 holds (about 3.4e38); past it a float32 file holds inf."""


def check_writable_numbers(model: Model, target: str, *, float32: bool = False) -> None:
    """Refuse (:class:`~shapegen.errors.GeometryError`, naming ``target`` and the first block
    or surface at fault) a model with a vertex coordinate or a density that is not a finite
    number, or, with ``float32``, a coordinate beyond :data:`FLOAT32_MAX`."""
    bound = FLOAT32_MAX if float32 else sys.float_info.max  # inf is beyond either
    parts = [("block", b) for b in model.blocks] + [("surface", s) for s in model.surfaces]
    arrays = [np.asarray(part.vertices, dtype=float).ravel() for _, part in parts]
    coordinates = np.concatenate(arrays) if arrays else np.empty(0)
    densities = np.array([block.density for block in model.blocks], dtype=float)
    with np.errstate(invalid="ignore"):
        fine = bool((np.abs(coordinates) <= bound).all()) and bool(np.isfinite(densities).all())
    if fine:
        return
    for kind, part in parts:
        values = np.asarray(part.vertices, dtype=float)
        with np.errstate(invalid="ignore"):
            bad = values[~(np.abs(values) <= bound)]
        if len(bad):
            raise GeometryError(f"{target}: not written: {kind} {part.id!r} {_described(bad[0])}")
        density = getattr(part, "density", 0.0)
        if kind == "block" and not math.isfinite(density):
            raise GeometryError(f"{target}: not written: block {part.id!r} has density {density}")
    raise AssertionError("a number out of range was not found again")


def _described(value: float) -> str:
    if math.isnan(value):
        return "has a coordinate that is NaN (not a number)"
    if math.isinf(value):
        return "has a coordinate that is infinite"
    return f"has a coordinate of {value:.3g} m, beyond what float32 holds ({FLOAT32_MAX:.3g})"
