"""Scene Layer Packages (``.slpk``): a 3D Object scene layer of the I3S specification, 1.7.

I3S (Esri's Indexed 3D Scene layer format, an OGC community standard; Esri/i3s-spec) stores a
layer as JSON documents and binary buffers in a zip archive. What is written here, for a list
of :class:`Feature` (a triangle mesh each, metres, the scene's x east, y north, z up):

``metadata.json``
    the package's metadata (``folderPattern`` BASIC, ``archiveCompressionType`` STORE,
    ``resourceCompressionType`` GZIP or NONE, ``I3SVersion`` 1.7, ``nodeCount``), not gzipped.
``3dSceneLayer.json.gz``
    the layer: ``layerType`` 3DObject, its ``store`` (profile ``meshpyramids``, version 1.7, the
    ``defaultGeometrySchema`` of the legacy buffer), ``nodePages``, one material and one
    geometry definition, the ``fields`` and ``attributeStorageInfo`` of the feature attributes.
``nodepages/0.json.gz``
    the node tree as a flat array: node 0 the root, without a mesh (the specification keeps
    the root of a 3D Object layer empty), node 1 its only child, holding every feature.
``nodes/1/geometries/0.bin.gz``
    the geometry buffer: ``vertexCount``, ``featureCount`` (UInt32 each), then ``position``
    (Float32 x 3 per vertex, relative to the node's bounding box centre), ``normal`` (Float32
    x 3), ``uv0`` (Float32 x 2, zero: no texture), ``color`` (UInt8 x 4: each triangle's RGBA, as
    CityEngine's encoder writes a leaf's colour), ``featureId``
    (UInt64 per feature), ``faceRange`` (UInt32 x 2 per feature: its first and last triangle,
    inclusive); triangles are listed vertex after vertex (no index buffer), little-endian, in
    this fixed order.
``nodes/1/attributes/f_K/0.bin.gz``
    an attribute per feature: ``f_0`` the object ids, then one per field (the count as UInt32,
    then the values: Float64, or for text the UTF-8 byte counts and the bytes).
``@specialIndexFileHASH128@``
    the last entry: the MD5 of every entry's name (lower case) and its offset in the archive,
    sorted as the specification sorts them, 24 bytes each.

Resources are gzipped one by one and stored in the archive without compression, as the
specification asks. In a local scene (any projected coordinate system) positions and bounding
boxes are in the scene's units; in a global scene (WGS84, wkid 4326) the centres are longitude
and latitude in degrees, the vertex offsets from them degrees east and north and metres up, and
each box turns with the east-north-up frame at its centre.
"""

from __future__ import annotations

__all__ = ["Feature", "SceneLayer", "encode_slpk", "HASH_INDEX_NAME"]

import gzip
import hashlib
import io
import json
import math
import struct
import uuid
import zipfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

HASH_INDEX_NAME = "@specialIndexFileHASH128@"
I3S_VERSION = "1.7"
EARTH_RADIUS_M = 6378137.0
"""The WGS84 semi-major axis: Web Mercator's sphere, and the ECEF frame of a global box."""
LEAF_LOD_THRESHOLD = math.pi * (5.0e7 / 2.0) ** 2
"""The leaf's screen-area threshold (pixels squared): a disc 5e7 pixels wide, so no client ever
asks for finer children than the leaf (which has none)."""


@dataclass(frozen=True)
class Feature:
    """One feature of the layer: a triangle mesh and its attributes.

    ``positions`` (n, 3) metres in the scene's frame (x east, y north, z up); ``triangles``
    (t, 3) indices into them, counter-clockwise seen from outside; ``colors`` (t, 4) each
    triangle's sRGB and opacity, 0 to 255 (None: opaque white); ``attributes`` field name to
    a number or a text.
    """

    positions: np.ndarray
    triangles: np.ndarray
    attributes: Mapping[str, float | str] = field(default_factory=dict)
    colors: np.ndarray | None = None


