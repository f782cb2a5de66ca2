"""Coordinate systems of GIS files: which one a file's coordinates are in, and those coordinates
taken to WGS84 longitude/latitude.

A file says its system in a GeoJSON ``crs`` member (old-style named CRS:
``urn:ogc:def:crs:EPSG::3857``, ``EPSG:2154``...), in a ``.prj`` file beside it (WKT, as a
shapefile has), or the user says it (``--crs EPSG:2154``). Two more names are shapegen's own:
``lonlat`` (WGS84 longitude/latitude, RFC 7946) and ``metres`` (east and north metres on the
ground in a local frame that has no place on the earth).

Every system that pyproj knows goes one way: its positions are transformed to WGS84
longitude/latitude (pyproj), then projected onto the tangent plane at the city's origin
(:func:`shapegen.readers.projection.east_north`). Distances in the local frame are therefore
ground distances, whatever the projection's own scale (Web Mercator's 1/cos(latitude): one
EPSG:3857 metre is 0.69 m on the ground at 46.4 N). Longitude/latitude on another datum than
WGS84 (ETRS89, NAD83...) is refused rather than read as if it were WGS84.
"""

from __future__ import annotations

__all__ = ["LONLAT", "METRES", "InputCrs", "file_crs", "parse_crs", "resolve_crs"]

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError

LONLAT = "lonlat"
METRES = "metres"
_WGS84_NAMES = ("CRS84", "OGC:1.3:CRS84", "OGC:CRS84", "EPSG:4326", "EPSG::4326", "WGS84")


@dataclass(frozen=True)
class InputCrs:
    """The coordinate system of an input.

    Attributes
    ----------
    name
        ``"lonlat"``, ``"metres"``, or the system's authority code (``"EPSG:2154"``), else its
        name.
    wkt
        The system as WKT for a projected one (what pyproj reads back), else ``""``.
    """

    name: str
    wkt: str = ""

    @property
    def located(self) -> bool:
        """Whether the coordinates have a place on the earth (all but ``metres``)."""
        return self.name != METRES

    @property
    def projected(self) -> bool:
        """Whether positions go through pyproj to reach longitude/latitude."""
        return bool(self.wkt)

    def to_lonlat(self, points) -> np.ndarray:
        """``(k, 2)`` WGS84 longitude/latitude (degrees) of ``(k, 2)`` positions in this system
        (easting first); not finite where the projection has no inverse."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if not self.projected:
            return points
        lon, lat = _transformer(self.wkt, True).transform(points[:, 0], points[:, 1])
        return np.column_stack([lon, lat])

    def from_lonlat(self, points) -> np.ndarray:
        """``(k, 2)`` positions in this system of WGS84 longitude/latitude ``(k, 2)``."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if not self.projected:
            return points
        x, y = _transformer(self.wkt, False).transform(points[:, 0], points[:, 1])
        return np.column_stack([x, y])

    def projjson(self) -> dict | None:
        """The system as PROJJSON (GeoParquet's ``crs``): CRS84 for ``lonlat``, None (unknown)
        for ``metres``."""
        if not self.located:
            return None
        pyproj = _pyproj(self.name)
        crs = pyproj.CRS.from_wkt(self.wkt) if self.projected else pyproj.CRS("OGC:CRS84")
        return crs.to_json_dict()

    def urn(self) -> str | None:
        """The old-style GeoJSON name of a projected system (``urn:ogc:def:crs:EPSG::2154``),
        None when it has no authority code or is not projected."""
        if not self.projected or ":" not in self.name:
            return None
        authority, code = self.name.split(":", 1)
        return f"urn:ogc:def:crs:{authority}::{code}"


def _pyproj(name: str):
    try:
        import pyproj
    except ImportError:
        raise InputFormatError(
            f"coordinates in {name} need pyproj, which is not installed (pip install pyproj)"
        ) from None
    return pyproj


@functools.lru_cache(maxsize=16)
def _transformer(wkt: str, inverse: bool):
    pyproj = _pyproj("a projected system")
    source, target = pyproj.CRS.from_wkt(wkt), pyproj.CRS("OGC:CRS84")
    if not inverse:
        source, target = target, source
    return pyproj.Transformer.from_crs(source, target, always_xy=True)


def parse_crs(text: str, where: str) -> InputCrs:
    """The system that ``text`` names: ``lonlat``, ``metres``, or anything pyproj reads
    (``EPSG:2154``, ``urn:ogc:def:crs:EPSG::3857``, WKT, PROJJSON). ``where`` names the input
    in errors (one line each: unknown, longitude/latitude on another datum, not a map)."""
    text = str(text).strip()
    if text.lower() in (LONLAT, METRES):
        return InputCrs(text.lower())
    if text.upper().replace("URN:OGC:DEF:CRS:", "").endswith(_WGS84_NAMES):
        return InputCrs(LONLAT)
    pyproj = _pyproj(text)
    try:
        crs = pyproj.CRS.from_user_input(text)
    except pyproj.exceptions.CRSError:
        shown = text if len(text) <= 60 else text[:57] + "..."
        raise InputFormatError(
            f"{where}: {shown!r} is not a coordinate system pyproj knows (give EPSG:NNNN, a"
            " WKT .prj, 'lonlat' or 'metres')"
        ) from None
    return _checked(crs, where, text)


