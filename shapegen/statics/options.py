"""The settings of a block analysis, as one frozen object checked once.

>>> StaticsOptions(friction=0.5, kern=1 / 3).pyramid
'cone'
>>> StaticsOptions.from_mapping({"frcition": 0.5})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
shapegen.errors.OptionError: unknown statics option 'frcition' (did you mean 'friction'?); ...
"""

from __future__ import annotations

__all__ = ["StaticsOptions", "SOLVERS", "AUTO_ORDER", "PYRAMIDS", "DEFAULT_PYRAMID"]

import dataclasses
import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass

from shapegen.errors import OptionError
from shapegen.statics.solvers import BACKENDS, cone_refusal, takes_cones
from shapegen.statics.tilt import normalized_azimuth

AUTO_ORDER = ("reduced", "clarabel")
"""``solver="auto"``: the fastest back-end first, the next if it fails (for the exact cone, only
those that declare they take cones; every bundled one does)."""

PYRAMIDS = ("4", "4r", "8", "cone")
"""Friction models: pyramids inscribed in the Coulomb cone (4, 4 turned by 45 degrees, 8 sides),
or the exact cone (a second-order cone: the verdict does not turn with the model)."""
DEFAULT_PYRAMID = "cone"
"""The exact Coulomb cone: Coulomb's law itself, whose verdict does not depend on how the model
is turned; the pyramids (the papers' linearisation, inside the cone and so on the safe side)
stay options."""
SOLVERS = ("auto", *BACKENDS)
"""Valid values of :attr:`StaticsOptions.solver`."""


