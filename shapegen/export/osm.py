"""OpenStreetMap ways (OSM XML): read one, project it to local metres, place a bridge on it.

An OSM XML file (``<osm>``, API 0.6) lists ``<node id lat lon>`` elements and ``<way id>``
elements whose ``<nd ref>`` children name their nodes in order. :func:`read_way` reads the one way
asked for and its nodes, in two streaming passes (the way first, then only its nodes), so a large
extract is never held in memory.

Projection. The nodes are projected onto the local tangent plane of the WGS84 ellipsoid at the
way's first node: geodetic latitude/longitude (height 0) -> earth-centred coordinates -> east,
north, up about the first node; the up component (the earth's curvature, ``d^2 / 2R``, about
0.6 m at 2.7 km) is dropped. Over a few kilometres distances in this plane differ from geodesic
ones by less than ``(d / R)^2 / 6`` relative (2.7 km: 3e-8). shapegen is y-up and right-handed:
east -> +x, up -> +y, north -> -z.

Placement (:func:`place_on_way`). A bridge rule set runs along +x from x = 0 to x = ``length``
with its width across z. The bridge is given the way's **straight** length, first node to last
(a bridge is straight; the polyline length, along every node, is reported beside it), then turned
about +y so that +x points from the first node to the last and moved so that its start (x = 0)
sits on the first node, its width (the model's extent in z) centred on the way.
"""

from __future__ import annotations

__all__ = [
    "WGS84_A",
    "WGS84_F",
    "OsmNode",
    "OsmWay",
    "read_way",
    "east_north",
    "require_straight_length",
    "place_on_way",
]

import math
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.model.model import Model, PointLoad

WGS84_A = 6_378_137.0
"""WGS84 semi-major axis, m."""
WGS84_F = 1.0 / 298.257223563
"""WGS84 flattening (dimensionless)."""
_E2 = WGS84_F * (2.0 - WGS84_F)  # first eccentricity squared

# A way whose ends are closer than this gives no direction to place a bridge along, m.
_MIN_STRAIGHT_LENGTH_M = 0.01
# Way ids listed when the one asked for is missing.
_LISTED_WAYS = 8


@dataclass(frozen=True)
class OsmNode:
    """An OSM node: its id and WGS84 position (degrees)."""

    id: int
    lat: float
    lon: float


@dataclass(frozen=True)
class OsmWay:
    """An OSM way with its nodes in order.

    Attributes
    ----------
    id
        The way's OSM id.
    nodes
        Its nodes (at least two), in the way's order.
    tags
        Its ``<tag k v>`` pairs.
    source
        The file it was read from.
    """

    id: int
    nodes: tuple[OsmNode, ...]
    tags: dict[str, str] = field(default_factory=dict)
    source: str = ""

    @property
    def east_north(self) -> np.ndarray:
        """``(k, 2)`` east and north of each node about the first one, m."""
        lat = np.array([node.lat for node in self.nodes])
        lon = np.array([node.lon for node in self.nodes])
        return east_north(lat, lon, self.nodes[0].lat, self.nodes[0].lon)

    @property
    def straight_length(self) -> float:
        """Distance from the first node to the last in the local plane, m."""
        return float(np.hypot(*self.east_north[-1]))

    @property
    def polyline_length(self) -> float:
        """Length along every node in the local plane, m."""
        return float(np.hypot(*np.diff(self.east_north, axis=0).T).sum())

    @property
    def heading(self) -> float:
        """Direction from the first node to the last, degrees clockwise from north in [0, 360)."""
        east, north = self.east_north[-1]
        # Rounded to 1e-9 degree so that round-off west of due north reads 0, not 359.99...
        return round(math.degrees(math.atan2(east, north)), 9) % 360.0

    def to_report(self) -> dict:
        """The ``osm`` object of a build report (plain JSON types; m and degrees)."""
        first, last = self.nodes[0], self.nodes[-1]
        return {
            "file": self.source,
            "way": self.id,
            "name": self.tags.get("name"),
            "nodes": len(self.nodes),
            "straight_length": self.straight_length,
            "polyline_length": self.polyline_length,
            "heading": self.heading,
            "first_node": {"id": first.id, "lat": first.lat, "lon": first.lon},
            "last_node": {"id": last.id, "lat": last.lat, "lon": last.lon},
            "projection": "WGS84 local tangent plane at the first node: east +x, north -z",
        }


