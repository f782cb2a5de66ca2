"""The Coulomb friction coefficient of a joint, checked in one place wherever one is given: a
model (:class:`~shapegen.model.model.Model`), a model file, the statics options, an assembly,
the simulation. Each says the one line in its own words (a model file's ``"friction": ...``).

>>> checked_friction(0.7)
0.7
>>> checked_friction(-0.1)
Traceback (most recent call last):
...
shapegen.errors.OptionError: friction must be a finite number >= 0; got -0.1
"""

from __future__ import annotations

__all__ = ["checked_friction"]

import math

from shapegen.errors import OptionError


def checked_friction(value: object) -> float:
    """``value`` as a friction coefficient mu (dimensionless, a finite number >= 0), or an
    :class:`~shapegen.errors.OptionError` naming ``friction``."""
    number = None
    if not isinstance(value, bool):
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            number = None
    if number is None or not math.isfinite(number) or number < 0:
        raise OptionError(f"friction must be a finite number >= 0; got {value!r}", "friction")
    return number