def _checked(crs, where: str, text: str = "") -> InputCrs:
    authority = crs.to_authority(min_confidence=90)
    name = f"{authority[0]}:{authority[1]}" if authority else crs.name
    if name == "unknown" and text:  # a proj string's system has no name: show the string
        name = repr(text if len(text) <= 60 else text[:57] + "...")
    if crs.is_geographic:
        datum = crs.datum.name if crs.datum is not None else ""
        if "World Geodetic System 1984" in datum and crs.prime_meridian.longitude == 0:
            return InputCrs(LONLAT)
        raise InputFormatError(
            f"{where}: {name} ({crs.name}) is longitude/latitude on another datum than WGS84;"
            " reproject the file to WGS84 (EPSG:4326) or to a projected system"
        )
    if not crs.is_projected:
        raise InputFormatError(
            f"{where}: {name} ({crs.name}) is not a map projection nor longitude/latitude"
        )
    pyproj = _pyproj(name)
    wkt = crs.to_wkt()
    try:  # made now, so that a system proj cannot invert (+to_meter=1e-300) is this input's line
        if not wkt:
            raise pyproj.exceptions.CRSError("it has no WKT")
        _transformer(wkt, True)
        _transformer(wkt, False)
    except (pyproj.exceptions.CRSError, pyproj.exceptions.ProjError) as exc:
        reason = " ".join(str(exc).split())[:160]
        raise InputFormatError(
            f"{where}: {name} ({crs.name}): pyproj cannot take it to longitude/latitude ({reason})"
        ) from None
    return InputCrs(name, wkt)


def _member_text(member: object, where: str) -> str:
    """The name in a GeoJSON ``crs`` member (``{"type": "name", "properties": {"name": ...}}``,
    or a bare string)."""
    if isinstance(member, str):
        return member
    properties = member.get("properties") if isinstance(member, dict) else None
    name = properties.get("name") if isinstance(properties, dict) else None
    if not isinstance(name, str) or not name.strip():
        raise InputFormatError(
            f"{where}: its crs member names no system (expected"
            ' {"type": "name", "properties": {"name": "EPSG:NNNN"}})'
        )
    return name


def file_crs(member: object, path: str | Path | None, where: str) -> InputCrs | None:
    """The system a file declares: its GeoJSON ``crs`` member, or the ``.prj`` beside ``path``
    (``lots.geojson`` -> ``lots.prj``); None when it declares none. Both, naming different
    systems, are refused."""
    declared = None
    if member is not None:
        declared = parse_crs(_member_text(member, where), f"{where}: crs member")
    beside = prj_crs(Path(path)) if path is not None else None
    if declared is not None and beside is not None and not same_crs(declared, beside):
        raise InputFormatError(
            f"{where}: its crs member says {declared.name} and {Path(path).with_suffix('.prj')}"
            f" says {beside.name}"
        )
    return declared or beside


def prj_crs(path: Path) -> InputCrs | None:
    """The system of the ``.prj`` file beside ``path`` (WKT), or None without one."""
    prj = path.with_suffix(".prj")
    if not prj.is_file():
        return None
    try:
        text = prj.read_text(encoding="utf-8-sig").strip()
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or "not UTF-8 text"
        raise InputFormatError(f"{prj}: cannot read it ({reason})") from None
    pyproj = _pyproj(str(prj))
    try:
        crs = pyproj.CRS.from_wkt(text)
    except pyproj.exceptions.CRSError:
        raise InputFormatError(
            f"{prj}: not a coordinate system in WKT (a .prj beside a file says its system)"
        ) from None
    return _checked(crs, str(prj))


def same_crs(a: InputCrs, b: InputCrs) -> bool:
    """Whether two systems are one (by name, else as pyproj compares them)."""
    if a.name == b.name:
        return True
    if not (a.projected and b.projected):
        return False
    pyproj = _pyproj(a.name)
    return pyproj.CRS.from_wkt(a.wkt).equals(pyproj.CRS.from_wkt(b.wkt), ignore_axis_order=True)


def resolve_crs(member: object, path: str | Path | None, option: str | None) -> InputCrs | None:
    """The system of a file's coordinates: ``--crs`` (``option``) and what the file declares
    (:func:`file_crs`), which must agree when both are given; None when neither says (the
    caller detects longitude/latitude or metres from the coordinates)."""
    where = str(path) if path is not None else "lots"
    given = parse_crs(option, f"--crs {option}") if option is not None else None
    declared = file_crs(member, path, where)
    if given is None or declared is None or same_crs(given, declared):
        return given or declared
    source = "its crs member" if member is not None else "the .prj beside it"
    if given.name == METRES:
        raise InputFormatError(
            f"{where}: {source} says {_said(declared)}; --crs metres would take its coordinates"
            " for metres on the ground: leave --crs out"
        )
    raise InputFormatError(
        f"{where}: --crs {option} but {source} says {_said(declared)}; leave --crs out or fix"
        " the file"
    )


def _said(crs: InputCrs) -> str:
    return "WGS84 longitude/latitude" if crs.name == LONLAT else crs.name
