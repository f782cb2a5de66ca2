"""Lots of a city: polygons read from GeoJSON or OpenStreetMap buildings, in one local metric frame.

A :class:`Lot` is one footprint: its id, its outer ring in metres (east, north) about the city's
origin, counter-clockwise seen from above, and the properties of the feature it came from (which
override the rule's attrs of the same names, as CityEngine maps object attributes).

Coordinates. A GeoJSON file holds longitude/latitude (RFC 7946) or projected metres; which is
detected (a ``crs`` member naming WGS84, or every coordinate within +-180 / +-90 degrees, means
longitude/latitude) or given (``crs="lonlat"`` or ``crs="metres"``). Longitude/latitude is
projected onto the WGS84 tangent plane at the centre of the lots' bounding box
(:func:`shapegen.readers.projection.east_north`: over a few kilometres distances agree with geodesic
ones to 1e-7); projected metres are moved so that the same centre is the origin. The origin is
recorded in the outputs so that results can be put back on a map. In shapegen's frame east is
+x, up +y and north -z.

A feature that cannot be a lot (fewer than three distinct corners, a self-crossing ring, no
area, a hole) is kept as a lot with a ``problem``: the run records it as a failed row instead
of stopping.
"""

from __future__ import annotations

__all__ = ["CRS_CHOICES", "City", "Lot", "city_from_polygons", "read_lots"]

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.readers import geojson
from shapegen.readers.osm import read_buildings

CRS_CHOICES = ("lonlat", "metres")
# Corners closer than this are one corner, m.
_MERGE_M = 1e-3
# Smallest lot area built, m^2.
_MIN_AREA_M2 = 0.01
# Widest lot built, m: wider is a mistake of units (metres near the origin read as degrees).
_MAX_LOT_M = 5000.0


@dataclass(frozen=True)
class Lot:
    """One footprint.

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
    geometry
        The GeoJSON geometry as read (input coordinates), for the results table.
    problem
        Why it cannot be built (the row's error), or None.
    """

    id: str
    ring: np.ndarray
    properties: dict = field(default_factory=dict)
    geometry: dict | None = None
    problem: str | None = None

    @property
    def area(self) -> float:
        """Area of the footprint, m^2."""
        x, y = self.ring[:, 0], self.ring[:, 1]
        return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


@dataclass(frozen=True)
class City:
    """The lots of one input and the frame they are in.

    Attributes
    ----------
    lots
        In input order.
    crs
        ``"lonlat"`` or ``"metres"``: the input's coordinates.
    origin
        The local frame's origin in input coordinates: ``(lon, lat)`` degrees or ``(x, y)`` m.
    skipped
        Features that are not polygons (points, lines), counted, not read.
    source
        The file read, or ``""``.
    """

    lots: list[Lot]
    crs: str
    origin: tuple[float, float]
    skipped: int = 0
    source: str = ""

    def frame(self) -> dict:
        """How the local frame relates to the input's coordinates (for the outputs)."""
        projection = (
            "WGS84 local tangent plane at the origin"
            if self.crs == "lonlat"
            else "input metres less the origin"
        )
        return {
            "crs": self.crs,
            "origin": list(self.origin),
            "projection": projection,
            "axes": "east +x, up +y, north -z (m)",
        }


# ------------------------------------------------------------------------------ reading
def read_lots(path: str | Path, crs: str | None = None) -> City:
    """Read the lots of a GeoJSON FeatureCollection (``.geojson``/``.json``) or of the buildings
    of an OSM XML file (``.osm``: closed ways tagged ``building``).

    Raises
    ------
    InputFormatError
        One line naming the file: unreadable, not GeoJSON (or OSM XML), no polygon, two lots
        with one id, an unknown or unconfirmed coordinate system.
    """
    path = Path(path)
    if crs is not None and crs not in CRS_CHOICES:
        raise InputFormatError(f"--crs {crs}: expected one of {', '.join(CRS_CHOICES)}")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    head = data[:512].lstrip()
    if path.suffix.lower() == ".osm" or head.startswith(b"<"):
        if crs == "metres":
            raise InputFormatError(f"{path}: OSM nodes are longitude/latitude; --crs metres")
        features, skipped = read_buildings(path)
        return _city(features, "lonlat", skipped, str(path))
    try:
        document = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        where = f":{exc.lineno}:{exc.colno}" if isinstance(exc, json.JSONDecodeError) else ""
        raise InputFormatError(
            f"{path}{where}: not a GeoJSON file (invalid JSON) nor OSM XML"
        ) from None
    features = geojson.features(document, str(path))
    declared = geojson.declared_crs(document.get("crs"))
    polygons = [f for f in features if geojson.is_polygon(f)]
    skipped = len(features) - len(polygons)
    if declared is not None and declared != "lonlat" and crs != "metres":
        raise InputFormatError(
            f"{path}: its crs is {declared!r}; give --crs metres if its units are metres"
            " (other units are not read)"
        )
    if declared == "lonlat" and crs == "metres":
        raise InputFormatError(f"{path}: its crs member says WGS84 longitude/latitude, not metres")
    if crs is None:
        crs = declared or _detected_crs(polygons)
    return _city(polygons, crs, skipped, str(path))


