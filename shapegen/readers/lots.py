"""Lots from the command line and from files: a width and depth, a polygon, a GeoJSON feature,
an OBJ face.

:func:`read_lot` takes what follows ``--lot``:

- ``12,8`` or ``12x8``: a rectangle, width along x and depth along z (m);
- ``"0,8 12,8 12,0 0,0"``: a polygon, corners ``x,z`` in metres separated by spaces;
- ``lots.geojson`` or ``lots.geojson#ID``: the first Polygon (or one-part MultiPolygon)
  feature of a GeoJSON file, or the one whose ``id`` (or ``id`` property) is ``ID``;
- ``plot.obj``: the first face of an OBJ file, its corners' ``x`` and ``z`` (y up).

A polygon lot is given to :meth:`~shapegen.engine.grammar_api.Grammar.build` as its corners
``(x, z)``, counter-clockwise seen from above (+y) as CityEngine wants them; a ring given the
other way round is reversed, keeping its first corner first (as ``shapegen city`` does), so
the first edge (the lot's front, along which the scope's x axis runs) starts at the corner
given first.

GeoJSON coordinates are longitude/latitude (RFC 7946) when every one lies within +-180 /
+-90 degrees and no ``crs`` member names another system; they are projected onto the WGS84
tangent plane at the centre of the lot's bounding box (:func:`shapegen.export.osm.east_north`;
over a lot, distances agree with geodesic ones far below a millimetre), east along +x and north
along -z. Coordinates that are not longitude/latitude are taken as metres (east, north) and
moved so that the same centre is the origin.

Every mistake is one :class:`~shapegen.errors.InputFormatError` line naming the input.
"""

from __future__ import annotations

__all__ = ["Lot", "checked_polygon", "lot_from_geojson", "lot_from_obj", "read_lot"]

import math
import re
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError

Lot = tuple[float, float] | list[tuple[float, float]]
"""``(width, depth)`` in metres, or a polygon's corners ``[(x, z), ...]`` in metres."""

MERGE_M = 1e-6
"""Consecutive corners closer than this (m) are one corner (a repeated closing corner...)."""
MAX_LONLAT_SPAN_DEG = 0.5
"""A longitude/latitude lot wider than this (about 55 km) is refused as a likely mistake
(metres written without a ``crs`` member)."""


def read_lot(text: str) -> Lot:
    """The lot that ``--lot text`` names (see the module's documentation for the forms)."""
    stripped = text.strip()
    path, _, feature = stripped.partition("#")
    suffix = Path(path).suffix.lower()
    if suffix in (".geojson", ".json"):
        return lot_from_geojson(path, feature or None)
    if suffix == ".obj":
        if feature:
            raise InputFormatError(f"--lot {text}: an OBJ lot takes no #ID (its first face)")
        return lot_from_obj(path)
    # "3.4, 3" is WIDTH,DEPTH and "0, 0 12, 0 ..." corners: spaces beside a comma do not separate
    corners = re.sub(r"\s*,\s*", ",", stripped).replace(";", " ").split()
    if len(corners) == 1:
        stripped = corners[0]
        sides = stripped.split(",") if "," in stripped else stripped.lower().split("x")
        if len(sides) != 2:
            raise InputFormatError(
                f"--lot {text!r}: expected WIDTH,DEPTH (m), corners 'x,z x,z x,z ...' (m), "
                "a .geojson file or an .obj file"
            )
        width, depth = (_number(v.strip(), text) for v in sides)
        if width <= 0 or depth <= 0:
            raise InputFormatError(f"--lot {text!r}: lot sides must be > 0 m")
        return width, depth
    points = []
    for corner in corners:
        parts = corner.split(",")
        if len(parts) != 2:
            raise InputFormatError(f"--lot {text!r}: a corner is x,z in metres, got {corner!r}")
        points.append(tuple(_number(v, text) for v in parts))
    return checked_polygon(points, f"--lot {text!r}")


def _number(raw: str, text: str) -> float:
    try:
        value = float(raw)
    except ValueError:
        raise InputFormatError(f"--lot {text!r}: {raw!r} is not a number") from None
    if not math.isfinite(value):
        raise InputFormatError(f"--lot {text!r}: coordinates must be finite numbers, got {raw}")
    return value


