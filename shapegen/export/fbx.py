"""Binary FBX 7.4: meshes of polygon faces, one node each, written as Autodesk's format has them.

FBX is a tree of named records, each with a list of typed values and its own children. The
binary form (what CityEngine's runtime writes: PyPRT 1.12 writes version 7700) is the one
most readers take: Blender's importer refuses the ASCII form. Version 7400 has 32-bit record
offsets, so a file holds up to 4 GiB; the readers that read 7700 read 7400.

The layout, from the published descriptions of the format:

- the header: ``Kaydara FBX Binary  \\x00``, the bytes 0x1A 0x00, the version (uint32);
- a record: the offset of its end in the file, the number of values and their byte length
  (uint32 each), the name's length (uint8) and the name, the values, the children, and, when
  it has children (or no values), a record of 13 zero bytes closing them;
- a value: a type letter and the value, little-endian: ``I`` int32, ``L`` int64, ``D`` double,
  ``C`` bool (one byte), ``S`` text (uint32 length and the bytes); an array
  (``i``, ``d``, ...) is its length, its encoding (0, not compressed) and byte length, then the
  items;
- the top level closes with the zero record, then the footer: a 16-byte code, zeros up to the
  version (uint32) so that the file ends on a 16-byte boundary, 120 zeros, a 16-byte magic.

What Autodesk's FBX SDK asks beyond the layout (measured with CityEngine's runtime, PyPRT 1.12,
whose FBX reader is that SDK: it reported "geometry must at least contain one mesh" until each
held): object ids and the connections' ids are int64 (``L``) even when small; every object
type is declared in ``Definitions``; the footer's code goes with the file's ``FileId`` and
``CreationTime`` (a fixed triple, so the file is the same for the same models).

Objects (geometry, model, material) have int64 ids and are tied by ``Connections``: geometry
and material to their model, the model to the scene's root (id 0). A face is its corners'
vertex indices with the last written as ``-(i + 1)``. Coordinates are metres, y up, with
``UnitScaleFactor`` 100 (centimetres per unit), so a reader asking for metres reads them as they
are.

Texturing, as CityEngine's runtime writes it (PyPRT 1.12's file of a textured OBJ, read record
by record): the texture coordinates are the geometry's ``LayerElementUV`` named ``uvSet0``, one
``(u, v)`` per face corner (``ByPolygonVertex``, ``IndexToDirect``: ``UV`` and ``UVIndex``),
listed in the ``Layer``; a material's diffuse texture is a ``Texture`` object (type
``TextureVideoClip``, its ``UVSet`` uvSet0) tied to the material's ``DiffuseColor`` property
(an ``OP`` connection) and holding a ``Video`` object (a ``Clip``) that names the file, both
by ``FileName`` (absolute) and ``RelativeFilename`` (from the FBX file's folder). Colours are
written as that runtime writes them: each sRGB component c as c ** 2.2 (its file of a grey
0.5 shows 0.2176, of 128/255 0.2195).
"""

from __future__ import annotations

__all__ = ["FbxMesh", "FbxTexture", "encode_fbx"]

import struct
from dataclasses import dataclass, field

import numpy as np

VERSION = 7400
HEADER = b"Kaydara FBX Binary  \x00\x1a\x00"
ZERO_RECORD = bytes(13)
# the footer code goes with this FileId and CreationTime (the SDK checks the three together);
# the magic ends every binary FBX file
FILE_ID = bytes.fromhex("28b3 2aeb b624 ccc2 bfc8 b02a a92b fcf1")
CREATION_TIME = "1970-01-01 10:00:00:000"
FOOTER_ID = bytes.fromhex("fabc ab09 d0c8 d466 b176 fb83 1cf7 267e")
FOOTER_MAGIC = bytes.fromhex("f85a 8c6a def5 d97e ece9 0ce3 758f 290b")


#: the power CityEngine's runtime raises a colour component to in an FBX material (sRGB to
#: linear, as measured: see the module)
COLOR_GAMMA = 2.2
UV_SET = "uvSet0"


@dataclass(frozen=True)
class FbxTexture:
    """A texture file as a material names it: ``path`` absolute, ``relative`` from the FBX
    file's folder."""

    path: str
    relative: str