def city_from_polygons(
    polygons,
    *,
    ids=None,
    properties=None,
    crs: str = "metres",
) -> City:
    """A city from Python data: ``polygons`` are sequences of ``(x, y)`` corners (metres, or
    ``(lon, lat)`` with ``crs="lonlat"``), any orientation; ``ids`` default to ``#1``, ``#2``...;
    ``properties`` a dict per lot."""
    if crs not in CRS_CHOICES:
        raise InputFormatError(f"crs {crs!r}: expected one of {', '.join(CRS_CHOICES)}")
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
    return _city(features, crs, 0, "")


def _detected_crs(features: list[dict]) -> str:
    """``lonlat`` when every corner of every lot lies within +-180 / +-90 degrees."""
    for feature in features:
        if not geojson.within_lonlat(geojson.positions(feature["geometry"])):
            return "metres"
    return "lonlat"


def _city(features: list[dict], crs: str, skipped: int, source: str) -> City:
    if not features:
        where = f"{source}: " if source else ""
        raise InputFormatError(f"{where}no polygons to use as lots")
    points = np.concatenate([geojson.positions(f["geometry"]) for f in features])
    if len(points) == 0:
        raise InputFormatError(f"{source or 'lots'}: no polygon has a valid corner")
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (lo + hi)
    if crs == "metres":
        centre = np.round(centre)  # whole metres, so the origin reads cleanly
    origin = (float(centre[0]), float(centre[1]))
    lots: list[Lot] = []
    seen: set[str] = set()
    for number, feature in enumerate(features, start=1):
        properties = feature.get("properties")
        properties = dict(properties) if isinstance(properties, dict) else {}
        lot_id = geojson.feature_id(feature) or f"#{number}"
        if lot_id in seen:
            raise InputFormatError(f"{source or 'lots'}: two lots have the id {lot_id!r}")
        seen.add(lot_id)
        ring, problem = _ring(feature["geometry"], crs, origin)
        lots.append(Lot(lot_id, ring, properties, feature["geometry"], problem))
    return City(lots, crs, origin, skipped, source)


def _ring(geometry: dict, crs: str, origin: tuple[float, float]) -> tuple[np.ndarray, str | None]:
    """The outer ring in local metres, counter-clockwise and cleaned, and what is wrong with it."""
    points, problem = geojson.outer_ring(geometry)
    if problem is not None:
        return np.zeros((0, 2)), problem
    if crs == "lonlat" and not geojson.within_lonlat(points):
        return np.zeros((0, 2)), "a corner outside longitude -180..180 / latitude -90..90"
    ring = geojson.distinct_corners(geojson.local_metres(points, crs == "lonlat", origin), _MERGE_M)
    if len(ring) < 3:
        return ring, f"a polygon of {len(ring)} distinct corner(s); a lot needs 3"
    span = float(np.max(np.ptp(ring, axis=0)))
    if span > _MAX_LOT_M:
        hint = "; are its coordinates metres? (--crs metres)" if crs == "lonlat" else ""
        return ring, f"a lot {span / 1000:.4g} km across (at most {_MAX_LOT_M / 1000:g} km){hint}"
    from shapely.geometry import Polygon

    shape = Polygon(ring)
    if not shape.is_valid:
        return ring, "a self-crossing polygon"
    if shape.area < _MIN_AREA_M2:
        return ring, f"a polygon of {shape.area:.3g} m^2 (at least {_MIN_AREA_M2} m^2)"
    if not shape.exterior.is_ccw:
        ring = ring[::-1]
        ring = np.roll(ring, 1, axis=0)  # keep the first corner first
    return ring, None
