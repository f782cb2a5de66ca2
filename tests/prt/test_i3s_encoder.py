"""The I3S encoder (``com.esri.prt.codecs.I3SEncoder``): the package read back as the I3S 1.7
specification lays it out (Esri/i3s-spec), by a reader written here from the specification and
not from the writer, its JSON documents validated against the specification's own schemas."""

from __future__ import annotations

import gzip
import hashlib
import json
import math
import struct
import zipfile
from pathlib import Path

import numpy as np
import pytest
from prt_shapes import DATA, EXTRUSION, FIXED, SMALL, SQUARE

import shapegen.prt as pyprt
from shapegen.errors import OptionError

jsonschema = pytest.importorskip("jsonschema")
referencing = pytest.importorskip("referencing")

SCHEMAS = DATA / "i3s-spec-schema"
CITYENGINE_PACKAGE = DATA / "i3s-pyprt" / "extrusion_pyprt112.slpk"
I3S = "com.esri.prt.codecs.I3SEncoder"
HASH_INDEX = "@specialIndexFileHASH128@"
WEB_MERCATOR_RADIUS_M = 6378137.0


# --- a reader from the specification ------------------------------------------------------


def read_package(path: Path) -> dict:
    """Every entry of the .slpk: JSON documents parsed, binaries as bytes, gzip undone."""
    with zipfile.ZipFile(path) as archive:
        infos = archive.infolist()
        assert all(i.compress_type == zipfile.ZIP_STORED for i in infos), "the archive is STORE"
        out = {"_order": [i.filename for i in infos], "_offsets": {}}
        for info in infos:
            data = archive.read(info)
            out["_offsets"][info.filename] = info.header_offset
            name = info.filename
            if name.endswith(".gz"):
                data, name = gzip.decompress(data), name[:-3]
            out[name] = json.loads(data) if name.endswith(".json") else data
    with open(path, "rb") as handle:
        out["_bytes"] = handle.read()
    return out


def geometry_buffer(data: bytes, definition: dict) -> dict:
    """The arrays of a non-compressed geometry buffer, by the geometryBuffer layout of I3S 1.7:
    ``offset`` bytes skipped, then the attributes present, in the fixed order, each
    ``component * sizeof(type) * (vertices or features)`` bytes."""
    sizes = {"Float32": "<f4", "UInt8": "u1", "UInt16": "<u2", "UInt32": "<u4", "UInt64": "<u8"}
    vertices, features = struct.unpack_from("<II", data, 0)  # the legacy header
    at = definition.get("offset", 0)
    out = {}
    for name in ("position", "normal", "uv0", "uv1", "color", "uvRegion", "featureId", "faceRange"):
        if name not in definition:
            continue
        spec = definition[name]
        binding = spec.get(
            "binding", "per-feature" if name in ("featureId", "faceRange") else "per-vertex"
        )
        count = vertices if binding == "per-vertex" else features
        dtype = np.dtype(sizes[spec["type"]])
        n = count * spec["component"]
        out[name] = np.frombuffer(data, dtype=dtype, count=n, offset=at).reshape(
            count, spec["component"]
        )
        at += n * dtype.itemsize
    assert at == len(data), "the buffer holds exactly the attributes its definition lists"
    return out


def schema_validator(name: str):
    """A Draft 4 validator of the schema file ``name``, its ``$include`` merged and its
    references resolved among the copied schemas (names without case)."""
    files = {p.name.lower(): p for p in SCHEMAS.glob("*.json")}

    def load(file_name: str) -> dict:
        schema = json.loads(files[file_name.lower()].read_text())
        included = schema.pop("$include", None)
        if included:
            base = load(included)
            schema["properties"] = {**base.get("properties", {}), **schema.get("properties", {})}
            schema["required"] = sorted(
                set(base.get("required", [])) | set(schema.get("required", []))
            )
        return schema

    def retrieve(uri: str):
        return referencing.Resource.from_contents(
            load(uri.rsplit("/", 1)[-1]), referencing.jsonschema.DRAFT4
        )

    registry = referencing.Registry(retrieve=retrieve)
    return jsonschema.Draft4Validator(load(name), registry=registry)


def scene_to_cga(points: np.ndarray) -> np.ndarray:
    """The scene's x east, y north, z up back to CGA's x, y up, z south."""
    return np.column_stack([points[:, 0], points[:, 2], -points[:, 1]])


