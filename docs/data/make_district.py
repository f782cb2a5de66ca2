"""Writes docs/data/district.geojson: 30 house lots along a street near Cluny (46.434 N, 4.659 E)
in RFC 7946 GeoJSON, five of them odd or made to fail, and a well (a point).

Run from the repository: ``.venv/bin/python docs/data/make_district.py``. The lots are laid out
in metres on a street turned 18 degrees from east and placed by inverting shapegen's own
tangent-plane projection, so a rectangle in metres is a rectangle to the millimetre.
"""

import json
import math

import numpy as np

from shapegen.readers.projection import east_north

lat0, lon0 = 46.4340, 4.6590
R = 6378137.0  # only for the first guess of each inversion


def lonlat(e, n):
    # invert the tangent-plane projection at (lat0, lon0) by fixed-point steps
    lon = lon0 + math.degrees(e / (R * math.cos(math.radians(lat0))))
    lat = lat0 + math.degrees(n / R)
    for _ in range(6):
        got = east_north(lat, lon, lat0, lon0)
        lon += math.degrees((e - got[0]) / (R * math.cos(math.radians(lat0))))
        lat += math.degrees((n - got[1]) / R)
    return [round(lon, 9), round(lat, 9)]


rng = np.random.default_rng(7)
theta = math.radians(18)
rot = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
feats = []


def add(ring_en, props, fid, holes=()):
    ring = [lonlat(*(rot @ p)) for p in ring_en]
    ring.append(ring[0])
    coords = [ring] + [[lonlat(*(rot @ p)) for p in h] + [lonlat(*(rot @ h[0]))] for h in holes]
    feats.append(
        {
            "type": "Feature",
            "id": fid,
            "properties": props,
            "geometry": {"type": "Polygon", "coordinates": coords},
        }
    )


k = 0
# two rows of houses facing a street along east (x), the back row facing north
for n0, depth, sign in [(6.0, 9.0, 1), (-6.0, 10.0, -1)]:
    x = 0.0
    for _ in range(12):
        w = float(rng.choice([8.0, 9.0, 10.0, 12.0, 14.0]))
        d = depth + float(rng.uniform(-1, 1.5))
        storeys = int(rng.integers(1, 4))
        jetty = float(rng.choice([0.0, 0.1, 0.2, 0.35]))
        k += 1
        if sign > 0:
            ring = [(x, n0), (x + w, n0), (x + w, n0 + d), (x, n0 + d)]
        else:
            ring = [(x + w, n0), (x, n0), (x, n0 - d), (x + w, n0 - d)]
            ring = [ring[0], ring[1], ring[2], ring[3]]
            ring = ring[::-1]  # counter-clockwise
            ring = [ring[-1]] + ring[:-1]
        add(ring, {"name": f"house {k}", "storeys": storeys, "jetty": jetty}, f"lot-{k:02d}")
        x += w + 1.0
# odd shapes at the end of the street
x = 150.0
add(
    [(x, 6), (x + 14, 6), (x + 12, 16), (x + 1, 15)],
    {"name": "trapezoid", "storeys": 2, "jetty": 0.1},
    "lot-25",
)
add(
    [(x, -6), (x, -18), (x + 16, -18), (x + 16, -12), (x + 8, -12), (x + 8, -6)],
    {"name": "L-shaped corner", "storeys": 1, "jetty": 0.0},
    "lot-26",
)
# made to fail
add(
    [(x + 20, 6), (x + 32, 6), (x + 32, 14), (x + 20, 14)],
    {"name": "bad storeys", "storeys": "three"},
    "lot-27",
)
add([(x + 20, -6), (x + 30, -6), (x + 30, -6.0000001)], {"name": "sliver"}, "lot-28")
add(
    [(x + 36, 6), (x + 56, 6), (x + 56, 26), (x + 36, 26)],
    {"name": "courtyard", "storeys": 2},
    "lot-29",
    holes=[[(x + 42, 12), (x + 42, 20), (x + 50, 20), (x + 50, 12)]],
)
add(
    [(x + 36, -6), (x + 48, -6), (x + 48, -14), (x + 36, -14)][::-1],
    {"name": "tower house", "storeys": 6, "jetty": 0.5},
    "lot-30",
)
feats.append(
    {
        "type": "Feature",
        "id": "well",
        "properties": {"name": "well"},
        "geometry": {"type": "Point", "coordinates": lonlat(140, 0)},
    }
)
doc = {"type": "FeatureCollection", "name": "district", "features": feats}
text = json.dumps(doc, indent=None)
text = text.replace('{"type": "Feature"', '\n{"type": "Feature"')
open("docs/data/district.geojson", "w").write(text + "\n")
print(len(feats))