@dataclass(frozen=True)
class StaticsOptions:
    """How a block model is analysed.

    Attributes
    ----------
    friction
        Coulomb coefficient mu of every joint (dimensionless, >= 0); None uses the model's own.
    pyramid
        Friction model: ``"cone"`` (the default: the exact Coulomb cone ||ft|| <= mu fn, a
        second-order cone per joint vertex, so the verdict does not depend on how the model is
        turned), or a pyramid inscribed in it as the papers linearise it: ``"4"`` (|ft1|,
        |ft2| <= mu/sqrt(2) fn, Whiting et al. 2009), ``"4r"`` (the same square turned 45
        degrees, |ft1| + |ft2| <= mu fn) or ``"8"`` (the octagon). A pyramid holds less
        friction than the cone in most directions: a verdict with it is on the safe side.
    kern
        Every joint polygon is scaled about its centroid by this factor in (0, 1]: a geometric
        factor of safety (1/3: forces through the middle third of a rectangular joint).
    solver
        QP back-end: ``"auto"`` (the reduced interior point method, Clarabel if it fails),
        ``"reduced"``, ``"clarabel"`` or ``"cvxpy"``; each takes the cone and the pyramids.
    tilt
        Degrees in [0, 90): every load turned by this angle, the tilting-table test
        (:mod:`shapegen.statics.tilt`); 0 judges the model as it is loaded.
    azimuth
        Degrees in the ground plane from +x towards +z: the direction gravity is tilted towards
        (normalised to [0, 360)); None, with a tilt, tilts it towards the worst direction, the
        one of least lateral capacity (:func:`shapegen.statics.multiplier.worst_direction`).
    structural
        Labels or rule names (``"A,B"`` or a sequence): only the blocks with one of them are
        structure, the other structural blocks are ornaments that ride as load on the body
        they rest on (:mod:`shapegen.statics.bodies`); empty: every structural block.
    ignore
        Labels or rule names of ornaments: blocks that ride as load, whatever ``structural``
        says.

    Raises
    ------
    OptionError
        On construction, naming the option and its valid values.
    """

    friction: float | None = None
    pyramid: str = DEFAULT_PYRAMID
    kern: float = 1.0
    solver: str = "auto"
    tilt: float = 0.0
    azimuth: float | None = None
    structural: tuple[str, ...] = ()
    ignore: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in ("structural", "ignore"):
            object.__setattr__(self, name, _labels(getattr(self, name), name))
        if self.pyramid not in PYRAMIDS:
            raise OptionError(f"pyramid must be one of {', '.join(PYRAMIDS)}; got {self.pyramid!r}")
        if self.solver not in SOLVERS:
            raise OptionError(f"solver must be one of {', '.join(SOLVERS)}; got {self.solver!r}")
        if not self.backends():
            raise OptionError(cone_refusal(self.solver))
        kern = _number(self.kern)
        if kern is None or not 0 < kern <= 1:
            raise OptionError(f"kern must be a number in (0, 1]; got {self.kern!r}")
        object.__setattr__(self, "kern", kern)
        if self.friction is not None:
            friction = _number(self.friction)
            if friction is None or friction < 0:
                raise OptionError(f"friction must be a finite number >= 0; got {self.friction!r}")
            object.__setattr__(self, "friction", friction)
        tilt = _number(self.tilt)
        if tilt is None or not 0 <= tilt < 90:
            raise OptionError(
                f"tilt must be a number of degrees, at least 0 and below 90; got {self.tilt!r}"
            )
        object.__setattr__(self, "tilt", tilt)
        if self.azimuth is not None:
            azimuth = _number(self.azimuth)
            if azimuth is None:
                raise OptionError(
                    f"azimuth must be a finite number of degrees; got {self.azimuth!r}"
                )
            object.__setattr__(self, "azimuth", normalized_azimuth(azimuth))

    @classmethod
    def from_mapping(cls, settings: Mapping[str, object]) -> StaticsOptions:
        """Options from ``name -> value``; an unknown name is an error with a suggestion."""
        names = [f.name for f in dataclasses.fields(cls)]
        for name in settings:
            if name not in names:
                close = difflib.get_close_matches(str(name), names, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise OptionError(
                    f"unknown statics option {name!r}{hint}; options: {', '.join(names)}"
                )
        return cls(**settings)

    def backends(self) -> tuple[str, ...]:
        """The back-ends to try, in order: :data:`AUTO_ORDER` for ``"auto"`` (only those that
        take cones for the exact cone), else the one named; empty when it cannot solve the
        friction model."""
        names = AUTO_ORDER if self.solver == "auto" else (self.solver,)
        if self.pyramid == "cone":
            names = tuple(name for name in names if takes_cones(name))
        return names

    def shrunk(self, margin: float) -> StaticsOptions:
        """The same options with every joint shrunk to ``1 - margin`` of the kern: a design that
        stands with them stands with that geometric reserve."""
        return dataclasses.replace(self, kern=self.kern * (1.0 - margin))

    def towards(self, azimuth: float | None) -> StaticsOptions:
        """The same options with the tilt towards ``azimuth`` (degrees; None: the worst)."""
        return dataclasses.replace(self, azimuth=azimuth)

    def selecting(self, structural=None, ignore=None) -> StaticsOptions:
        """The same options with the structure selected by ``structural`` and ``ignore`` where
        these options select none (the command line's choice wins over the rule's)."""
        changes = {}
        if not self.structural and structural:
            changes["structural"] = structural
        if not self.ignore and ignore:
            changes["ignore"] = ignore
        return dataclasses.replace(self, **changes) if changes else self

    @property
    def tilted(self) -> bool:
        """True when the loads are turned (a tilt above 0)."""
        return self.tilt > 0

    def to_report(self) -> dict:
        """Plain JSON values (the structure selected only when one is)."""
        report = dataclasses.asdict(self)
        for name in ("structural", "ignore"):
            if report[name]:
                report[name] = list(report[name])
            else:
                del report[name]
        return report


def _labels(value: object, name: str) -> tuple[str, ...]:
    """Labels or rule names from ``"A,B"`` or a sequence of strings, in order, once each."""
    if value is None:
        return ()
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, list | tuple) and all(isinstance(v, str) for v in value):
        items = list(value)
    else:
        raise OptionError(f"{name} takes labels or rule names separated by commas; got {value!r}")
    return tuple(dict.fromkeys(item.strip() for item in items if item.strip()))


def _number(value: object) -> float | None:
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None