@dataclass(frozen=True)
class SceneLayer:
    """What the layer says of itself: ``name``, the coordinate system ``wkid`` (4326 makes a
    global scene), ``uid`` (the store's id), back faces culled or not, resources gzipped."""

    name: str
    wkid: int
    uid: str = ""
    cull_back_faces: bool = False
    gzip_resources: bool = True

    @property
    def is_global(self) -> bool:
        return self.wkid == 4326


def encode_slpk(features: Sequence[Feature], layer: SceneLayer) -> bytes:
    """The ``.slpk`` archive of ``features`` as one layer (see the module's documentation)."""
    triangles, colors, feature_ids, face_ranges = _triangle_soup(features)
    points = triangles.reshape(-1, 3)
    if len(points):
        low, high = points.min(axis=0), points.max(axis=0)
    else:
        low = high = np.zeros(3)
    box = _oriented_box(low, high, layer.is_global)
    fields_, storage, columns = _attribute_tables(features)
    resources: dict[str, bytes] = {}

    def put(name: str, payload: bytes) -> None:
        if layer.gzip_resources:
            resources[name + ".gz"] = gzip.compress(payload, mtime=0)
        else:
            resources[name] = payload

    nodes = [
        {"index": 0, "obb": box["obb"], "children": [1]},
        {
            "index": 1,
            "parentIndex": 0,
            "lodThreshold": LEAF_LOD_THRESHOLD,
            "obb": box["obb"],
            "mesh": {
                "material": {"definition": 0},
                "geometry": {
                    "definition": 0,
                    "resource": 1,
                    "vertexCount": int(len(points)),
                    "featureCount": len(feature_ids),
                },
                "attribute": {"resource": 1},
            },
        },
    ]
    if feature_ids:
        put(
            "nodes/1/geometries/0.bin",
            _geometry_buffer(points, colors, box, feature_ids, face_ranges),
        )
        for key, payload in _attribute_buffers(feature_ids, columns).items():
            put(f"nodes/1/attributes/{key}/0.bin", payload)
    else:
        del nodes[1]["mesh"]  # no shape gave geometry: an empty node, not an empty buffer
    put("nodepages/0.json", _json({"nodes": nodes}))
    translucent = bool(len(colors)) and bool((colors[:, 3] < 255).any())
    put("3dSceneLayer.json", _json(_scene_layer(layer, box, fields_, storage, translucent)))
    metadata = {
        "folderPattern": "BASIC",
        "archiveCompressionType": "STORE",
        "resourceCompressionType": "GZIP" if layer.gzip_resources else "NONE",
        "I3SVersion": I3S_VERSION,
        "nodeCount": len(nodes),
    }
    resources["metadata.json"] = _json(metadata)
    return _archive(resources)


def _triangle_soup(features: Sequence[Feature]):
    """(t, 3, 3) corners of every triangle, feature after feature, and (t, 4) their colours;
    the feature ids (1, 2, ...) and each feature's inclusive range of triangles. A feature
    without triangles is left out of the geometry (a range cannot be empty) but keeps its id."""
    parts, colors, ids, ranges, start = [], [], [], [], 0
    for k, feature in enumerate(features):
        positions = np.asarray(feature.positions, dtype=float).reshape(-1, 3)
        triangles = np.asarray(feature.triangles, dtype=np.int64).reshape(-1, 3)
        if not len(triangles):
            continue
        parts.append(positions[triangles])
        if feature.colors is None:
            colors.append(np.full((len(triangles), 4), 255, dtype=np.uint8))
        else:
            colors.append(np.asarray(feature.colors, dtype=np.uint8).reshape(len(triangles), 4))
        ids.append(k + 1)
        ranges.append((start, start + len(triangles) - 1))
        start += len(triangles)
    soup = np.concatenate(parts) if parts else np.zeros((0, 3, 3))
    rgba = np.concatenate(colors) if colors else np.zeros((0, 4), dtype=np.uint8)
    return soup, rgba, ids, ranges


