"""Writes the district (docs/data/district.geojson, WGS84 longitude/latitude) in two projected
systems, as GIS files often come:

- ``district_3857.geojson``: Web Mercator (EPSG:3857), said by an old-style GeoJSON ``crs``
  member ``urn:ogc:def:crs:EPSG::3857``;
- ``district_l93.geojson`` with ``district_l93.prj`` beside it: Lambert-93 (EPSG:2154, the
  French national grid), said by the ``.prj`` (WKT) alone.

Run from the repository: ``.venv/bin/python docs/data/make_district_crs.py``. Coordinates are
rounded to 0.1 mm; every other member (ids, properties, the well) is copied as it is.
"""

import copy
import json
from pathlib import Path

import pyproj

HERE = Path(__file__).resolve().parent
SYSTEMS = {
    "district_3857.geojson": ("EPSG:3857", "member"),
    "district_l93.geojson": ("EPSG:2154", "prj"),
}


def projected(coordinates, transformer):
    """The same nesting of lists with every position ``[lon, lat]`` projected."""
    if coordinates and isinstance(coordinates[0], int | float):
        x, y = transformer.transform(coordinates[0], coordinates[1])
        return [round(x, 4), round(y, 4)]
    return [projected(part, transformer) for part in coordinates]


def main() -> None:
    district = json.loads((HERE / "district.geojson").read_text(encoding="utf-8"))
    for name, (code, how) in SYSTEMS.items():
        transformer = pyproj.Transformer.from_crs("OGC:CRS84", code, always_xy=True)
        document = copy.deepcopy(district)
        for feature in document["features"]:
            geometry = feature["geometry"]
            geometry["coordinates"] = projected(geometry["coordinates"], transformer)
        if how == "member":
            urn = "urn:ogc:def:crs:" + code.replace(":", "::")
            crs = {"type": "name", "properties": {"name": urn}}
            document = {"type": "FeatureCollection", "name": district.get("name"), "crs": crs,
                        "features": document["features"]}  # fmt: skip
        else:
            wkt = pyproj.CRS(code).to_wkt(pyproj.enums.WktVersion.WKT1_ESRI)
            (HERE / name).with_suffix(".prj").write_text(wkt + "\n", encoding="utf-8")
        lines = ",\n".join(json.dumps(f) for f in document.pop("features"))
        head = json.dumps(document)[:-1]
        text = f'{head}, "features": [\n{lines}\n]}}\n'
        (HERE / name).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