@dataclass
class FbxMesh:
    """One node's mesh: ``vertices`` ``(n, 3)`` metres (y up), ``faces`` (vertex indices, each
    face counter-clockwise seen from its front), and each face's material: ``face_materials``
    indexes ``materials``, each ``(name, (r, g, b), opacity)`` or ``(name, (r, g, b), opacity,
    texture)`` with an :class:`FbxTexture` (or None). ``uvs``: per face its corners' ``(k, 2)``
    texture coordinates, or None for a face without; empty when no face has any."""

    name: str
    vertices: np.ndarray
    faces: list[list[int]]
    face_materials: list[int] = field(default_factory=list)
    materials: list[tuple] = field(default_factory=list)
    uvs: list[np.ndarray | None] = field(default_factory=list)


class _Record:
    def __init__(self, name: str, *values, children: list[_Record] | None = None):
        self.name = name
        self.values = values
        self.children = children or []

    def add(self, name: str, *values) -> _Record:
        child = _Record(name, *values)
        self.children.append(child)
        return child

    def encode(self, offset: int) -> bytes:
        """The record's bytes when it starts at ``offset`` in the file."""
        values = b"".join(_value(v) for v in self.values)
        name = self.name.encode("ascii")
        start = offset + 13 + len(name) + len(values)
        body = b""
        for child in self.children:
            body += child.encode(start + len(body))
        if self.children or not self.values:
            body += ZERO_RECORD
        end = start + len(body)
        head = struct.pack("<IIIB", end, len(self.values), len(values), len(name))
        return head + name + values + body


class _Id(int):
    """An object id: written as int64 (``L``) whatever its size, as readers expect ids."""


class _Raw(bytes):
    """Bytes written as a raw value (``R``), not as text."""


def _value(value) -> bytes:
    if isinstance(value, bool):
        return b"C" + struct.pack("<?", value)
    if isinstance(value, _Raw):
        return b"R" + struct.pack("<I", len(value)) + bytes(value)
    if isinstance(value, int):
        if -(2**31) <= value < 2**31 and not isinstance(value, _Id):
            return b"I" + struct.pack("<i", value)
        return b"L" + struct.pack("<q", value)
    if isinstance(value, float):
        return b"D" + struct.pack("<d", value)
    if isinstance(value, str):
        data = value.encode("utf-8")
        return b"S" + struct.pack("<I", len(data)) + data
    if isinstance(value, np.ndarray):
        kind = {"f": ("d", "<f8"), "i": ("i", "<i4")}[value.dtype.kind]
        data = np.ascontiguousarray(value, dtype=kind[1]).tobytes()
        return kind[0].encode() + struct.pack("<III", value.size, 0, len(data)) + data
    raise TypeError(f"no FBX value type for {type(value).__name__}")


def _properties(record: _Record, rows: list[tuple]) -> None:
    block = record.add("Properties70")
    for row in rows:
        block.add("P", *row)


ROOT = _Id(0)
"""The scene's root node."""


def _object_name(name: str, kind: str) -> str:
    """An object's name as binary FBX stores it: the name, 0x00 0x01, the class."""
    return f"{name}\x00\x01{kind}"


def _face_normals(vertices: np.ndarray, faces: list[list[int]]) -> np.ndarray:
    """Each face's unit normal (Newell's sum over its corners: a polygon's area vector)."""
    normals = np.zeros((len(faces), 3))
    for k, face in enumerate(faces):
        ring = vertices[face]
        nxt = np.roll(ring, -1, axis=0)
        normal = np.cross(ring, nxt).sum(axis=0)
        length = np.linalg.norm(normal)
        normals[k] = normal / length if length > 0 else (0.0, 1.0, 0.0)
    return normals


def _uv_layer(mesh: FbxMesh) -> tuple[np.ndarray, np.ndarray]:
    """The UV layer's distinct ``(u, v)`` values and each face corner's index into them; a
    face without coordinates has (0, 0) at its corners (the layer covers every corner)."""
    rows = [
        np.asarray(uv, dtype=float).reshape(len(face), 2)
        if uv is not None
        else np.zeros((len(face), 2))
        for face, uv in zip(mesh.faces, mesh.uvs, strict=True)
    ]
    corners = np.concatenate(rows) if rows else np.zeros((0, 2))
    values, index = np.unique(corners, axis=0, return_inverse=True)
    return values, index.reshape(-1).astype(np.int32)