def feature_triangles(package: dict) -> list[np.ndarray]:
    """Each feature's triangles (t, 3, 3), in CGA's frame, read through the node pages and the
    geometry definition the mesh names."""
    layer, nodes = package["3dSceneLayer.json"], package["nodepages/0.json"]["nodes"]
    out = []
    for node in nodes:
        if not node.get("mesh"):
            continue
        mesh = node["mesh"]["geometry"]
        definition = layer["geometryDefinitions"][mesh["definition"]]["geometryBuffers"][0]
        buffer = geometry_buffer(package[f"nodes/{mesh['resource']}/geometries/0.bin"], definition)
        positions = buffer["position"].astype(float) + node["obb"]["center"]
        triangles = scene_to_cga(positions).reshape(-1, 3, 3)
        out += [triangles[first : last + 1] for first, last in buffer["faceRange"].tolist()]
    return out


def area_by_normal(triangles: np.ndarray) -> dict:
    crosses = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    areas = np.linalg.norm(crosses, axis=1) / 2
    out: dict = {}
    for cross, area in zip(crosses, areas, strict=True):
        key = tuple(np.round(cross / np.linalg.norm(cross), 6) + 0.0)
        out[key] = out.get(key, 0.0) + area
    return out


def signed_volume(triangles: np.ndarray) -> float:
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)


def corner_set(triangles: np.ndarray) -> set:
    return {tuple(np.round(c, 3)) for c in triangles.reshape(-1, 3)}


def write_slpk(tmp_path, shapes, attrs, **options):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(s) for s in shapes])
    options = {"outputPath": str(tmp_path), "baseName": "layer", "sceneType": "Local", **options}
    assert generator.generate_model(attrs, str(EXTRUSION), I3S, options) == []
    return read_package(tmp_path / "layer.slpk")


def model_vertices(shapes, attrs):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(s) for s in shapes])
    models = generator.generate_model(attrs, str(EXTRUSION), "com.esri.pyprt.PyEncoder", {})
    return [np.asarray(m.get_vertices()).reshape(-1, 3) for m in models]


# --- the tests -------------------------------------------------------------------------------


def test_the_documents_validate_against_the_specification_schemas(tmp_path):
    package = write_slpk(tmp_path, [SQUARE, SMALL], [FIXED], sceneWkid="3857")
    for document, schema in (("3dSceneLayer.json", "3DSceneLayer.cmn.0107.json"),
                             ("nodepages/0.json", "nodePage.cmn.0107.json")):  # fmt: skip
        errors = [e.message for e in schema_validator(schema).iter_errors(package[document])]
        assert errors == [], f"{document}: {errors[:3]}"
    layer = package["3dSceneLayer.json"]
    assert layer["layerType"] == "3DObject" and layer["store"]["version"] == "1.7"
    assert layer["spatialReference"]["wkid"] == 3857
    metadata = package["metadata.json"]
    assert metadata["I3SVersion"] == "1.7" and metadata["nodeCount"] == 2
    assert metadata["resourceCompressionType"] == "GZIP"


def test_a_broken_document_fails_the_schema():
    """The validation can fail: a node without its box, a layer of an unknown type."""
    assert list(schema_validator("nodePage.cmn.0107.json").iter_errors({"nodes": [{"index": 0}]}))
    layer = {"id": 0, "version": "x", "layerType": "Mesh", "capabilities": [], "store": {}}
    assert list(schema_validator("3DSceneLayer.cmn.0107.json").iter_errors(layer))


def test_the_geometry_read_back_is_the_model(tmp_path):
    package = write_slpk(tmp_path, [SQUARE, SMALL], [FIXED])
    layer, nodes = package["3dSceneLayer.json"], package["nodepages/0.json"]["nodes"]
    root = nodes[layer["nodePages"]["rootIndex"]]
    (leaf,) = [nodes[i] for i in root["children"]]
    mesh = leaf["mesh"]["geometry"]
    definition = layer["geometryDefinitions"][mesh["definition"]]["geometryBuffers"][0]
    buffer = geometry_buffer(package[f"nodes/{mesh['resource']}/geometries/0.bin"], definition)
    positions = buffer["position"].astype(float) + leaf["obb"]["center"]
    assert len(positions) == mesh["vertexCount"] and len(positions) % 3 == 0
    # every corner within the node's box (a local box: no turn)
    assert leaf["obb"]["quaternion"] == [0, 0, 0, 1]
    low = np.subtract(leaf["obb"]["center"], leaf["obb"]["halfSize"])
    high = np.add(leaf["obb"]["center"], leaf["obb"]["halfSize"])
    assert np.all(positions >= low - 1e-4) and np.all(positions <= high + 1e-4)
    # each feature's faces are its shape's model, vertex for vertex
    ids, ranges = buffer["featureId"].ravel().tolist(), buffer["faceRange"].tolist()
    assert ids == [1, 2] and ranges[0][0] == 0 and ranges[1][0] == ranges[0][1] + 1
    triangles = scene_to_cga(positions).reshape(-1, 3, 3)
    for expected, (first, last) in zip(
        model_vertices([SQUARE, SMALL], [FIXED]), ranges, strict=True
    ):
        corners = triangles[first : last + 1].reshape(-1, 3)
        found = {tuple(np.round(c, 4)) for c in corners}
        assert found == {tuple(np.round(v, 4)) for v in expected}
    # a closed box 10 x 10 x 23: its surface, and outward normals (closed form)
    corners = triangles[ranges[0][0] : ranges[0][1] + 1]
    crosses = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    assert np.linalg.norm(crosses, axis=1).sum() / 2 == pytest.approx(
        2 * 100 + 4 * 10 * 23, rel=1e-6
    )
    outward = np.einsum("ij,ij->i", crosses, corners.mean(axis=1) - [5.0, 11.5, 5.0])
    assert np.all(outward > 0)
    normals = scene_to_cga(buffer["normal"].astype(float))[: 3 * len(corners)]
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)
    # the rule's color(buildingColor), "#FF00FF", on every vertex, opaque
    assert {tuple(c) for c in buffer["color"].tolist()} == {(255, 0, 255, 255)}
    assert layer["materialDefinitions"][0]["alphaMode"] == "opaque"


