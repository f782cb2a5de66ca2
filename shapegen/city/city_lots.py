"""Lots of a city: polygons read from GeoJSON or OpenStreetMap buildings, in one local metric frame.

A :class:`CityLot` is one footprint: its id, its outer ring in metres (east, north) about the city's
origin, counter-clockwise seen from above, its holes (a courtyard: a Polygon's interior rings,
RFC 7946), and the properties of the feature it came from (which override the rule's attrs of
the same names, as CityEngine maps object attributes). A lot with holes is built on a start
shape with those holes, as CityEngine builds on a shape with holes and as ``shapegen build
--lot`` does.

Coordinates. A GeoJSON file holds longitude/latitude (RFC 7946), coordinates in any system that
pyproj knows (named by its ``crs`` member, by a ``.prj`` beside it, or by ``crs="EPSG:2154"``),
or local metres (``crs="metres"``: east and north on the ground, no place on the earth). Without
any of these, every coordinate within +-180 / +-90 degrees means longitude/latitude, else metres.
A projected system is transformed to longitude/latitude (:mod:`shapegen.readers.crs`);
longitude/latitude is projected onto the WGS84 tangent plane at the centre of the lots' bounding
box (:func:`shapegen.readers.projection.east_north`: over a few kilometres distances agree with
geodesic ones to 1e-7), so a lot's metres are ground metres whatever the input's projection;
local metres are moved so that the same centre is the origin. The origin is recorded in the
outputs so that results can be put back on a map. In shapegen's frame east is +x, up +y and
north -z.

A feature that cannot be a lot (fewer than three distinct corners, a self-crossing ring, no
area, holes that cross, a MultiPolygon of several parts) is kept as a lot with a ``problem``:
the run records it as a failed row instead of stopping.
"""

from __future__ import annotations

__all__ = ["CRS_CHOICES", "City", "CityLot", "city_from_polygons", "read_lots"]

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError, LotError
from shapegen.model.lot import Lot
from shapegen.readers import geojson
from shapegen.readers.crs import LONLAT, METRES, InputCrs, parse_crs, resolve_crs
from shapegen.readers.files import is_gzip_file, parse_json_document, read_input_bytes
from shapegen.readers.osm import read_buildings
from shapegen.tolerances import LOT_MERGE_M

CRS_CHOICES = ("lonlat", "metres")
# Smallest lot area built, m^2.
_MIN_AREA_M2 = 0.01
# Widest lot built, m: wider is a mistake of units (metres near the origin read as degrees).
_MAX_LOT_M = 5000.0