def _oriented_box(low: np.ndarray, high: np.ndarray, is_global: bool) -> dict:
    """The node's bounding box in the layer's frame, and what turns a scene point into a
    buffer position (the offset from the box centre, in the buffer's units)."""
    centre = (low + high) / 2.0
    half = np.maximum((high - low) / 2.0, 0.0)
    if not is_global:
        obb = {"center": _floats(centre), "halfSize": _floats(half), "quaternion": [0, 0, 0, 1]}
        radius = float(np.linalg.norm(half))
        return {"obb": obb, "centre": centre, "degrees": None, "radius": radius}
    lon, lat = web_mercator_to_degrees(centre[0], centre[1])
    # Mercator metres are true metres times 1/cos(latitude): the half sizes taken from them
    # are never smaller than the true ones, so the box still holds every vertex
    obb = {
        "center": [lon, lat, float(centre[2])],
        "halfSize": _floats(half),
        "quaternion": _floats(_enu_quaternion(math.radians(lon), math.radians(lat))),
    }
    return {
        "obb": obb,
        "centre": centre,
        "degrees": (lon, lat),
        "radius": float(np.linalg.norm(half)),
    }


def web_mercator_to_degrees(x, y):
    """Longitude and latitude (degrees) of Web Mercator (EPSG:3857) metres ``x``, ``y``."""
    lon = np.degrees(np.asarray(x, dtype=float) / EARTH_RADIUS_M)
    lat = np.degrees(
        2.0 * np.arctan(np.exp(np.asarray(y, dtype=float) / EARTH_RADIUS_M)) - np.pi / 2
    )
    return (float(lon), float(lat)) if np.ndim(lon) == 0 else (lon, lat)


def _enu_quaternion(lon: float, lat: float) -> np.ndarray:
    """The rotation (x, y, z, w) taking east, north, up at ``lon``, ``lat`` (radians) to the
    ECEF axes (X through longitude 0 on the equator, Z the north pole)."""
    east = [-math.sin(lon), math.cos(lon), 0.0]
    north = [-math.sin(lat) * math.cos(lon), -math.sin(lat) * math.sin(lon), math.cos(lat)]
    up = [math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)]
    return rotation_quaternion(np.array([east, north, up]).T)


def rotation_quaternion(matrix: np.ndarray) -> np.ndarray:
    """The unit quaternion (x, y, z, w) of the rotation ``matrix`` (Shepperd's method)."""
    m = np.asarray(matrix, dtype=float)
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0:
        s = 2.0 * math.sqrt(1.0 + trace)
        q = [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0] * 4
        q[i] = s / 4
        q[j] = (m[j, i] + m[i, j]) / s
        q[k] = (m[k, i] + m[i, k]) / s
        q[3] = (m[k, j] - m[j, k]) / s
    return np.array(q) / np.linalg.norm(q)


def _geometry_buffer(points, colors, box, feature_ids, face_ranges) -> bytes:
    """The legacy non-indexed buffer (``defaultGeometrySchema``), little-endian."""
    corners = points.reshape(-1, 3, 3)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, lengths, out=np.zeros_like(normals), where=lengths > 0)
    normals = np.repeat(normals, 3, axis=0)
    offsets = points - box["centre"]
    if box["degrees"] is not None:
        # x, y offsets in degrees from the centre, as a global layer's positions are
        lon, lat = web_mercator_to_degrees(points[:, 0], points[:, 1])
        offsets = np.column_stack([lon - box["degrees"][0], lat - box["degrees"][1], offsets[:, 2]])
    header = struct.pack("<II", len(points), len(feature_ids))
    return b"".join(
        [
            header,
            offsets.astype("<f4").tobytes(),
            normals.astype("<f4").tobytes(),
            np.zeros((len(points), 2), dtype="<f4").tobytes(),
            np.repeat(colors, 3, axis=0).astype("u1").tobytes(),
            np.asarray(feature_ids, dtype="<u8").tobytes(),
            np.asarray(face_ranges, dtype="<u4").reshape(-1, 2).tobytes(),
        ]
    )