def checked_polygon(points, source: str) -> list[tuple[float, float]]:
    """``points`` ``(x, z)`` (m) as a lot: repeated corners dropped, at least 3 corners, finite,
    not crossing itself, with an area, counter-clockwise seen from above (+y; a clockwise ring
    is reversed keeping its first corner). ``source`` names the input in errors."""
    ring = np.asarray(points, dtype=float).reshape(-1, 2) if len(points) else np.zeros((0, 2))
    if not np.all(np.isfinite(ring)):
        raise InputFormatError(f"{source}: corner coordinates must be finite numbers")
    keep = [0] if len(ring) else []
    for k in range(1, len(ring)):
        if np.hypot(*(ring[k] - ring[keep[-1]])) > MERGE_M:
            keep.append(k)
    ring = ring[keep]
    if len(ring) > 1 and np.hypot(*(ring[-1] - ring[0])) <= MERGE_M:
        ring = ring[:-1]
    if len(ring) < 3:
        raise InputFormatError(
            f"{source}: a lot needs at least 3 distinct corners, got {len(ring)}"
        )
    import shapely  # a polygon lot's check; a WIDTH,DEPTH lot needs none

    polygon = shapely.Polygon(ring)
    spread = np.linalg.svd(ring - ring.mean(axis=0), compute_uv=False)
    if spread[1] <= 1e-9 * spread[0]:
        raise InputFormatError(f"{source}: the polygon has no area (its corners are in a line)")
    if not polygon.is_valid:
        raise InputFormatError(f"{source}: the polygon crosses itself ({_why(polygon)})")
    # In (x, z) with y up, a ring counter-clockwise seen from above has a negative shoelace sum.
    x, z = ring[:, 0], ring[:, 1]
    if float(np.dot(x, np.roll(z, -1)) - np.dot(np.roll(x, -1), z)) > 0:
        ring = np.roll(ring[::-1], 1, axis=0)  # reversed, the first corner kept first
    return [(float(a), float(b)) for a, b in ring]


def _why(polygon) -> str:
    """shapely's reason, its point written as x and z: ``self-intersection at x=1, z=0.5``."""
    import shapely

    reason = shapely.is_valid_reason(polygon)
    point = re.compile(r"\[([-\d.e+]+) ([-\d.e+]+)\]")
    return point.sub(lambda m: f" at x={float(m[1]):g}, z={float(m[2]):g}", reason).lower()


# ------------------------------------------------------------------------------ GeoJSON
def lot_from_geojson(path: str | Path, feature_id: str | None = None) -> list[tuple[float, float]]:
    """The lot of a GeoJSON file: its first Polygon or MultiPolygon feature (a FeatureCollection,
    a Feature or a bare geometry), or the feature whose ``id`` or ``id`` property is
    ``feature_id``; in local metres (see the module's documentation)."""
    from shapegen.export.blocks_json import parse_json_document, read_model_bytes

    path = Path(path)
    where = f"--lot {path}" + (f"#{feature_id}" if feature_id else "")
    if not path.is_file():
        raise InputFormatError(f"{where}: no such file")
    try:
        document = parse_json_document(read_model_bytes(path), str(path))
    except InputFormatError as exc:
        raise InputFormatError(f"--lot {exc}") from None
    features = _features(document, where)
    if feature_id is not None:
        chosen = [f for f in features if _feature_id(f) == feature_id]
        if not chosen:
            known = [i for i in (_feature_id(f) for f in features) if i is not None][:8]
            listed = ", ".join(known) if known else "none has an id"
            raise InputFormatError(f"{where}: no feature with id {feature_id!r} ({listed})")
    else:
        chosen = [f for f in features if _polygon_rings(f.get("geometry")) is not None]
        if not chosen:
            raise InputFormatError(f"{where}: no Polygon or MultiPolygon feature")
    feature = chosen[0]
    rings = _polygon_rings(feature.get("geometry"), where)
    if rings is None:
        kind = (feature.get("geometry") or {}).get("type")
        raise InputFormatError(f"{where}: the feature is a {kind}, not a Polygon")
    if len(rings) > 1:
        raise InputFormatError(
            f"{where}: the polygon has {len(rings) - 1} hole(s); a lot is one ring"
        )
    corners = rings[0]
    if not all(_is_point(p) for p in corners):
        raise InputFormatError(f"{where}: a corner is not two finite numbers")
    points = np.array([p[:2] for p in corners], dtype=float)
    if len(points) == 0:
        raise InputFormatError(f"{where}: the polygon has no corners")
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    if _is_lonlat(document, points):
        span = float(np.ptp(points, axis=0).max())
        if span > MAX_LONLAT_SPAN_DEG:
            raise InputFormatError(
                f"{where}: read as longitude/latitude, the lot spans {span:g} degrees; if its "
                'coordinates are metres, say so with a "crs" member naming the projection'
            )
        from shapegen.export.osm import east_north

        local = east_north(points[:, 1], points[:, 0], centre[1], centre[0])
    else:
        local = points - centre
    # east -> +x, north -> -z (y up)
    return checked_polygon(np.column_stack([local[:, 0], -local[:, 1]]), where)


