"""The settings of a block analysis, as one frozen object checked once.

>>> StaticsOptions(friction=0.5, kern=1 / 3).pyramid
'cone'
>>> StaticsOptions.from_mapping({"frcition": 0.5})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
shapegen.errors.OptionError: unknown statics option 'frcition' (did you mean 'friction'?); ...
"""

from __future__ import annotations

__all__ = [
    "StaticsOptions",
    "SOLVERS",
    "AUTO_ORDER",
    "PYRAMIDS",
    "DEFAULT_PYRAMID",
    "Reserve",
    "Tilt",
    "checked_azimuth",
    "checked_kern",
    "checked_pyramid",
    "statics_field",
    "statics_fields",
]

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

from shapegen.errors import OptionError, did_you_mean
from shapegen.model.friction import checked_friction
from shapegen.statics.solvers import BACKENDS, cone_refusal, takes_cones

AUTO_ORDER = ("reduced", "clarabel")
"""``solver="auto"``: the fastest back-end first, the next if it fails (for the exact cone, only
those that declare they take cones; every bundled one does)."""

PYRAMIDS = ("cone", "4", "4r", "8")
"""Friction models: the exact cone (a second-order cone: the verdict does not turn with the
model), or pyramids inscribed in the Coulomb cone (4, 4 turned by 45 degrees, 8 sides)."""
DEFAULT_PYRAMID = "cone"
"""The exact Coulomb cone: Coulomb's law itself, whose verdict does not depend on how the model
is turned; the pyramids (the papers' linearisation, inside the cone and so on the safe side)
stay options."""
SOLVERS = ("auto", *BACKENDS)
"""Valid values of :attr:`StaticsOptions.solver`."""


def _option(default, kind: str, help: str, **more):
    """A field with what a front end needs to offer it: its kind (``number``, ``choice`` with
    ``choices``, ``labels``, ``tilt``; ``azimuth`` is given with the tilt), its one-line help
    and a ``metavar``. The field checks its value itself, in ``__post_init__``."""
    return dataclasses.field(default=default, metadata={"kind": kind, "help": help, **more})


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

    friction: float | None = _option(
        None, "number", "friction coefficient of every joint (default: the model's, 0.7)",
        metavar="MU",
    )  # fmt: skip
    pyramid: str = _option(
        DEFAULT_PYRAMID, "choice",
        "friction model: the exact Coulomb cone, whose verdict does not turn with the model"
        " (default), or a pyramid inside it as the papers use: 4 sides, 4 rotated 45 degrees,"
        " 8 sides",
        choices=PYRAMIDS,
    )  # fmt: skip
    kern: float = _option(
        1.0, "number",
        "scale every joint about its centroid by K, a geometric factor of safety (1 = none,"
        " 1/3 = middle third; default 1)",
        metavar="K",
    )  # fmt: skip
    solver: str = _option("auto", "choice", "QP back-end (default auto)", choices=SOLVERS)
    tilt: float = _option(
        0.0, "tilt",
        "judge the design with gravity tilted by DEG degrees (below 90) towards AZIMUTH,"
        " degrees in the ground plane from +x towards +z (default: the worst direction"
        " found), as on a tilting table; with --optimize, find a design that stands so tilted",
        metavar="DEG[@AZIMUTH]",
    )  # fmt: skip
    azimuth: float | None = _option(None, "azimuth", "given with the tilt: DEG@AZIMUTH")
    structural: tuple[str, ...] = _option(
        (), "labels",
        "only the blocks with one of these labels or rule names are structure; the other"
        " blocks ride as load on the body they rest on (default: every block, or the rule's"
        ' @Structure("blocks", structural=...))',
        metavar="LABEL,...",
    )  # fmt: skip
    ignore: tuple[str, ...] = _option(
        (), "labels",
        "blocks with one of these labels or rule names are ornaments: their weight rides on"
        " the body they rest on, unjudged (default: none, or the rule's"
        ' @Structure("blocks", ignore=...))',
        metavar="LABEL,...",
    )  # fmt: skip

    def __post_init__(self) -> None:
        for name in ("structural", "ignore"):
            object.__setattr__(self, name, _labels(getattr(self, name), name))
        checked_pyramid(self.pyramid)
        if self.solver not in SOLVERS:
            raise OptionError(
                f"solver must be one of {', '.join(SOLVERS)}; got {self.solver!r}", "solver"
            )
        if not self.backends():
            raise OptionError(cone_refusal(self.solver), "solver")
        object.__setattr__(self, "kern", checked_kern(self.kern))
        if self.friction is not None:
            object.__setattr__(self, "friction", checked_friction(self.friction))
        tilt = Tilt(self.tilt, self.azimuth)  # the tilt's one check
        object.__setattr__(self, "tilt", tilt.degrees)
        object.__setattr__(self, "azimuth", tilt.azimuth)

    @classmethod
    def from_mapping(cls, settings: Mapping[str, object]) -> StaticsOptions:
        """Options from ``name -> value``; an unknown name is an error with a suggestion."""
        names = [f.name for f in dataclasses.fields(cls)]
        for name in settings:
            if name not in names:
                hint = did_you_mean(name, names, parenthesised=True)
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


