"""OpenStreetMap XML (``<osm>``, API 0.6): one way and its nodes, or every building.

An OSM XML file lists ``<node id lat lon>`` elements and ``<way id>`` elements whose
``<nd ref>`` children name their nodes in order. The file is streamed: each top-level element is
dropped once read, so a large extract is never held in memory. :func:`read_way` reads the one
way asked for and its nodes in two passes (the way first, then only its nodes);
:func:`read_buildings` reads the closed ways tagged ``building`` as GeoJSON-like features.
Positions are WGS84 degrees; :func:`~shapegen.readers.projection.east_north` projects them.
"""

from __future__ import annotations

__all__ = ["OsmNode", "OsmWay", "read_buildings", "read_way"]

import math
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.readers.projection import east_north

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


def read_buildings(path: str | Path) -> tuple[list[dict], int]:
    """The closed ways tagged ``building`` of an OSM XML file as GeoJSON-like Polygon features
    (``id`` ``way/ID``, the tags as properties, ``[lon, lat]`` corners), and how many buildings
    were skipped (open ways, relations).

    Raises
    ------
    InputFormatError
        Naming the file: unreadable or invalid XML, not an ``<osm>`` document, an id that is not
        an integer, a building's node the file lacks or whose position is not in range.
    """
    path = Path(path)
    ways: list[tuple[int, list[int], dict]] = []
    skipped = 0
    for element in _elements(path):
        if element.tag not in ("way", "relation"):
            continue
        tags = {tag.get("k"): tag.get("v") for tag in element.iter("tag") if tag.get("k")}
        if "building" not in tags:
            continue
        if element.tag == "relation":
            skipped += 1  # a multipolygon building: not read
            continue
        way_id = _osm_id(element, path)
        ways.append((way_id, _node_refs(element, way_id, path), tags))
    wanted = {ref for _, refs, _ in ways for ref in refs}
    nodes = _find_nodes(path, wanted) if wanted else {}
    features = []
    for way_id, refs, tags in ways:
        if len(refs) < 4 or refs[0] != refs[-1]:
            skipped += 1  # an open way is not a footprint
            continue
        missing = [ref for ref in refs if ref not in nodes]
        if missing:
            raise InputFormatError(f"{path}: way {way_id} refers to node {missing[0]}, not in it")
        ring = [[nodes[ref].lon, nodes[ref].lat] for ref in refs]
        features.append(
            {
                "type": "Feature",
                "id": f"way/{way_id}",
                "properties": tags,
                "geometry": {"type": "Polygon", "coordinates": [ring]},
            }
        )
    return features, skipped


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
    except LookupError as exc:  # the XML declaration names an encoding Python does not know
        raise InputFormatError(f"{path}: invalid XML: {exc}") from None


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
        tags = {tag.get("k"): tag.get("v") for tag in element.iter("tag") if tag.get("k")}
        return _node_refs(element, way_id, path), tags, others
    return None, {}, others


def _node_refs(element, way_id: int, path: Path) -> list[int]:
    """The ids of a way's nodes, in order."""
    refs = []
    for nd in element.iter("nd"):
        try:
            refs.append(int(nd.get("ref")))
        except (TypeError, ValueError):
            raise InputFormatError(
                f"{path}: way {way_id} has a node reference {nd.get('ref')!r}, not an integer id"
            ) from None
    return refs


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
