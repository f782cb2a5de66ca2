"""The lot a derivation starts on: one type, checked once, whatever front end made it.

A :class:`Lot` is either a rectangle, ``width`` along x and ``depth`` along z (m), or a polygon,
its corners ``(x, z)`` in metres, counter-clockwise seen from above (+y), the first corner first
(the lot's front edge, along which the start scope's x axis runs, starts there). It is made at
the edge (``--lot``, the design page's ``"lot"``, a city's footprint, ``Grammar.build(lot=...)``)
and passed down as it is; the derivation trusts it.

A polygon lot may have holes (a courtyard): ``holes``, each a ring of ``(x, z)`` corners inside
the polygon, kept clockwise seen from above (wound against the polygon, as CityEngine's holes
are; a hole given the other way round is reversed keeping its first corner first). It is made
by :meth:`Lot.polygon` with ``holes``, or read from ``{"polygon": [...], "holes": [[...]]}``.

A polygon is cleaned as it is checked: consecutive corners closer than
:data:`~shapegen.tolerances.LOT_MERGE_M` are one corner (a repeated closing corner goes), and
a ring given clockwise is reversed keeping its first corner first (as CityEngine takes a lot
drawn either way). A :class:`MeshLot` is the other start a derivation takes: faces in space,
as PyPRT's initial shapes read from a file (a building's faces, a sloped roof), in world
coordinates (m, y up). What cannot be a lot is one :class:`~shapegen.errors.LotError` line, without
the place it came from: each front end says that in its own words (``--lot '0,0 1,1': ...``,
``"lot": ...``, a city's failed row).

>>> Lot.of((12, 8))
Lot(size=(12.0, 8.0), corners=None, holes=())
>>> Lot.of([(0, 0), (4, 0), (4, 3), (0, 3), (0, 0)]).corners  # clockwise seen from above
((0.0, 0.0), (0.0, 3.0), (4.0, 3.0), (4.0, 0.0))
>>> Lot.polygon([(0, 0), (0, 8), (12, 8), (12, 0)], holes=[[(4, 3), (8, 3), (8, 5), (4, 5)]]).area
88.0
>>> Lot.of([(0, 0), (1, 1)])
Traceback (most recent call last):
...
shapegen.errors.LotError: a lot needs at least 3 distinct corners, got 2
"""

from __future__ import annotations

__all__ = ["Lot", "MeshLot"]

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from shapegen.errors import LotError
from shapegen.limits import LOT_EXTENT_LIMIT_M
from shapegen.tolerances import FLAT_REL, LOT_MERGE_M

_SHAPE = "a lot is (width, depth) in metres or a polygon of 3 or more (x, z) corners in metres"