class Reserve(float):
    """The reserve ``M`` in [0, 1) a design is judged with: for block statics every joint shrunk
    about its centroid and the friction coefficient lowered to ``1 - M`` of themselves
    (:func:`~shapegen.statics.reserve.with_reserve`), for cables the diameter limit lowered to
    ``1 - M`` of itself; 0 is none. A number, checked once, when made, where a margin is given
    (``--margin`` and the other fields of
    :class:`~shapegen.search.search_options.SearchOptions`, the design page's ``"margin"``, a
    library call), and passed inward as it is: :meth:`of` takes a ``Reserve`` without looking at
    it again. Its refusal is one
    :class:`~shapegen.errors.OptionError` naming ``margin``.

    >>> Reserve(0.1) * 2
    0.2
    >>> Reserve.of(Reserve(0.1)) == 0.1, bool(Reserve())
    (True, False)
    >>> Reserve(1)
    Traceback (most recent call last):
    ...
    shapegen.errors.OptionError: margin must be at least 0 and below 1; got 1
    """

    __slots__ = ()

    def __new__(cls, margin: object = 0.0) -> Reserve:
        if isinstance(margin, bool) or not isinstance(margin, int | float):
            raise OptionError(f"margin must be a number in [0, 1); got {margin!r}", "margin")
        if not 0.0 <= margin < 1.0:
            raise OptionError(f"margin must be at least 0 and below 1; got {margin:g}", "margin")
        return super().__new__(cls, margin)

    @classmethod
    def of(cls, margin: object) -> Reserve:
        """``margin`` as a reserve: a :class:`Reserve` as it is (checked when it was made),
        anything else checked now."""
        return margin if isinstance(margin, Reserve) else cls(margin)


@dataclass(frozen=True)
class Tilt:
    """The tilting-table test (:mod:`shapegen.statics.tilt`): every load turned by ``degrees``
    in [0, 90) towards ``azimuth``, degrees in the ground plane from +x towards +z (normalised
    to [0, 360); None: the worst direction). Checked once, when made, wherever a tilt is given
    (``--tilt DEG[@AZIMUTH]`` through :meth:`parse`, :class:`StaticsOptions`' ``tilt`` and
    ``azimuth``); its refusal is one :class:`~shapegen.errors.OptionError` naming ``tilt`` or
    ``azimuth``.

    >>> Tilt.parse("20@-90")
    Tilt(degrees=20.0, azimuth=270.0)
    """

    degrees: float = 0.0
    azimuth: float | None = None

    def __post_init__(self) -> None:
        degrees = _number(self.degrees)
        if degrees is None or not 0 <= degrees < 90:
            hint = ""
            if degrees is not None and degrees < 0:
                hint = f"; to tilt the other way add 180 to the azimuth ({-degrees:g}@180)"
            raise OptionError(
                f"tilt must be a number of degrees, at least 0 and below 90; got"
                f" {self.degrees!r}{hint}",
                "tilt",
            )
        object.__setattr__(self, "degrees", degrees)
        if self.azimuth is not None:
            object.__setattr__(self, "azimuth", checked_azimuth(self.azimuth))

    @classmethod
    def parse(cls, text: str) -> Tilt:
        """``DEG`` or ``DEG@AZIMUTH`` (degrees), as ``--tilt`` takes it."""
        degrees, sep, azimuth = text.partition("@")
        try:
            degrees = float(degrees)
        except ValueError:
            raise OptionError(
                f"expected DEG or DEG@AZIMUTH (degrees), got {text!r}", "tilt"
            ) from None
        if not sep:
            return cls(degrees)
        try:
            return cls(degrees, float(azimuth))
        except ValueError:
            raise OptionError(
                f"the azimuth {azimuth.strip()!r} in {text!r} is not a number of degrees",
                "azimuth",
            ) from None


def checked_azimuth(azimuth: object) -> float:
    """A direction in the ground plane, degrees from +x towards +z, normalised to [0, 360), or
    an :class:`~shapegen.errors.OptionError` naming ``azimuth``: its one check (a tilt's
    direction, ``--capacity``'s)."""
    number = _number(azimuth)
    if number is None:
        raise OptionError(f"azimuth must be a finite number of degrees; got {azimuth!r}", "azimuth")
    from shapegen.statics.tilt import normalized_azimuth

    return normalized_azimuth(number)


def checked_pyramid(pyramid: object) -> str:
    """The friction model ``pyramid``, one of :data:`PYRAMIDS`, or an
    :class:`~shapegen.errors.OptionError`: its one check (the options, an assembly's
    arguments, a friction cone's rows)."""
    if pyramid not in PYRAMIDS:
        raise OptionError(
            f"pyramid must be one of {', '.join(PYRAMIDS)}; got {pyramid!r}", "pyramid"
        )
    return pyramid


def checked_kern(kern: object) -> float:
    """The joint scale ``kern``, a number in (0, 1], or an :class:`~shapegen.errors.OptionError`:
    its one check (the options, an assembly's arguments)."""
    number = _number(kern)
    if number is None or not 0 < number <= 1:
        raise OptionError(f"kern must be a number in (0, 1]; got {kern!r}", "kern")
    return number


def statics_fields() -> tuple[dataclasses.Field, ...]:
    """The options, in order, each with ``metadata`` ``kind``, ``help`` and its ``choices`` or
    ``metavar`` (how the command line makes its flags)."""
    return dataclasses.fields(StaticsOptions)


def statics_field(name: str) -> dataclasses.Field:
    """The field of option ``name``."""
    return next(f for f in statics_fields() if f.name == name)


def _labels(value: object, name: str) -> tuple[str, ...]:
    """Labels or rule names from ``"A,B"`` or a sequence of strings, in order, once each."""
    if value is None:
        return ()
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, list | tuple) and all(isinstance(v, str) for v in value):
        items = list(value)
    else:
        raise OptionError(
            f"{name} takes labels or rule names separated by commas; got {value!r}", name
        )
    return tuple(dict.fromkeys(item.strip() for item in items if item.strip()))


def _number(value: object) -> float | None:
    if isinstance(value, bool):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None