def _attribute_tables(features: Sequence[Feature]):
    """The layer's ``fields`` and ``attributeStorageInfo`` and the columns of values: the
    object id, then every attribute name in order of first appearance; a field is a number
    (Float64) when all its values are numbers, text otherwise."""
    names: list[str] = []
    for feature in features:
        names += [n for n in feature.attributes if n not in names]
    fields_ = [{"name": "OID", "type": "esriFieldTypeOID", "alias": "OBJECTID"}]
    storage = [
        {
            "key": "f_0",
            "name": "OID",
            "header": [{"property": "count", "valueType": "UInt32"}],
            "ordering": ["ObjectIds"],
            "objectIds": {"valueType": "UInt32", "valuesPerElement": 1},
        }
    ]
    columns: dict[str, tuple[str, list]] = {}
    for k, name in enumerate(names, start=1):
        values = [f.attributes.get(name) for f in features if _has_geometry(f)]
        numeric = all(
            isinstance(v, int | float | np.floating) and not isinstance(v, bool)
            for v in values
            if v is not None
        )
        key = f"f_{k}"
        if numeric:
            fields_.append({"name": name, "type": "esriFieldTypeDouble", "alias": name})
            storage.append(
                {
                    "key": key,
                    "name": name,
                    "header": [{"property": "count", "valueType": "UInt32"}],
                    "ordering": ["attributeValues"],
                    "attributeValues": {"valueType": "Float64", "valuesPerElement": 1},
                }
            )
            columns[key] = ("number", [math.nan if v is None else float(v) for v in values])
        else:
            fields_.append({"name": name, "type": "esriFieldTypeString", "alias": name})
            storage.append(
                {
                    "key": key,
                    "name": name,
                    "header": [
                        {"property": "count", "valueType": "UInt32"},
                        {"property": "attributeValuesByteCount", "valueType": "UInt32"},
                    ],
                    "ordering": ["attributeByteCounts", "attributeValues"],
                    "attributeByteCounts": {"valueType": "UInt32", "valuesPerElement": 1},
                    "attributeValues": {
                        "valueType": "String",
                        "encoding": "UTF-8",
                        "valuesPerElement": 1,
                    },
                }
            )
            columns[key] = ("text", ["" if v is None else _text(v) for v in values])
    return fields_, storage, columns


def _has_geometry(feature: Feature) -> bool:
    return len(np.asarray(feature.triangles).reshape(-1, 3)) > 0