# ------------------------------------------------------------------------------ reading
def read_way(path: str | Path, way_id: int) -> OsmWay:
    """Read way ``way_id`` and its nodes from the OSM XML file ``path``.

    Raises
    ------
    InputFormatError
        Naming the file: unreadable or invalid XML, not an ``<osm>`` document, no way with that
        id (a few ids present are listed), fewer than two nodes, a node the file lacks, or a
        latitude/longitude that is not a number in range.
    """
    path = Path(path)
    refs, tags, others = _find_way(path, way_id)
    if refs is None:
        shown = ", ".join(str(i) for i in others[:_LISTED_WAYS])
        more = f" and {len(others) - _LISTED_WAYS} more" if len(others) > _LISTED_WAYS else ""
        listing = f" (ways: {shown}{more})" if others else " (it has no ways)"
        raise InputFormatError(f"{path}: no way with id {way_id}{listing}")
    if len(refs) < 2:
        raise InputFormatError(
            f"{path}: way {way_id} has {len(refs)} node{'s' if len(refs) != 1 else ''};"
            " a bridge needs at least two"
        )
    found = _find_nodes(path, set(refs))
    missing = [ref for ref in refs if ref not in found]
    if missing:
        raise InputFormatError(
            f"{path}: way {way_id} refers to node {missing[0]}, which is not in the file"
            + (f" ({len(set(missing))} nodes missing)" if len(set(missing)) > 1 else "")
        )
    nodes = tuple(found[ref] for ref in refs)
    return OsmWay(id=way_id, nodes=nodes, tags=tags, source=str(path))


def _elements(path: Path):
    """The document's top-level elements (nodes, ways...), each once it is complete.

    Each is dropped from the root once handed over, so memory stays bounded.
    """
    try:
        with open(path, "rb") as handle:
            root = None
            depth = 0
            for event, element in ElementTree.iterparse(handle, events=("start", "end")):
                if event == "start":
                    depth += 1
                    if root is None:
                        root = element
                        if element.tag != "osm":
                            raise InputFormatError(
                                f"{path}: not an OSM XML file (root element <{element.tag}>,"
                                " expected <osm>)"
                            )
                    continue
                depth -= 1
                if depth == 1:
                    yield element
                    root.clear()
    except ElementTree.ParseError as exc:
        line, column = exc.position
        message = str(exc).split(":")[0]
        raise InputFormatError(f"{path}:{line}:{column + 1}: invalid XML: {message}") from None
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None


def _osm_id(element, path: Path) -> int:
    raw = element.get("id")
    try:
        return int(raw)
    except (TypeError, ValueError):
        raise InputFormatError(
            f"{path}: a <{element.tag}> has id {raw!r}; OSM ids are integers"
        ) from None


def _find_way(path: Path, way_id: int) -> tuple[list[int] | None, dict[str, str], list[int]]:
    """The way's node references and tags (None when absent) and the ids of the other ways."""
    others: list[int] = []
    for element in _elements(path):
        if element.tag != "way":
            continue
        this_id = _osm_id(element, path)
        if this_id != way_id:
            others.append(this_id)
            continue
        refs = []
        for nd in element.iter("nd"):
            try:
                refs.append(int(nd.get("ref")))
            except (TypeError, ValueError):
                raise InputFormatError(
                    f"{path}: way {way_id} has a node reference {nd.get('ref')!r},"
                    " not an integer id"
                ) from None
        tags = {tag.get("k"): tag.get("v") for tag in element.iter("tag") if tag.get("k")}
        return refs, tags, others
    return None, {}, others


def _find_nodes(path: Path, wanted: set[int]) -> dict[int, OsmNode]:
    """The nodes among ``wanted`` that the file has, by id, their coordinates checked."""
    found: dict[int, OsmNode] = {}
    for element in _elements(path):
        if element.tag != "node":
            continue
        node_id = _osm_id(element, path)
        if node_id in wanted:
            lat = _degrees(element, "lat", 90.0, node_id, path)
            lon = _degrees(element, "lon", 180.0, node_id, path)
            found[node_id] = OsmNode(node_id, lat, lon)
            if len(found) == len(wanted):
                break
    return found