def _add_texture(objects: _Record, texture: FbxTexture, name: str, texture_id, video_id) -> None:
    """A ``Texture`` and the ``Video`` naming its file, as Autodesk's SDK writes them."""
    video = objects.add("Video", video_id, _object_name(name, "Video"), "Clip")
    video.add("Type", "Clip")
    _properties(video, [("Path", "KString", "XRefUrl", "", texture.path),
                        ("RelPath", "KString", "XRefUrl", "", texture.relative)])  # fmt: skip
    video.add("UseMipMap", 0)
    video.add("Filename", texture.path)
    video.add("RelativeFilename", texture.relative)
    record = objects.add("Texture", texture_id, _object_name(name, "Texture"), "")
    record.add("Type", "TextureVideoClip")
    record.add("Version", 202)
    record.add("TextureName", _object_name(name, "Texture"))
    _properties(record, [("UVSet", "KString", "", "", UV_SET), ("UseMaterial", "bool", "", "", 1)])
    record.add("Media", _object_name(name, "Video"))
    record.add("FileName", texture.path)
    record.add("RelativeFilename", texture.relative)
    record.add("ModelUVTranslation", 0.0, 0.0)
    record.add("ModelUVScaling", 1.0, 1.0)
    record.add("Texture_Alpha_Source", "None")
    record.add("Cropping", 0, 0, 0, 0)


