"""Write neubrandenburg.geojson.gz: 10 000 building footprints of Neubrandenburg as city lots.

The source is ``neubrandenburg.osm.bz2``, an OpenStreetMap extract (Overpass API, edits up to
2016-02-10) that JOSM ships as sample data in its source tree (``nodist/data``; Debian's source
package ``josm`` 0.0.svn18646+dfsg: ``apt-get source josm``). The data is (c) OpenStreetMap
contributors under the Open Database License (see ODbL.md beside this script).

Every closed way tagged ``building`` is a footprint; the 10 000 whose first corner lies nearest
to the market square (53.5573 N, 13.2609 E) are kept, so the lots are one contiguous district
(the old town inside its ring wall and the blocks around it). Each is a GeoJSON Polygon feature
with id ``way/ID``, corners as [longitude, latitude] to 7 decimals (about 1 cm), its ring
counter-clockwise (RFC 7946), and its ``building``, ``building:levels`` and ``height`` tags as
properties. The file is gzipped with no time stamp, so running this again writes the same bytes.

Run: ``python tests/data/osm/make_neubrandenburg.py PATH/neubrandenburg.osm.bz2`` (the standard
library only).
"""

from __future__ import annotations

import bz2
import gzip
import json
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

CENTRE = (13.2609, 53.5573)  # the market square, lon/lat
LOTS = 10_000
KEPT_TAGS = ("building", "building:levels", "height")
OUT = Path(__file__).with_name("neubrandenburg.geojson.gz")


def read_buildings(source: Path):
    nodes: dict[int, tuple[float, float]] = {}
    ways = []
    with bz2.open(source) as handle:
        for _, element in ET.iterparse(handle):
            if element.tag == "node":
                nodes[int(element.get("id"))] = (
                    float(element.get("lon")),
                    float(element.get("lat")),
                )
                element.clear()
            elif element.tag == "way":
                tags = {t.get("k"): t.get("v") for t in element.iter("tag")}
                refs = [int(nd.get("ref")) for nd in element.iter("nd")]
                if "building" in tags and len(refs) >= 4 and refs[0] == refs[-1]:
                    ways.append((int(element.get("id")), refs, tags))
                element.clear()
    return nodes, ways


def main() -> None:
    source = Path(sys.argv[1])
    nodes, ways = read_buildings(source)
    scale = math.cos(math.radians(CENTRE[1]))

    def distance(way) -> float:
        lon, lat = nodes[way[1][0]]
        return math.hypot((lon - CENTRE[0]) * scale, lat - CENTRE[1])

    complete = [way for way in ways if all(ref in nodes for ref in way[1])]
    chosen = sorted(complete, key=distance)[:LOTS]
    chosen.sort(key=lambda way: way[0])
    features = []
    for way_id, refs, tags in chosen:
        ring = [[round(nodes[r][0], 7), round(nodes[r][1], 7)] for r in refs]
        area = sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:], strict=False))
        if area < 0:
            ring.reverse()  # counter-clockwise, as RFC 7946 asks of an outer ring
        properties = {k: tags[k] for k in KEPT_TAGS if k in tags}
        features.append(
            {
                "type": "Feature",
                "id": f"way/{way_id}",
                "properties": properties,
                "geometry": {"type": "Polygon", "coordinates": [ring]},
            }
        )
    document = {
        "type": "FeatureCollection",
        "attribution": "(c) OpenStreetMap contributors, ODbL 1.0 (openstreetmap.org/copyright)",
        "features": features,
    }
    text = json.dumps(document, separators=(",", ":")).replace(
        '},{"type":"Feature"', '},\n{"type":"Feature"'
    )
    with open(OUT, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0, filename="") as out:
        out.write(text.encode("utf-8") + b"\n")
    print(
        f"{len(ways)} buildings in {source.name}, {len(features)} written to {OUT.name}"
        f" ({OUT.stat().st_size / 1e6:.2f} MB)"
    )


if __name__ == "__main__":
    main()