def _degrees(element, key: str, limit: float, node_id: int, path: Path) -> float:
    raw = element.get(key)
    try:
        value = float(raw)
    except (TypeError, ValueError):
        value = math.nan
    if not math.isfinite(value) or abs(value) > limit:
        raise InputFormatError(
            f"{path}: node {node_id} has {key}={raw!r}; expected degrees from {-limit:g}"
            f" to {limit:g}"
        )
    return value


# ------------------------------------------------------------------------------ projection
def east_north(lat, lon, origin_lat: float, origin_lon: float) -> np.ndarray:
    """Project WGS84 positions onto the local tangent plane at an origin.

    Parameters
    ----------
    lat, lon
        Geodetic latitude and longitude, degrees (scalars or arrays of one shape).
    origin_lat, origin_lon
        The tangent point, degrees.

    Returns
    -------
    numpy.ndarray
        ``(..., 2)``: east and north of each position, m, about the origin (heights 0 on the
        ellipsoid; the up component is dropped).
    """
    lat, lon = np.broadcast_arrays(np.radians(lat), np.radians(lon))
    phi0, lambda0 = math.radians(origin_lat), math.radians(origin_lon)
    # Earth-centred offsets from the origin; differences of 6e6 m coordinates keep some 1e-9 m.
    delta = _earth_centred(lat, lon) - _earth_centred(np.array(phi0), np.array(lambda0))
    dx, dy, dz = np.moveaxis(delta, -1, 0)
    east = -math.sin(lambda0) * dx + math.cos(lambda0) * dy
    north = (
        -math.sin(phi0) * math.cos(lambda0) * dx
        - math.sin(phi0) * math.sin(lambda0) * dy
        + math.cos(phi0) * dz
    )
    return np.stack([east, north], axis=-1)


def _earth_centred(phi: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """Earth-centred, earth-fixed coordinates of points on the ellipsoid, m."""
    prime_vertical = WGS84_A / np.sqrt(1.0 - _E2 * np.sin(phi) ** 2)
    return np.stack(
        [
            prime_vertical * np.cos(phi) * np.cos(lam),
            prime_vertical * np.cos(phi) * np.sin(lam),
            prime_vertical * (1.0 - _E2) * np.sin(phi),
        ],
        axis=-1,
    )


# ------------------------------------------------------------------------------ placement
def require_straight_length(way: OsmWay) -> float:
    """The way's straight length (m); an error when its ends coincide (no direction)."""
    length = way.straight_length
    if length < _MIN_STRAIGHT_LENGTH_M:
        raise InputFormatError(
            f"{way.source}: the first and last nodes of way {way.id} coincide ({length:.3g} m"
            " apart); a bridge needs two distinct ends"
        )
    return length


def place_on_way(model: Model, way: OsmWay) -> Model:
    """The model turned and moved onto the way, in the way's local frame (m).

    The model's +x axis is turned about +y to point from the way's first node to its last, its
    x = 0 put on the first node (the frame's origin) and its extent in z centred on the way;
    heights are kept. ``metadata["osm"]`` records the way (:meth:`OsmWay.to_report`).
    """
    require_straight_length(way)
    theta = math.radians(way.heading)
    # Columns: where the model's x, y, z axes go. x -> (east sin, north cos) = (sin, 0, -cos).
    rotation = np.array(
        [
            [math.sin(theta), 0.0, math.cos(theta)],
            [0.0, 1.0, 0.0],
            [-math.cos(theta), 0.0, math.sin(theta)],
        ]
    )
    if model.blocks:
        lo = min(float(block.vertices[:, 2].min()) for block in model.blocks)
        hi = max(float(block.vertices[:, 2].max()) for block in model.blocks)
        middle = 0.5 * (lo + hi)
    else:
        middle = 0.0
    offset = -middle * rotation[:, 2]
    blocks = [block.transformed(rotation, offset) for block in model.blocks]
    loads = [
        PointLoad(load.block, rotation @ load.force, rotation @ load.point + offset)
        for load in model.loads
    ]
    metadata = {**model.metadata, "osm": way.to_report()}
    return Model(
        blocks,
        loads,
        gravity=model.gravity.copy(),
        ground=model.ground,
        friction=model.friction,
        metadata=metadata,
    )
