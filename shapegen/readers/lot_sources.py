"""Lots from the command line and from files: a width and depth, a polygon, a GeoJSON feature,
an OBJ face.

:func:`read_lot` takes what follows ``--lot``:

- ``12,8`` or ``12x8``: a rectangle, width along x and depth along z (m);
- ``"0,8 12,8 12,0 0,0"``: a polygon, corners ``x,z`` in metres separated by spaces; rings
  after a ``|`` are its holes (``"0,8 12,8 12,0 0,0 | 4,3 4,5 8,5 8,3"``: a courtyard);
- ``lots.geojson`` or ``lots.geojson#ID``: the first Polygon (or one-part MultiPolygon)
  feature of a GeoJSON file, or the one whose ``id`` (or ``id`` property) is ``ID``;
- ``plot.obj``: the first face of an OBJ file, its corners' ``x`` and ``z`` (y up).

A polygon lot is given to :meth:`~shapegen.engine.grammar_api.Grammar.build` as its corners
``(x, z)``, counter-clockwise seen from above (+y) as CityEngine wants them; a ring given the
other way round is reversed, keeping its first corner first (as ``shapegen city`` does), so
the first edge (the lot's front, along which the scope's x axis runs) starts at the corner
given first.

GeoJSON coordinates are in the system that a ``crs`` member or a ``.prj`` beside the file
names (any that pyproj knows, :mod:`shapegen.readers.crs`: transformed to longitude/latitude),
else longitude/latitude (RFC 7946) when every one lies within +-180 / +-90 degrees; they are
projected onto the WGS84 tangent plane at the centre of the lot's bounding box
(:mod:`shapegen.readers.geojson`; over a lot, distances agree with geodesic ones far below a
millimetre), east along +x and north along -z. Other coordinates are taken as local metres
(east, north) and moved so that the same centre is the origin.

Every mistake is one :class:`~shapegen.errors.InputFormatError` line naming the input; what
the input holds is checked by the one :class:`~shapegen.model.lot.Lot` check, its line behind
the input's name.
"""

from __future__ import annotations

__all__ = ["checked_polygon", "lot_from_geojson", "lot_from_obj", "read_lot"]

import re
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError, LotError
from shapegen.model.lot import Lot
from shapegen.readers import geojson
from shapegen.readers.crs import file_crs
from shapegen.readers.files import parse_json_document, read_model_bytes
from shapegen.readers.obj import obj_polygons

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
    if suffix and Path(path).is_file():  # not "osm_x.osm" read as WIDTHxDEPTH
        raise InputFormatError(
            f"--lot {text}: a lot is read from a .geojson, .json or .obj file, not a "
            f"{suffix} file (shapegen city reads OSM XML and gzipped GeoJSON)"
        )
    outline, *inner = stripped.split("|")  # a polygon's holes follow it, each after a "|"
    if inner:
        holes = [_corners(ring, text) for ring in inner]
        return checked_polygon(_corners(outline, text), f"--lot {text!r}", holes)
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
        try:
            return Lot.rectangle(width, depth)
        except LotError as exc:
            raise LotError(f"--lot {text!r}: {exc}") from None
    return checked_polygon(_corners(stripped, text), f"--lot {text!r}")


def _corners(ring: str, text: str) -> list[tuple[float, float]]:
    """The ``x,z`` corners (m) of one ring of ``--lot text``."""
    points = []
    for corner in re.sub(r"\s*,\s*", ",", ring).replace(";", " ").split():
        parts = corner.split(",")
        if len(parts) != 2:
            raise InputFormatError(f"--lot {text!r}: a corner is x,z in metres, got {corner!r}")
        points.append(tuple(_number(v, text) for v in parts))
    return points


def _number(raw: str, text: str) -> float:
    try:
        value = float(raw)
    except ValueError:
        raise InputFormatError(f"--lot {text!r}: {raw!r} is not a number") from None
    return value  # finite and in range: the Lot's check


def checked_polygon(points, source: str, holes=()) -> Lot:
    """``points`` ``(x, z)`` (m) as a polygon :class:`~shapegen.model.lot.Lot` (with
    ``holes``, rings of ``(x, z)``), its refusal one line behind ``source``, which names the
    input."""
    try:
        return Lot.polygon(points, holes)
    except LotError as exc:
        raise LotError(f"{source}: {exc}") from None


# ------------------------------------------------------------------------------ GeoJSON
def lot_from_geojson(path: str | Path, feature_id: str | None = None) -> Lot:
    """The lot of a GeoJSON file: its first Polygon or MultiPolygon feature (a FeatureCollection,
    a Feature or a bare geometry), or the feature whose ``id`` or ``id`` property is
    ``feature_id``; in local metres (see the module's documentation)."""
    path = Path(path)
    where = f"--lot {path}" + (f"#{feature_id}" if feature_id else "")
    if not path.is_file():
        raise InputFormatError(f"{where}: no such file")
    try:
        document = parse_json_document(read_model_bytes(path), str(path))
    except InputFormatError as exc:
        raise InputFormatError(f"--lot {exc}") from None
    found = geojson.features(document, where)
    if feature_id is not None:
        chosen = [f for f in found if geojson.feature_id(f) == feature_id]
        if not chosen:
            known = [i for i in map(geojson.feature_id, found) if i is not None][:8]
            listed = ", ".join(known) if known else "none has an id"
            raise InputFormatError(f"{where}: no feature with id {feature_id!r} ({listed})")
    else:
        chosen = [f for f in found if geojson.is_polygon(f)]
        if not chosen:
            raise InputFormatError(f"{where}: no Polygon or MultiPolygon feature")
    rings, problem = geojson.polygon_rings(chosen[0].get("geometry"))
    if problem is not None:
        raise InputFormatError(f"{where}: {problem}")
    sizes = [len(ring) for ring in rings]  # a courtyard's rings are its lot's holes
    points = np.vstack(rings)
    member = document.get("crs") if isinstance(document, dict) else None
    declared = file_crs(member, path, where)
    if declared is not None and declared.projected:
        points = declared.to_lonlat(points)
        if not np.all(np.isfinite(points)):
            raise InputFormatError(f"{where}: a corner where {declared.name} has no lon/lat")
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    lonlat = (declared is None or declared.located) and geojson.within_lonlat(points)
    if lonlat:
        span = float(np.ptp(points, axis=0).max())
        if span > MAX_LONLAT_SPAN_DEG:
            raise InputFormatError(
                f"{where}: read as longitude/latitude, the lot spans {span:g} degrees; if its "
                'coordinates are metres, say so with a "crs" member naming the projection'
            )
    local = geojson.local_metres(points, lonlat, centre)
    # east -> +x, north -> -z (y up)
    flat = np.column_stack([local[:, 0], -local[:, 1]])
    parts = np.split(flat, np.cumsum(sizes)[:-1])
    return checked_polygon(parts[0], where, parts[1:])


# ------------------------------------------------------------------------------ OBJ
def lot_from_obj(path: str | Path) -> Lot:
    """The first face of an OBJ file as a lot: its corners' ``(x, z)`` (m, y up)."""
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
    vertices, faces = obj_polygons(text, where)
    if not faces:
        raise InputFormatError(f"{where}: the file has no face")
    return checked_polygon(vertices[faces[0]][:, [0, 2]], f"{where} (its first face)")