def test_the_reader_reads_cityengines_package_and_finds_the_same_triangles(tmp_path):
    """The reader on a package PyPRT 1.12 wrote (tests/data/i3s-pyprt): it holds the same
    models, and shapegen's package the same triangles, feature for feature."""
    theirs = feature_triangles(read_package(CITYENGINE_PACKAGE))
    ours = feature_triangles(write_slpk(tmp_path, [SQUARE, SMALL], [FIXED], sceneWkid="3857"))
    assert [len(t) for t in ours] == [len(t) for t in theirs] == [12, 12]
    for mine, reference in zip(ours, theirs, strict=True):
        assert corner_set(mine) == corner_set(reference)
        # the same faces, turned the same way: the area facing each direction (the diagonals
        # that cut a quad may differ)
        assert area_by_normal(mine) == pytest.approx(area_by_normal(reference))
        # and enclosing the same volume, positive: outward on both (divergence theorem)
        assert signed_volume(mine) == pytest.approx(signed_volume(reference), rel=1e-6)
        assert signed_volume(reference) > 0


def test_no_geometry_is_an_empty_node_and_still_valid(tmp_path):
    """A shape that cannot be generated (a hole named by a face index the shape does not
    have, here) has no feature."""
    holed = pyprt.InitialShape(
        SQUARE + [2, 0, 2, 8, 0, 8, 2, 0, 8], list(range(7)), [4, 3], [[0, 5]]
    )
    generator = pyprt.ModelGenerator([holed])
    options = {"outputPath": str(tmp_path), "baseName": "layer", "sceneType": "Local"}
    generator.generate_model([FIXED], str(EXTRUSION), I3S, options)
    package = read_package(tmp_path / "layer.slpk")
    assert "mesh" not in package["nodepages/0.json"]["nodes"][1]
    assert not any("geometries" in name for name in package["_order"])
    for document, schema in (("3dSceneLayer.json", "3DSceneLayer.cmn.0107.json"),
                             ("nodepages/0.json", "nodePage.cmn.0107.json")):  # fmt: skip
        assert not list(schema_validator(schema).iter_errors(package[document]))


def test_the_hash_index_is_last_and_finds_every_entry(tmp_path):
    package = write_slpk(tmp_path, [SQUARE], [FIXED])
    assert package["_order"][-1] == HASH_INDEX
    table = package[HASH_INDEX]
    assert len(table) == 24 * (len(package["_order"]) - 1)
    rows = [
        (table[k : k + 16], struct.unpack_from("<Q", table, k + 16)[0])
        for k in range(0, len(table), 24)
    ]
    keys = [struct.unpack("<QQ", digest) for digest, _ in rows]
    assert keys == sorted(keys)
    offsets = dict(rows)
    raw = package["_bytes"]
    for name in package["_order"][:-1]:
        offset = offsets[hashlib.md5(name.lower().encode()).digest()]
        assert raw[offset : offset + 4] == b"PK\x03\x04"  # a local file header ...
        length = struct.unpack_from("<H", raw, offset + 26)[0]
        assert raw[offset + 30 : offset + 30 + length].decode() == name  # ... of that entry