def _text(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _attribute_buffers(feature_ids: list[int], columns: dict) -> dict[str, bytes]:
    count = struct.pack("<I", len(feature_ids))
    out = {"f_0": count + np.asarray(feature_ids, dtype="<u4").tobytes()}
    for key, (kind, values) in columns.items():
        if kind == "number":
            out[key] = count + np.asarray(values, dtype="<f8").tobytes()
        else:
            # each string with its terminating NUL, as the specification counts its bytes
            encoded = [v.encode("utf-8") + b"\0" for v in values]
            sizes = np.asarray([len(e) for e in encoded], dtype="<u4")
            total = struct.pack("<I", int(sizes.sum()))
            out[key] = count + total + sizes.tobytes() + b"".join(encoded)
    return out


def _scene_layer(
    layer: SceneLayer, box: dict, fields_: list, storage: list, translucent: bool
) -> dict:
    centre, half = np.asarray(box["obb"]["center"]), np.asarray(box["obb"]["halfSize"])
    if box["degrees"] is None:
        low, high = centre - half, centre + half
    else:
        # the extent in degrees: the box's half sizes taken along the Mercator axes
        corners = box["centre"][:2] + np.array([[-1, -1], [1, 1]]) * half[:2]
        lon, lat = web_mercator_to_degrees(corners[:, 0], corners[:, 1])
        low = np.array([lon[0], lat[0], centre[2] - half[2]])
        high = np.array([lon[1], lat[1], centre[2] + half[2]])
    crs = f"http://www.opengis.net/def/crs/EPSG/0/{layer.wkid}"
    return {
        "id": 0,
        "href": "./layers/0",
        "layerType": "3DObject",
        "version": str(uuid.uuid4()).upper(),
        "name": layer.name,
        "capabilities": ["View"],
        "spatialReference": {"wkid": layer.wkid, "latestWkid": layer.wkid},
        "heightModelInfo": {"heightModel": "gravity_related_height", "heightUnit": "meter"},
        "store": {
            "id": layer.uid or str(uuid.uuid4()).upper(),
            "profile": "meshpyramids",
            "version": I3S_VERSION,
            "extent": [float(low[0]), float(low[1]), float(high[0]), float(high[1])],
            "indexCRS": crs,
            "vertexCRS": crs,
            "normalReferenceFrame": "east-north-up"
            if layer.is_global
            else "vertex-reference-frame",
            "lodType": "MeshPyramid",
            "lodModel": "node-switching",
            "defaultGeometrySchema": {
                "geometryType": "triangles",
                "topology": "PerAttributeArray",
                "header": [
                    {"property": "vertexCount", "type": "UInt32"},
                    {"property": "featureCount", "type": "UInt32"},
                ],
                "ordering": ["position", "normal", "uv0", "color"],
                "vertexAttributes": {
                    "position": {"valueType": "Float32", "valuesPerElement": 3},
                    "normal": {"valueType": "Float32", "valuesPerElement": 3},
                    "uv0": {"valueType": "Float32", "valuesPerElement": 2},
                    "color": {"valueType": "UInt8", "valuesPerElement": 4},
                },
                "featureAttributeOrder": ["id", "faceRange"],
                "featureAttributes": {
                    "id": {"valueType": "UInt64", "valuesPerElement": 1},
                    "faceRange": {"valueType": "UInt32", "valuesPerElement": 2},
                },
            },
        },
        "nodePages": {
            "nodesPerPage": 64,
            "rootIndex": 0,
            "lodSelectionMetricType": "maxScreenThresholdSQ",
        },
        "materialDefinitions": [
            {
                "pbrMetallicRoughness": {
                    "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 1.0,
                },
                "alphaMode": "blend" if translucent else "opaque",
                "doubleSided": not layer.cull_back_faces,
                "cullFace": "back" if layer.cull_back_faces else "none",
            }
        ],
        "geometryDefinitions": [
            {
                "topology": "triangle",
                "geometryBuffers": [
                    {
                        "offset": 8,
                        "position": {"type": "Float32", "component": 3},
                        "normal": {"type": "Float32", "component": 3},
                        "uv0": {"type": "Float32", "component": 2},
                        "color": {"type": "UInt8", "component": 4},
                        "featureId": {"type": "UInt64", "component": 1, "binding": "per-feature"},
                        "faceRange": {"type": "UInt32", "component": 2, "binding": "per-feature"},
                    }
                ],
            }
        ],
        "fields": fields_,
        "attributeStorageInfo": storage,
    }


def _archive(resources: dict[str, bytes]) -> bytes:
    """The zip of ``resources`` (STORE), then the hash index of their names as its last
    entry. Entry times are fixed, so the same layer gives the same bytes but for its ids."""
    stream = io.BytesIO()
    stamp = (1980, 1, 1, 0, 0, 0)
    with zipfile.ZipFile(stream, "w", compression=zipfile.ZIP_STORED) as archive:
        offsets = {}
        for name, payload in resources.items():
            info = zipfile.ZipInfo(name, date_time=stamp)
            archive.writestr(info, payload)
            offsets[name] = archive.getinfo(name).header_offset
        archive.writestr(zipfile.ZipInfo(HASH_INDEX_NAME, date_time=stamp), _hash_index(offsets))
    return stream.getvalue()


def _hash_index(offsets: Mapping[str, int]) -> bytes:
    """MD5 of each canonical name (lower case, ``/``, no leading ``/``) with its offset; sorted
    on the digest read as two little-endian 64-bit words, the first word first."""
    rows = []
    for name, offset in offsets.items():
        canonical = name.replace("\\", "/").lstrip("/").lower()
        digest = hashlib.md5(canonical.encode("utf-8")).digest()
        rows.append((struct.unpack("<QQ", digest), digest, offset))
    rows.sort(key=lambda row: row[0])
    return b"".join(digest + struct.pack("<Q", offset) for _, digest, offset in rows)


def _json(document: object) -> bytes:
    return json.dumps(document, separators=(",", ":"), allow_nan=False).encode("utf-8")


def _floats(values) -> list[float]:
    return [float(v) for v in np.asarray(values, dtype=float).ravel()]