@dataclass(frozen=True)
class CityLot:
    """One footprint of a city (its lot to build on is made from its ``ring`` by
    :class:`~shapegen.model.lot.Lot`, the one lot check).

    Attributes
    ----------
    id
        Unique within the city: the feature's ``id``, else its ``id`` property, else ``#n``
        (its position in the file, from 1); OSM buildings are ``way/ID``.
    ring
        ``(k, 2)`` corners, east and north of the city's origin (m), counter-clockwise seen
        from above, the first corner not repeated.
    properties
        The feature's properties (OSM tags), for attrs of the same names.
    holes
        The footprint's holes (courtyards): ``(h, 2)`` rings in the frame of ``ring``, wound
        the other way round (clockwise seen from above), the first corner not repeated.
    warnings
        What was changed in reading it, one line each (its row's warnings): a hole that is not
        inside the footprint is removed, as CityEngine's runtime removes it ("hole(s) outside
        its boundary (removed)", tests/data/prt_city_courtyards.json).
    geometry
        The GeoJSON geometry as read (input coordinates), for the results table; None when it
        holds a number that is not finite (NaN, inf: the lot has a ``problem``).
    problem
        Why it cannot be built (the row's error), or None.
    """

    id: str
    ring: np.ndarray
    properties: dict = field(default_factory=dict)
    geometry: dict | None = None
    problem: str | None = None
    holes: tuple[np.ndarray, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def area(self) -> float:
        """Area of the footprint, its holes taken out, m^2."""
        return sum(_signed_area(ring) for ring in (self.ring, *self.holes))


def _signed_area(ring: np.ndarray) -> float:
    """Area of a ring, m^2: positive counter-clockwise seen from above, negative clockwise."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


@dataclass(frozen=True)
class City:
    """The lots of one input and the frame they are in.

    Attributes
    ----------
    lots
        In input order.
    crs
        The input's coordinates: ``"lonlat"``, ``"metres"`` or a projected system's code
        (``"EPSG:2154"``, else its name).
    origin
        The local frame's origin in input coordinates: ``(lon, lat)`` degrees, ``(x, y)``
        m of the projected system, or ``(x, y)`` local metres.
    skipped
        Features that are not polygons (points, lines), counted, not read.
    source
        The file read, or ``""``.
    origin_lonlat
        The origin as WGS84 ``(lon, lat)`` degrees (the tangent point), None for local metres.
    input_crs
        The input's system in full (:class:`~shapegen.readers.crs.InputCrs`: its WKT).
    """

    lots: list[CityLot]
    crs: str
    origin: tuple[float, float]
    skipped: int = 0
    source: str = ""
    origin_lonlat: tuple[float, float] | None = None
    input_crs: InputCrs | None = None

    def frame(self) -> dict:
        """How the local frame relates to the input's coordinates (for the outputs)."""
        if self.crs == LONLAT:
            projection = "WGS84 local tangent plane at the origin"
        elif self.crs == METRES:
            projection = "input metres less the origin"
        else:
            projection = (
                f"{self.crs} to WGS84 longitude/latitude (pyproj), then the WGS84 local"
                " tangent plane at the origin"
            )
        frame = {
            "crs": self.crs,
            "origin": list(self.origin),
            "projection": projection,
            "axes": "east +x, up +y, north -z (m)",
        }
        if self.origin_lonlat is not None:
            frame["origin_lonlat"] = list(self.origin_lonlat)
        return frame


# ------------------------------------------------------------------------------ reading
def read_lots(path: str | Path, crs: str | None = None) -> City:
    """Read the lots of a GeoJSON FeatureCollection (``.geojson``/``.json``, or gzipped:
    ``.geojson.gz``) or of the buildings of an OSM XML file (``.osm``: closed ways tagged
    ``building``).

    ``crs`` is ``"lonlat"``, ``"metres"`` or any system pyproj reads (``"EPSG:2154"``); without
    it the file's ``crs`` member or the ``.prj`` beside it says, else the coordinates' range.

    Raises
    ------
    InputFormatError
        One line naming the file: unreadable, over ``max_file_bytes`` (a gzipped file once
        inflated: read in a stream that stops there), nested deeper than ``max_json_depth``,
        not GeoJSON (or OSM XML), no polygon, two lots
        with one id, an unknown system, longitude/latitude on another datum than WGS84, an
        unreadable ``.prj``, a ``crs`` that contradicts the file's.
    """
    path = Path(path)
    data = read_input_bytes(path, "lots file", gunzip=True)
    head = data[:512].lstrip()
    if head.startswith(b"<") and is_gzip_file(path):
        raise InputFormatError(f"{path}: gzipped OSM XML is not read; gunzip it first")
    if path.suffix.lower() == ".osm" or head.startswith(b"<"):
        if crs is not None and parse_crs(crs, f"--crs {crs}").name != LONLAT:
            raise InputFormatError(f"{path}: OSM nodes are longitude/latitude; --crs {crs}")
        features, skipped = read_buildings(path)
        return _city(features, InputCrs(LONLAT), skipped, str(path))
    document = parse_json_document(data, str(path), "not a GeoJSON file nor OSM XML")
    features = geojson.features(document, str(path))
    member = document.get("crs") if isinstance(document, dict) else None
    chosen = resolve_crs(member, path, crs)
    polygons = [f for f in features if geojson.is_polygon(f)]
    skipped = len(features) - len(polygons)
    corners = _Corners(polygons)
    if chosen is None:
        chosen = InputCrs(_detected_crs(polygons, corners))
    return _city(polygons, chosen, skipped, str(path), corners)


def city_from_polygons(
    polygons,
    *,
    ids=None,
    properties=None,
    crs: str = "metres",
) -> City:
    """A city from Python data: ``polygons`` are sequences of ``(x, y)`` corners (metres, or
    ``(lon, lat)`` with ``crs="lonlat"``, or coordinates of any system pyproj reads with
    ``crs="EPSG:NNNN"``), any orientation; ``ids`` default to ``#1``, ``#2``...; ``properties``
    a dict per lot."""
    chosen = parse_crs(crs, f"crs {crs!r}")
    polygons = list(polygons)
    ids = list(ids) if ids is not None else [None] * len(polygons)
    props = list(properties) if properties is not None else [{}] * len(polygons)
    if not (len(ids) == len(props) == len(polygons)):
        raise InputFormatError("polygons, ids and properties must be as many")
    features = [
        {
            "type": "Feature",
            "id": lot_id,
            "properties": dict(prop or {}),
            "geometry": {"type": "Polygon", "coordinates": [[list(map(float, p)) for p in poly]]},
        }
        for poly, lot_id, prop in zip(polygons, ids, props, strict=True)
    ]
    return _city(features, chosen, 0, "")


class _Corners:
    """The corners of every feature: the plain polygons' in one array, read at once
    (:func:`~shapegen.city.lot_rings.plain_corners`), the others' feature by feature."""

    def __init__(self, features: list[dict]):
        from shapegen.city.lot_rings import plain_corners

        self.plain, self.points, self.offsets = plain_corners(features)
        others = [
            geojson.positions(f["geometry"])
            for f, plain in zip(features, self.plain.tolist(), strict=True)
            if not plain
        ]
        self.all = np.concatenate([self.points, *others]) if others else self.points


def _detected_crs(features: list[dict], corners: _Corners | None = None) -> str:
    """``lonlat`` when every corner of every lot lies within +-180 / +-90 degrees."""
    corners = corners or _Corners(features)
    return LONLAT if geojson.within_lonlat(corners.all) else METRES


def _city(
    features: list[dict],
    crs: InputCrs,
    skipped: int,
    source: str,
    corners: _Corners | None = None,
) -> City:
    from shapegen.city.lot_rings import plain_rings

    if not features:
        where = f"{source}: " if source else ""
        raise InputFormatError(f"{where}no polygons to use as lots")
    corners = corners or _Corners(features)
    points = corners.all
    if len(points) == 0:
        raise InputFormatError(f"{source or 'lots'}: no polygon has a valid corner")
    origin_lonlat = None
    if crs.projected:
        lonlat = crs.to_lonlat(points)
        lonlat = lonlat[np.all(np.isfinite(lonlat), axis=1)]
        if len(lonlat) == 0:
            raise InputFormatError(
                f"{source or 'lots'}: no corner lies where {crs.name} reaches longitude/latitude"
            )
        centre = 0.5 * (lonlat.min(axis=0) + lonlat.max(axis=0))
        origin_lonlat = (float(centre[0]), float(centre[1]))
        back = crs.from_lonlat(centre[None])[0]
        origin = (float(back[0]), float(back[1]))
    else:
        centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
        if crs.name == METRES:
            centre = np.round(centre)  # whole metres, so the origin reads cleanly
        origin = (float(centre[0]), float(centre[1]))
        if crs.name == LONLAT:
            origin_lonlat = origin
    read = plain_rings(corners.points, corners.offsets, crs, origin_lonlat or origin,
                       _MAX_LOT_M, _MIN_AREA_M2)  # fmt: skip
    found: list = [None] * len(features)
    for k, ring in zip(np.flatnonzero(corners.plain).tolist(), read, strict=True):
        found[k] = ring
    lots: list[CityLot] = []
    seen: set[str] = set()
    for number, feature in enumerate(features, start=1):
        properties = feature.get("properties")
        properties = dict(properties) if isinstance(properties, dict) else {}
        lot_id = geojson.feature_id(feature) or f"#{number}"
        if lot_id in seen:
            raise InputFormatError(f"{source or 'lots'}: two lots have the id {lot_id!r}")
        seen.add(lot_id)
        geometry = feature["geometry"]
        holes, notes = (), ()
        if found[number - 1] is not None:  # a plain polygon, all its numbers finite
            ring, problem = found[number - 1]
        else:
            ring, holes, problem, notes = _rings(geometry, crs, origin_lonlat or origin)
            if not geojson.is_finite(geometry):  # a row with its error, without a shape
                geometry = None
        lots.append(CityLot(lot_id, ring, properties, geometry, problem, holes, notes))
    return City(lots, crs.name, origin, skipped, source, origin_lonlat, crs)


def _rings(
    geometry: dict, crs: InputCrs, origin: tuple[float, float]
) -> tuple[np.ndarray, tuple[np.ndarray, ...], str | None, tuple[str, ...]]:
    """The outer ring in local metres, counter-clockwise and cleaned, its holes (clockwise),
    what is wrong with them, and what was changed (holes outside the ring removed).
    ``origin`` is ``(lon, lat)`` for a system on the earth, else local metres."""
    rings, problem = geojson.polygon_rings(geometry)
    if problem is not None:
        return np.zeros((0, 2)), (), problem, ()
    sizes = [len(ring) for ring in rings]
    points = np.vstack(rings)  # every ring projected in one call
    if crs.projected:
        points = crs.to_lonlat(points)
        if not np.all(np.isfinite(points)):
            problem = f"a corner where {crs.name} reaches no longitude/latitude"
            return np.zeros((0, 2)), (), problem, ()
    if crs.located and not geojson.within_lonlat(points):
        return np.zeros((0, 2)), (), "a corner outside longitude -180..180 / latitude -90..90", ()
    local = geojson.local_metres(points, crs.located, origin)
    ring, *holes = np.split(local, np.cumsum(sizes)[:-1])
    span = float(np.max(np.ptp(ring, axis=0))) if len(ring) else 0.0
    if span > _MAX_LOT_M:
        hint = "; are its coordinates metres? (--crs metres)" if crs.name == LONLAT else ""
        problem = f"a lot {span / 1000:.4g} km across (at most {_MAX_LOT_M / 1000:g} km){hint}"
        return ring, (), problem, ()
    holes, notes = _holes_inside(ring, holes)
    try:  # the one lot check, in (x, z) = (east, -north)
        lot = Lot.polygon(ring * [1.0, -1.0], [hole * [1.0, -1.0] for hole in holes])
    except LotError as exc:
        return ring, (), str(exc), notes
    ring = np.array(lot.corners) * [1.0, -1.0]
    holes = tuple(np.array(hole) * [1.0, -1.0] for hole in lot.holes)
    if lot.area < _MIN_AREA_M2:
        problem = f"a polygon of {lot.area:.3g} m^2 (at least {_MIN_AREA_M2} m^2)"
        return ring, holes, problem, notes
    return ring, holes, None, notes


def _holes_inside(ring: np.ndarray, holes: list) -> tuple[list, tuple[str, ...]]:
    """The ``holes`` that lie inside ``ring`` (on its outline counts), and a warning for the
    others, which CityEngine's runtime removes from an initial shape ("contained: 1 hole(s)
    outside its boundary (removed)") and builds on the rest. A ring the lot check refuses
    (too few corners, crossing itself) is left to it."""
    if not holes:
        return holes, ()
    import shapely

    outline = shapely.Polygon(ring) if len(ring) >= 3 else None
    if outline is None or not outline.is_valid:
        return holes, ()
    inside = [
        hole for hole in holes
        if len(hole) < 3 or not shapely.Polygon(hole).is_valid
        or outline.buffer(LOT_MERGE_M).covers(shapely.Polygon(hole))
    ]  # fmt: skip
    removed = len(holes) - len(inside)
    if not removed:
        return holes, ()
    return inside, (f"{removed} hole(s) outside the lot's outline removed (as CityEngine does)",)