def test_reports_are_feature_attributes(tmp_path):
    package = write_slpk(tmp_path, [SQUARE, SMALL], [FIXED])
    layer = package["3dSceneLayer.json"]
    storage = {s["name"]: s for s in layer["attributeStorageInfo"]}
    object_ids = package[f"nodes/1/attributes/{storage['OID']['key']}/0.bin"]
    assert struct.unpack("<III", object_ids) == (2, 1, 2)
    heights = package[f"nodes/1/attributes/{storage['Min Height.0']['key']}/0.bin"]
    count, *values = struct.unpack("<Idd", heights)
    assert count == 2 and values == [23.0, 23.0]
    text = (
        package[f"nodes/1/attributes/{storage['Text']['key']}/0.bin"] if "Text" in storage else None
    )
    if text is not None:
        count, total = struct.unpack_from("<II", text)
        sizes = struct.unpack_from(f"<{count}I", text, 8)
        assert sum(sizes) == total and len(text) == 8 + 4 * count + total


def test_a_global_scene_is_in_degrees_from_web_mercator_metres(tmp_path):
    package = write_slpk(tmp_path, [SQUARE], [FIXED], sceneType="Global")
    layer, nodes = package["3dSceneLayer.json"], package["nodepages/0.json"]["nodes"]
    assert layer["spatialReference"]["wkid"] == 4326
    leaf = nodes[1]
    buffer = geometry_buffer(
        package["nodes/1/geometries/0.bin"], layer["geometryDefinitions"][0]["geometryBuffers"][0]
    )
    lon_lat_z = buffer["position"].astype(float) + leaf["obb"]["center"]
    # x = 10 m east on the equator is 10 / R radians of longitude; z = 10 m south -> latitude
    assert lon_lat_z[:, 0].max() == pytest.approx(
        math.degrees(10 / WEB_MERCATOR_RADIUS_M), rel=1e-5
    )
    south = math.degrees(2 * math.atan(math.exp(-10 / WEB_MERCATOR_RADIUS_M)) - math.pi / 2)
    assert lon_lat_z[:, 1].min() == pytest.approx(south, rel=1e-5)
    assert lon_lat_z[:, 2].max() == pytest.approx(23.0, abs=1e-4)
    assert np.linalg.norm(leaf["obb"]["quaternion"]) == pytest.approx(1.0)


def test_per_leaf_features_and_options_that_change_the_layer(tmp_path):
    options = {"layerBackfaceCulling": [True], "layerName": ["Blocks"], "compression": False}
    package = write_slpk(
        tmp_path, [SQUARE, SMALL], [FIXED], layerFeatureGranularity=["1"], **options
    )
    layer = package["3dSceneLayer.json"]
    assert layer["name"] == "Blocks" and layer["materialDefinitions"][0]["cullFace"] == "back"
    assert package["metadata.json"]["resourceCompressionType"] == "NONE"
    assert not any(name.endswith(".gz") for name in package["_order"])
    generator = pyprt.ModelGenerator([pyprt.InitialShape(s) for s in (SQUARE, SMALL)])
    models = generator.generate_model([FIXED], str(EXTRUSION), "com.esri.pyprt.PyEncoder", {})
    leaves = sum(len(m.model.blocks) + len(m.model.surfaces) for m in models)
    assert package["nodepages/0.json"]["nodes"][1]["mesh"]["geometry"]["featureCount"] == leaves


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"bogus": 1}, "not bogus"),
        ({"sceneType": "Planet"}, "not Local or Global"),
        ({"layerEnabled": [False]}, "only True"),
        ({"layerName": ["a", "b"]}, "one layer"),
        ({"layerName": "a"}, "per-layer list"),
        ({"layerFeatureGranularity": ["2"]}, "feature granularity"),
        ({"maxDepth": 1}, "at least 2"),
        ({"author": "me"}, "no field for it"),
        ({"sceneType": "Local", "sceneWkid": "4326"}, "use Global"),
        ({"errorFallback": True}, "only False"),
    ],
)
def test_options_are_refused_with_one_line_and_nothing_written(tmp_path, options, message):
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    with pytest.raises(OptionError, match=message) as caught:
        generator.generate_model(
            [FIXED], str(EXTRUSION), I3S, {"outputPath": str(tmp_path), **options}
        )
    assert "\n" not in str(caught.value)
    assert list(tmp_path.iterdir()) == []


def test_existing_files_skip_keeps_the_package(tmp_path):
    (tmp_path / "layer.slpk").write_bytes(b"kept")
    generator = pyprt.ModelGenerator([pyprt.InitialShape(SQUARE)])
    options = {"outputPath": str(tmp_path), "baseName": "layer", "existingFiles": "SKIP"}
    generator.generate_model([FIXED], str(EXTRUSION), I3S, options)
    assert (tmp_path / "layer.slpk").read_bytes() == b"kept"