@dataclass(frozen=True)
class Lot:
    """A rectangle lot (``size``: width along x, depth along z, m) or a polygon lot
    (``corners``: ``(x, z)`` m, counter-clockwise seen from above); exactly one is set. Made
    by :meth:`rectangle`, :meth:`polygon` or :meth:`of`, which check it."""

    size: tuple[float, float] | None = None
    corners: tuple[tuple[float, float], ...] | None = None
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()

    def __post_init__(self):
        if (self.size is None) == (self.corners is None):
            raise LotError(_SHAPE)
        if self.size is not None:
            if self.holes:
                raise LotError("a rectangle lot has no holes: give the polygon with its holes")
            object.__setattr__(self, "size", _checked_size(self.size))
        else:
            object.__setattr__(self, "corners", _checked_corners(self.corners))
            if self.holes:
                holes = tuple(_checked_corners(h, hole=True) for h in self.holes)
                _check_holes(self.corners, holes)
                object.__setattr__(self, "holes", holes)

    @classmethod
    def rectangle(cls, width: float, depth: float) -> Lot:
        """A ``width`` x ``depth`` lot (m, each finite and > 0)."""
        return cls(size=(width, depth))

    @classmethod
    def polygon(cls, corners, holes=()) -> Lot:
        """A polygon lot of ``corners`` ``(x, z)`` (m), either way round, with ``holes``
        (rings of ``(x, z)`` corners inside it, either way round)."""
        return cls(corners=corners, holes=tuple(holes))

    @classmethod
    def of(cls, value) -> Lot:
        """``value`` as a lot: a :class:`Lot` as it is, two numbers as a rectangle, a sequence
        of ``(x, z)`` pairs as a polygon."""
        if isinstance(value, Lot):
            return value
        if isinstance(value, dict) and set(value) <= {"polygon", "holes"} and "polygon" in value:
            holes = value.get("holes") or ()
            if isinstance(holes, str | bytes) or not all(_is_pair_list(h) for h in holes):
                raise LotError(f"a lot's holes are rings of (x, z) corners, got {_shown(holes)}")
            return cls.polygon(value["polygon"], holes)
        if isinstance(value, str | bytes):
            raise LotError(f"{_SHAPE}, got {_shown(value)}")
        try:
            items = list(value)
        except TypeError:
            raise LotError(f"{_SHAPE}, got {_shown(value)}") from None
        if len(items) == 2 and not any(_is_pair(item) for item in items):
            return cls(size=tuple(items))
        if not all(_is_pair(item) for item in items):
            raise LotError(f"{_SHAPE}, got {_shown(value)}")
        return cls(corners=items)

    @property
    def is_polygon(self) -> bool:
        return self.corners is not None

    @property
    def area(self) -> float:
        """The lot's area, m²."""
        if self.size is not None:
            return self.size[0] * self.size[1]
        return _ring_area(self.corners) - sum(_ring_area(hole) for hole in self.holes)

    def to_json(self) -> list | dict:
        """``[width, depth]`` or ``[[x, z], ...]`` (m), or ``{"polygon": [...], "holes":
        [[...], ...]}`` for a lot with holes, as the design page and the reports write a lot;
        :meth:`of` reads it back."""
        if self.size is not None:
            return list(self.size)
        polygon = [list(corner) for corner in self.corners]
        if self.holes:
            return {"polygon": polygon, "holes": [[list(c) for c in h] for h in self.holes]}
        return polygon


def _ring_area(ring) -> float:
    x, z = np.array(ring, dtype=float).T
    return 0.5 * abs(float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)))


def _is_pair_list(ring) -> bool:
    return _is_pair(ring) and all(_is_pair(item) for item in ring)


def _check_holes(corners, holes) -> None:
    """Each hole lies inside the polygon, and no two holes overlap (shapely's validity of the
    polygon with its holes; holes may touch, as shapely allows)."""
    import shapely

    polygon = shapely.Polygon(corners, holes)
    if not polygon.is_valid:
        raise LotError(f"the lot's holes do not fit inside it ({_why(polygon)})")


def _is_pair(item) -> bool:
    return isinstance(item, Sequence | np.ndarray) and not isinstance(item, str)