def _features(document: object, where: str) -> list[dict]:
    if not isinstance(document, dict):
        raise InputFormatError(f"{where}: not a GeoJSON object")
    kind = document.get("type")
    if kind == "FeatureCollection":
        features = document.get("features")
        if not isinstance(features, list):
            raise InputFormatError(f'{where}: "features" must be a list')
        return [f for f in features if isinstance(f, dict)]
    if kind == "Feature":
        return [document]
    if kind in ("Polygon", "MultiPolygon"):
        return [{"type": "Feature", "geometry": document}]
    raise InputFormatError(f"{where}: not GeoJSON (type {kind!r})")


def _feature_id(feature: dict) -> str | None:
    value = feature.get("id")
    if value is None and isinstance(feature.get("properties"), dict):
        value = feature["properties"].get("id")
    if value is None:
        return None
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    return str(value)


def _polygon_rings(geometry: object, where: str | None = None) -> list | None:
    """The rings of a Polygon (or a MultiPolygon of one part); None for another geometry."""
    if not isinstance(geometry, dict) or geometry.get("type") not in ("Polygon", "MultiPolygon"):
        return None
    coordinates = geometry.get("coordinates")
    if geometry["type"] == "MultiPolygon":
        if not isinstance(coordinates, list) or len(coordinates) != 1:
            if where is None:
                return []
            parts = len(coordinates) if isinstance(coordinates, list) else 0
            raise InputFormatError(
                f"{where}: a MultiPolygon of {parts} parts; a lot is one polygon"
            )
        coordinates = coordinates[0]
    if not isinstance(coordinates, list) or not coordinates:
        if where is None:
            return []
        raise InputFormatError(f"{where}: the polygon has no coordinates")
    if not all(isinstance(ring, list) for ring in coordinates):
        if where is None:
            return []
        raise InputFormatError(f"{where}: a polygon's rings must be lists of corners")
    return coordinates


def _is_point(p) -> bool:
    return (
        isinstance(p, list)
        and len(p) >= 2
        and all(type(v) in (int, float) for v in p[:2])
        and all(math.isfinite(v) for v in p[:2])
    )


def _is_lonlat(document: dict, points: np.ndarray) -> bool:
    member = document.get("crs")
    if isinstance(member, dict):
        name = str((member.get("properties") or {}).get("name", ""))
        if name and not ("CRS84" in name.upper() or name.endswith((":4326", "::4326"))):
            return False
    return bool(np.all(np.abs(points[:, 0]) <= 180) and np.all(np.abs(points[:, 1]) <= 90))


# ------------------------------------------------------------------------------ OBJ
def lot_from_obj(path: str | Path) -> list[tuple[float, float]]:
    """The first face of an OBJ file as a lot: its corners' ``(x, z)`` (m, y up)."""
    from shapegen.export.blocks_json import read_model_bytes

    path = Path(path)
    where = f"--lot {path}"
    if not path.is_file():
        raise InputFormatError(f"{where}: no such file")
    try:
        text = read_model_bytes(path).decode("utf-8")
    except InputFormatError as exc:
        raise InputFormatError(f"--lot {exc}") from None
    except UnicodeDecodeError:
        raise InputFormatError(f"{where}: not an OBJ text file (invalid UTF-8)") from None
    vertices: list[tuple[float, float]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "v":
            try:
                x, _, z = (float(v) for v in fields[1:4])
            except ValueError:
                raise InputFormatError(f"{where}:{number}: a vertex needs x y z numbers") from None
            vertices.append((x, z))
        elif fields[0] == "f":
            corners = []
            for item in fields[1:]:
                try:
                    index = int(item.split("/")[0])
                except ValueError:
                    raise InputFormatError(f"{where}:{number}: bad face corner {item!r}") from None
                position = index - 1 if index > 0 else len(vertices) + index
                if not 0 <= position < len(vertices):
                    raise InputFormatError(
                        f"{where}:{number}: the face names vertex {index}, which is not defined"
                    )
                corners.append(vertices[position])
            return checked_polygon(corners, f"{where} (its first face)")
    raise InputFormatError(f"{where}: the file has no face")