def encode_fbx(meshes: list[FbxMesh], *, creator: str = "shapegen", normals: bool = True) -> bytes:
    """A binary FBX 7.4 file of ``meshes``, each its own node under the scene's root; with
    ``normals`` each face's normal at each of its corners."""
    header = _Record("FBXHeaderExtension")
    header.add("FBXHeaderVersion", 1003)
    header.add("FBXVersion", VERSION)
    header.add("Creator", creator)
    settings = _Record("GlobalSettings")
    settings.add("Version", 1000)
    axes = [("UpAxis", 1), ("UpAxisSign", 1), ("FrontAxis", 2), ("FrontAxisSign", 1),
            ("CoordAxis", 0), ("CoordAxisSign", 1), ("OriginalUpAxis", 1),
            ("OriginalUpAxisSign", 1)]  # fmt: skip
    _properties(
        settings,
        [(name, "int", "Integer", "", value) for name, value in axes]
        + [
            ("UnitScaleFactor", "double", "Number", "", 100.0),
            ("OriginalUnitScaleFactor", "double", "Number", "", 100.0),
        ],
    )
    objects = _Record("Objects")
    connections = _Record("Connections")
    next_id = (_Id(k) for k in range(1_000_000, 2**62))
    counts = {"Model": 0, "Geometry": 0, "Material": 0, "Texture": 0, "Video": 0}
    for mesh in meshes:
        vertices = np.asarray(mesh.vertices, dtype=float).reshape(-1, 3)
        geometry_id, model_id = next(next_id), next(next_id)
        counts["Geometry"] += 1
        counts["Model"] += 1
        geometry = objects.add("Geometry", geometry_id, _object_name(mesh.name, "Geometry"), "Mesh")
        geometry.add("Vertices", vertices.ravel())
        polygon_index = np.array(
            [i for face in mesh.faces for i in (*face[:-1], -face[-1] - 1)], dtype=np.int32
        )
        geometry.add("PolygonVertexIndex", polygon_index)
        geometry.add("GeometryVersion", 124)
        layer = _Record("Layer", 0)
        layer.add("Version", 100)
        if normals:
            per_face = _face_normals(vertices, mesh.faces)
            per_corner = np.repeat(per_face, [len(face) for face in mesh.faces], axis=0)
            element = geometry.add("LayerElementNormal", 0)
            element.add("Version", 101)
            element.add("Name", "")
            element.add("MappingInformationType", "ByPolygonVertex")
            element.add("ReferenceInformationType", "Direct")
            element.add("Normals", per_corner.ravel())
            entry = layer.add("LayerElement")
            entry.add("Type", "LayerElementNormal")
            entry.add("TypedIndex", 0)
        if any(uv is not None for uv in mesh.uvs):
            values, index = _uv_layer(mesh)
            element = geometry.add("LayerElementUV", 0)
            element.add("Version", 101)
            element.add("Name", UV_SET)
            element.add("MappingInformationType", "ByPolygonVertex")
            element.add("ReferenceInformationType", "IndexToDirect")
            element.add("UV", values.ravel())
            element.add("UVIndex", index)
            entry = layer.add("LayerElement")
            entry.add("Type", "LayerElementUV")
            entry.add("TypedIndex", 0)
        if mesh.materials:
            element = geometry.add("LayerElementMaterial", 0)
            element.add("Version", 101)
            element.add("Name", "")
            element.add("MappingInformationType", "ByPolygon")
            element.add("ReferenceInformationType", "IndexToDirect")
            element.add("Materials", np.array(mesh.face_materials, dtype=np.int32))
            entry = layer.add("LayerElement")
            entry.add("Type", "LayerElementMaterial")
            entry.add("TypedIndex", 0)
        geometry.children.append(layer)
        model = objects.add("Model", model_id, _object_name(mesh.name, "Model"), "Mesh")
        model.add("Version", 232)
        _properties(model, [("DefaultAttributeIndex", "int", "Integer", "", 0)])
        model.add("Shading", True)
        model.add("Culling", "CullingOff")
        connections.add("C", "OO", model_id, ROOT)
        connections.add("C", "OO", geometry_id, model_id)
        for name, rgb, opacity, *texture in mesh.materials:
            material_id = next(next_id)
            counts["Material"] += 1
            material = objects.add("Material", material_id, _object_name(name, "Material"), "")
            material.add("Version", 102)
            material.add("ShadingModel", "lambert")
            material.add("MultiLayer", 0)
            color = tuple(max(float(c), 0.0) ** COLOR_GAMMA for c in rgb)
            _properties(
                material,
                [
                    ("DiffuseColor", "Color", "", "A", *color),
                    ("Diffuse", "Vector3D", "Vector", "", *color),
                    ("TransparencyFactor", "Number", "", "A", float(1.0 - opacity)),
                    ("Opacity", "double", "Number", "", float(opacity)),
                ],
            )
            connections.add("C", "OO", material_id, model_id)
            if texture and texture[0] is not None:
                texture_id, video_id = next(next_id), next(next_id)
                counts["Texture"] += 1
                counts["Video"] += 1
                _add_texture(objects, texture[0], f"{name}_tex", texture_id, video_id)
                connections.add("C", "OP", texture_id, material_id, "DiffuseColor")
                connections.add("C", "OO", video_id, texture_id)
    definitions = _Record("Definitions")
    definitions.add("Version", 100)
    used = {kind: n for kind, n in counts.items() if n}
    definitions.add("Count", sum(used.values()) + 1)
    definitions.add("ObjectType", "GlobalSettings").add("Count", 1)
    for kind, n in used.items():
        template = definitions.add("ObjectType", kind)
        template.add("Count", n)
    documents = _Record("Documents")
    documents.add("Count", 1)
    document = documents.add("Document", next(next_id), "Scene", "Scene")
    _properties(document, [])
    document.add("RootNode", ROOT)
    takes = _Record("Takes")
    takes.add("Current", "")
    records = [header, _Record("FileId", _Raw(FILE_ID)), _Record("CreationTime", CREATION_TIME),
               _Record("Creator", creator), settings, documents, _Record("References"),
               definitions, objects, connections, takes]  # fmt: skip
    out = bytearray(HEADER + struct.pack("<I", VERSION))
    for record in records:
        out += record.encode(len(out))
    out += ZERO_RECORD + FOOTER_ID
    # zeros (at least one) up to the version, so that the file ends on a 16-byte boundary
    tail = 4 + 120 + len(FOOTER_MAGIC)
    out += bytes((-(len(out) + tail)) % 16 or 16)
    out += struct.pack("<I", VERSION) + bytes(120) + FOOTER_MAGIC
    return bytes(out)