def _shown(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _number(value) -> float:
    if isinstance(value, bool):
        raise LotError(f"{_SHAPE}, got {value!r}")
    try:
        return float(value)
    except OverflowError:  # an integer past float's range: an infinite size, refused as one
        return math.inf if value > 0 else -math.inf
    except (TypeError, ValueError):
        raise LotError(f"{_SHAPE}, got {_shown(value)}") from None


def _checked_size(size) -> tuple[float, float]:
    width, depth = (_number(v) for v in size)
    if not (math.isfinite(width) and math.isfinite(depth)) or width <= 0 or depth <= 0:
        raise LotError(
            f"lot width and depth must be finite numbers > 0 m, got {width:g} x {depth:g}"
        )
    if max(width, depth) > LOT_EXTENT_LIMIT_M:
        raise LotError(
            f"lot width and depth must be at most {LOT_EXTENT_LIMIT_M:g} m, got "
            f"{width:.3g} x {depth:.3g}"
        )
    return width, depth


def _checked_corners(corners, hole: bool = False) -> tuple[tuple[float, float], ...]:
    try:
        ring = np.array([[_number(x), _number(z)] for x, z in corners], dtype=float)
    except ValueError:
        raise LotError(f"{_SHAPE}, got {_shown(corners)}") from None
    ring = ring.reshape(-1, 2)
    if not np.all(np.isfinite(ring)):
        raise LotError("corner coordinates must be finite numbers")
    # the extent first: the distances between corners 1e308 m apart overflow
    farthest = float(np.abs(ring).max(initial=0.0))
    if farthest > LOT_EXTENT_LIMIT_M:
        raise LotError(
            f"corners must lie within {LOT_EXTENT_LIMIT_M:g} m of the origin, got a coordinate "
            f"of {farthest:.3g} m"
        )
    ring = _distinct(ring)
    what = "a lot's hole" if hole else "a lot"
    if len(ring) < 3:
        raise LotError(f"{what} needs at least 3 distinct corners, got {len(ring)}")
    spread = np.linalg.svd(ring - ring.mean(axis=0), compute_uv=False)
    if spread[1] <= FLAT_REL * spread[0]:
        raise LotError(
            f"{'a hole' if hole else 'the polygon'} has no area (its corners are in a line)"
        )
    import shapely  # a polygon lot's check; a rectangle needs none

    polygon = shapely.Polygon(ring)
    if not polygon.is_valid:
        raise LotError(f"the polygon crosses itself ({_why(polygon)})")
    # In (x, z) with y up, a ring counter-clockwise seen from above has a negative shoelace sum.
    # A hole is kept the other way round (clockwise seen from above), as CityEngine's are.
    x, z = ring[:, 0], ring[:, 1]
    if (float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)) > 0) != hole:
        ring = np.roll(ring[::-1], 1, axis=0)  # reversed, the first corner kept first
    return tuple((float(a), float(b)) for a, b in ring)


def _distinct(ring: np.ndarray) -> np.ndarray:
    """Each run of corners closer than ``LOT_MERGE_M`` kept once; a closing corner that repeats
    the first dropped."""
    if len(ring) == 0:
        return ring
    keep = [0]
    for k in range(1, len(ring)):
        if math.hypot(*(ring[k] - ring[keep[-1]])) > LOT_MERGE_M:
            keep.append(k)
    ring = ring[keep]
    if len(ring) > 1 and math.hypot(*(ring[-1] - ring[0])) <= LOT_MERGE_M:
        ring = ring[:-1]
    return ring


def _why(polygon) -> str:
    """shapely's reason, its point written as x and z: ``self-intersection at x=1, z=0.5``."""
    import shapely

    reason = shapely.is_valid_reason(polygon)
    point = re.compile(r"\[([-\d.e+]+) ([-\d.e+]+)\]")
    return point.sub(lambda m: f" at x={float(m[1]):g}, z={float(m[2]):g}", reason).lower()


@dataclass(frozen=True, eq=False)
class MeshLot:
    """A start of several faces, or of one face that is not level: ``vertices`` ``(n, 3)`` in
    metres (world coordinates, y up) and ``faces`` (each three or more vertex indices, turned
    counter-clockwise seen from its front), as PyPRT reads an initial shape from a file. The
    start scope has x along the first face's first edge and y along its normal."""

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]

    def __post_init__(self):
        vertices = np.asarray(self.vertices, dtype=float)
        if vertices.ndim != 2 or vertices.shape[1:] != (3,) or len(vertices) < 3:
            raise LotError("a mesh lot needs three or more (x, y, z) vertices")
        if not np.all(np.isfinite(vertices)):
            raise LotError("a mesh lot's vertex coordinates must be finite numbers")
        if np.abs(vertices).max() > LOT_EXTENT_LIMIT_M:
            raise LotError(f"a mesh lot reaches beyond {LOT_EXTENT_LIMIT_M:g} m of the origin")
        faces = tuple(tuple(int(i) for i in face) for face in self.faces)
        if not faces or any(len(face) < 3 for face in faces):
            raise LotError("a mesh lot needs faces of three or more corners")
        if any(not 0 <= i < len(vertices) for face in faces for i in face):
            raise LotError(f"a mesh lot's face names a vertex outside its {len(vertices)}")
        object.__setattr__(self, "vertices", vertices)
        object.__setattr__(self, "faces", faces)
