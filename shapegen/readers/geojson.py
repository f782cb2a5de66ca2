"""GeoJSON (RFC 7946) as shapegen reads it: features, their ids, their outer rings, the
coordinate system, and corners in local metres. Lots (:mod:`shapegen.readers.lot_sources`)
and cities (:mod:`shapegen.city.city_lots`) both read through here, so both accept the same
input.

Coordinates are longitude/latitude unless a ``crs`` member (or a ``.prj``) names another system
(:mod:`shapegen.readers.crs` takes those to longitude/latitude); WGS84 positions are projected
onto the tangent plane at an origin (:func:`~shapegen.readers.projection.east_north`), local
metres are moved so that the origin is 0.
"""

from __future__ import annotations

__all__ = [
    "feature_id",
    "features",
    "is_finite",
    "is_point",
    "is_polygon",
    "local_metres",
    "polygon_rings",
    "positions",
    "within_lonlat",
]

import json
import math

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.readers.projection import east_north

POLYGONS = ("Polygon", "MultiPolygon")


def features(document: object, where: str) -> list[dict]:
    """The features of a FeatureCollection, a Feature, or a bare Polygon or MultiPolygon (as
    one feature without properties). ``where`` names the input in errors."""
    kind = document.get("type") if isinstance(document, dict) else type(document).__name__
    if kind == "FeatureCollection":
        found = document.get("features")
        if not isinstance(found, list) or not all(isinstance(f, dict) for f in found):
            raise InputFormatError(f"{where}: 'features' must be a list of Feature objects")
        return found
    if kind == "Feature":
        return [document]
    if kind in POLYGONS:
        return [{"type": "Feature", "geometry": document}]
    raise InputFormatError(
        f"{where}: not GeoJSON (type {kind!r}; expected a FeatureCollection, a Feature or a"
        " Polygon)"
    )


def feature_id(feature: dict) -> str | None:
    """The feature's ``id``, else its ``id`` property, as text (``7.0`` reads ``7``); None
    without one."""
    value = feature.get("id")
    if value is None and isinstance(feature.get("properties"), dict):
        value = feature["properties"].get("id")
    if value is None:
        return None
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    return str(value)


def is_polygon(feature: dict) -> bool:
    """Whether the feature's geometry is a Polygon or a MultiPolygon."""
    geometry = feature.get("geometry")
    return isinstance(geometry, dict) and geometry.get("type") in POLYGONS


def is_finite(geometry: object) -> bool:
    """Whether every number of a geometry is finite (JSON can hold it: NaN and inf read from
    ``NaN``/``Infinity`` cannot be written back as GeoJSON nor as WKB)."""
    try:
        json.dumps(geometry, allow_nan=False)
    except (ValueError, TypeError, RecursionError):
        return False
    return True


def within_lonlat(points: np.ndarray) -> bool:
    """Whether every ``(lon, lat)`` lies within +-180 / +-90 degrees."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    return bool(np.all(np.abs(points[:, 0]) <= 180) and np.all(np.abs(points[:, 1]) <= 90))


def polygon_rings(geometry: object) -> tuple[list[np.ndarray] | None, str | None]:
    """The rings of a Polygon (or a MultiPolygon of one part), each ``(k, 2)`` corners, the
    outer ring first and then its holes (RFC 7946's interior rings), and None; or None and
    why it is not one lot (a phrase)."""
    if not isinstance(geometry, dict) or geometry.get("type") not in POLYGONS:
        kind = geometry.get("type") if isinstance(geometry, dict) else None
        return None, f"a {kind}, not a Polygon"
    coordinates = geometry.get("coordinates")
    if geometry["type"] == "MultiPolygon":
        if not isinstance(coordinates, list) or len(coordinates) != 1:
            parts = len(coordinates) if isinstance(coordinates, list) else 0
            return None, f"a MultiPolygon of {parts} parts; a lot is one polygon"
        coordinates = coordinates[0]
    if not isinstance(coordinates, list) or not coordinates:
        return None, "a polygon without coordinates"
    if not all(isinstance(ring, list) for ring in coordinates):
        return None, "a polygon whose rings are not lists of corners"
    rings = []
    for corners in coordinates:
        if not corners:
            return None, "a polygon without corners"
        if not all(is_point(p) for p in corners):
            return None, "a corner that is not two finite numbers"
        rings.append(np.array([p[:2] for p in corners], dtype=float))
    return rings, None


def positions(geometry: object) -> np.ndarray:
    """``(k, 2)`` every valid position of every ring of a Polygon or MultiPolygon, holes and
    parts included (what a frame's origin and the coordinate system are judged from)."""
    if not isinstance(geometry, dict) or geometry.get("type") not in POLYGONS:
        return np.zeros((0, 2))
    coordinates = geometry.get("coordinates")
    polygons = coordinates if geometry["type"] == "MultiPolygon" else [coordinates]
    found = [
        p[:2]
        for polygon in (polygons if isinstance(polygons, list) else [])
        for ring in (polygon if isinstance(polygon, list) else [])
        for p in (ring if isinstance(ring, list) else [])
        if is_point(p)
    ]
    return np.array(found, dtype=float).reshape(-1, 2)


def is_point(p: object) -> bool:
    """Whether ``p`` is a GeoJSON position: at least two finite numbers (booleans are not)."""
    return (
        isinstance(p, list | tuple)
        and len(p) >= 2
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in p[:2])
        and all(math.isfinite(v) for v in p[:2])
    )


def local_metres(points: np.ndarray, lonlat: bool, origin) -> np.ndarray:
    """``(k, 2)`` east and north (m) about ``origin`` of ``points``: ``(lon, lat)`` degrees
    projected at the origin ``(lon, lat)`` when ``lonlat``, else metres less the origin."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if lonlat:
        return east_north(points[:, 1], points[:, 0], origin[1], origin[0])
    return points - np.asarray(origin, dtype=float)
