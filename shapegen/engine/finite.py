"""What an operation does with a parameter that is not a finite number."""

from __future__ import annotations

__all__ = ["finite_parameter"]

import math


def finite_parameter(program, node, state, value: float, what: str) -> float:
    """``value`` when finite. Otherwise, in a ``.cga`` file, 0 and a warning: CityEngine's
    runtime replaces an inf or nan float parameter of its builtins with zero by default
    (cga_changelog 2013.1, "inf/nan checks"); in a ``.grammar`` file an error naming ``what``."""
    if math.isfinite(value):
        return value
    if program.cga_dialect:
        state.run.warn(f"{node.location}: {what} is {value}: replaced by 0, as CityEngine does")
        return 0.0
    raise program.error(node, f"{what} must be a finite number, got {value}")
