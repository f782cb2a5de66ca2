"""A glTF 2.0 document of named triangle meshes, written as .glb or single-file .gltf.

What shapegen's files need of glTF and no more: one node per mesh (its name and ``extras``),
one primitive per mesh (float32 ``POSITION``, uint32 indices, triangles), a metallic-roughness
material by colour shared by the meshes of that colour, and the scene's ``extras``. Written
here rather than through a general scene library because that library's import (0.4 s, most
of it scipy.spatial, which writing never uses) was half of a small build's whole run. The
layout follows the specification (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html):
the binary chunk holds every array, each at a 4-byte boundary, and each position accessor
carries its ``min`` and ``max``.
"""

from __future__ import annotations

__all__ = ["GltfDocument", "glb_bytes"]

import base64
import json
import struct

import numpy as np

_FLOAT, _UINT32 = 5126, 5125  # accessor componentType
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963  # bufferView target
_TRIANGLES = 4


class GltfDocument:
    """Meshes added one by one (:meth:`add_mesh`), encoded once (:meth:`glb`, :meth:`gltf`)."""

    def __init__(self, extras: dict | None = None):
        self._scene: dict = {"nodes": []}
        if extras:
            self._scene["extras"] = extras
        self._nodes: list[dict] = []
        self._meshes: list[dict] = []
        self._materials: list[dict] = []
        self._material_index: dict[str, int] = {}
        self._accessors: list[dict] = []
        self._views: list[dict] = []
        self._chunks: list[bytes] = []
        self._length = 0
        self._written: dict[tuple[bytes, str], int] = {}  # one accessor per distinct array

    def add_mesh(
        self,
        name: str,
        vertices: np.ndarray,
        triangles: np.ndarray,
        color: np.ndarray,
        extras: dict | None = None,
        double_sided: bool = False,
    ) -> None:
        """A node ``name`` drawing ``triangles`` (``(t, 3)`` indices into the ``(n, 3)``
        ``vertices``) in ``color`` (RGBA 0..255; below 255 alpha it is blended)."""
        vertices = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1, 3)
        triangles = np.ascontiguousarray(triangles, dtype=np.uint32).reshape(-1)
        if not len(triangles):  # glTF accessors count at least one item
            raise ValueError(f"glTF node {name!r}: a mesh without triangles")
        indices = self._accessor(triangles, "SCALAR")
        positions = self._accessor(vertices, "VEC3")
        primitive = {
            "attributes": {"POSITION": positions},
            "indices": indices,
            "mode": _TRIANGLES,
            "material": self._material(color, double_sided),
        }
        self._meshes.append({"name": name, "primitives": [primitive]})
        node = {"name": name, "mesh": len(self._meshes) - 1}
        if extras is not None:
            node["extras"] = extras
        self._scene["nodes"].append(len(self._nodes))
        self._nodes.append(node)

    def glb(self) -> bytes:
        """The binary glTF of the document."""
        body = b"".join(self._chunks)
        return glb_bytes(self._document(None if not body else {"byteLength": len(body)}), body)

    def gltf(self) -> bytes:
        """The JSON glTF with its one buffer embedded as a base64 data URI."""
        body = b"".join(self._chunks)
        buffer = None
        if body:
            uri = "data:application/octet-stream;base64," + base64.b64encode(body).decode()
            buffer = {"byteLength": len(body), "uri": uri}
        return json.dumps(self._document(buffer), separators=(",", ":"), allow_nan=False).encode()

    # ------------------------------------------------------------------------------ parts
    def _accessor(self, array: np.ndarray, kind: str) -> int:
        """The accessor of ``array`` (uint32 indices or float32 points), written once: the
        meshes of one shape (the boxes' indices, a repeated surface) share it."""
        data = array.tobytes()
        index = self._written.get((data, kind))
        if index is not None:
            return index
        if kind == "VEC3":
            component, target, count = _FLOAT, _ARRAY_BUFFER, len(array)
            low, high = array.min(axis=0).tolist(), array.max(axis=0).tolist()
        else:
            component, target, count = _UINT32, _ELEMENT_ARRAY_BUFFER, array.size
            low, high = [int(array.min())], [int(array.max())]
        self._views.append(
            {"buffer": 0, "byteOffset": self._length, "byteLength": len(data), "target": target}
        )
        self._chunks.append(data)  # 4-byte items, so every view starts at a 4-byte boundary
        self._length += len(data)
        self._accessors.append(
            {
                "bufferView": len(self._views) - 1,
                "componentType": component,
                "count": int(count),
                "type": kind,
                "min": low,
                "max": high,
            }
        )
        index = self._written[data, kind] = len(self._accessors) - 1
        return index

    def _material(self, color, double_sided: bool) -> int:
        color = np.asarray(color, dtype=np.uint8).reshape(4)
        name = "shapegen-" + "".join(f"{c:02x}" for c in color) + ("-2" if double_sided else "")
        index = self._material_index.get(name)
        if index is None:
            material = {
                "name": name,
                "pbrMetallicRoughness": {
                    "baseColorFactor": (color / 255.0).tolist(),
                    "metallicFactor": 0.0,
                    "roughnessFactor": 0.9,
                },
            }
            if color[3] < 255:
                material["alphaMode"] = "BLEND"
            if double_sided:
                material["doubleSided"] = True
            index = self._material_index[name] = len(self._materials)
            self._materials.append(material)
        return index

    def _document(self, buffer: dict | None) -> dict:
        document = {"asset": {"version": "2.0", "generator": "shapegen"}, "scene": 0}
        scene = {key: value for key, value in self._scene.items() if value}
        document["scenes"] = [scene]
        if self._meshes:  # glTF's arrays are absent rather than empty
            document.update(
                nodes=self._nodes,
                meshes=self._meshes,
                materials=self._materials,
                accessors=self._accessors,
                bufferViews=self._views,
                buffers=[buffer],
            )
        return document


def glb_bytes(document: dict, binary: bytes) -> bytes:
    """A binary glTF of ``document`` (its JSON) and ``binary`` (its one buffer): a 12-byte
    header, the JSON chunk padded with spaces and the binary chunk with zeros to 4 bytes."""
    text = json.dumps(document, separators=(",", ":"), allow_nan=False).encode("utf-8")
    text += b" " * (-len(text) % 4)
    binary += b"\x00" * (-len(binary) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text
    if binary:
        chunks += struct.pack("<I4s", len(binary), b"BIN\x00") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks
