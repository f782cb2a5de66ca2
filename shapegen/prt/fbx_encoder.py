"""``com.esri.prt.codecs.FBXEncoder``: the generated models as ``<baseName>_0.fbx``.

Binary FBX 7.4 (:mod:`shapegen.export.fbx`), as CityEngine's runtime writes binary FBX (its
``fileType`` default); each initial shape is one node with one mesh of all its leaves, the
faces kept whole (quads, n-gons) with each face's normal at its corners, and a Lambert material
per colour. Faces lying on an initial shape read from an OBJ file carry its texture coordinates
(the mesh's UV layer) and its material with its diffuse texture, copied beside the file, as
PyPRT 1.12 writes them (:mod:`shapegen.prt.initial_textures`). The options are those
CityEngine's runtime documents for this encoder (Esri/cityengine-sdk, ``esri_prt_codecs.html``);
each is honoured or refused with one line, in :data:`FBX_OPTIONS`.

Coordinates are CGA's: metres, y up (the file says so in ``GlobalSettings``), as PyPRT 1.12
writes them (measured: its FBX of the extrusion rule reads, in metres y up, as the vertices its
PyEncoder gives).
"""

from __future__ import annotations

__all__ = ["FBX_OPTIONS", "fbx_writer"]

from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from shapegen.errors import OptionError
from shapegen.prt.encoder_options import checked_option_names

NAME = "com.esri.prt.codecs.FBXEncoder"
VERTEX_PRECISION_M = 0.001
"""CityEngine's default ``vertexPrecision``: vertices closer than 1 mm are merged."""
FBX_OPTIONS = {
    "outputPath": "the folder the file is written to",
    "baseName": "the file's name: <baseName>_0.fbx (default base_name)",
    "fileType": "BINARY (default) only: FBX 7.4 binary",
    "existingFiles": "OVERWRITE (default) or SKIP an existing file",
    "includeMaterials": "a Lambert material per leaf colour (default True), or none",
    "vertexNormals": "SET_MISSING (default), SET_ALL or PASS write each face's normal; NONE none",
    "normalsIndexing": "INDEXED or SEPARATED: normals are written per face corner either way",
    "createShapeGroups": "accepted: each initial shape is its own node either way",
    "meshGranularity": "INSTANCED (default), PER_MATERIAL or AS_GENERATED: one mesh per shape",
    "fileGranularity": "MEMORY_BUDGET (default) only: one file; START_SHAPE refused",
    "memoryBudget": "accepted: one file is written whatever its size (as with 0, no limit)",
    "localOffset": "NONE (default) only",
    "globalOffset": "[0, 0, 0] only",
    "triangulateMeshes": "False (default) only: faces are kept whole",
    "facesWithHoles": "TRIANGULATE_FACES_WITH_HOLES (default) only: an FBX polygon has no holes",
    "textureCoordinates": "FIRST or ALL (default: the one uv-set faces carry), or NONE",
    "collectTextures": "True (default): textures copied beside the file; False: named in place",
    "embedTextures": "False (default) only: a texture is a file the FBX names",
    "createTextureAtlases": "False (default) only",
    "errorFallback": "False only: a shape that fails is left out",
    "writeLog": "False (default) only",
    "shapeNameDelimiter": "accepted: nodes are named shape_<index>, no clash to resolve",
    "mergeVertices": "True (default): a shape's vertices closer than vertexPrecision are one",
    "vertexPrecision": "the distance within which vertices merge (default 0.001 m)",
    "mergeNormals": "accepted: each face corner has its face's normal, written per corner",
    "normalPrecision": "accepted: normals are not merged",
    "mergeTexcoords": "accepted: equal texture coordinates are written once (indexed)",
    "texcoordPrecision": "accepted: texture coordinates are kept as read",
    "maxAtlasDim": "accepted: no texture atlas is made",
    "atlasAddWrapBorder": "accepted: no texture atlas is made",
    "tempPath": "accepted: the file is written atomically in outputPath",
}
"""Every option the encoder takes, with what it does; any other is refused."""
REFUSED_TEXT = ("author", "applicationName", "applicationVersion", "applicationString",
                "applicationVendor")  # fmt: skip
CHOICES = {
    "fileType": ("BINARY",),
    "existingFiles": ("OVERWRITE", "SKIP"),
    "vertexNormals": ("SET_MISSING", "SET_ALL", "PASS", "NONE"),
    "normalsIndexing": ("INDEXED", "SEPARATED"),
    "meshGranularity": ("INSTANCED", "PER_MATERIAL", "AS_GENERATED"),
    "fileGranularity": ("MEMORY_BUDGET",),
    "localOffset": ("NONE",),
    "facesWithHoles": ("TRIANGULATE_FACES_WITH_HOLES",),
    # fmt: skip
    "textureCoordinates": ("NONE", "FIRST", "ALL"),
}
ONLY = {"triangulateMeshes": False, "embedTextures": False, "createTextureAtlases": False,
        "writeLog": False, "errorFallback": False}  # fmt: skip
FLAGS = ("includeMaterials", "createShapeGroups", "collectTextures",
         "mergeVertices", "mergeNormals", "mergeTexcoords", "atlasAddWrapBorder")  # fmt: skip


def fbx_writer(options: Mapping[str, object]) -> Callable[[list, Path, str], None]:
    """Check ``options`` (all but ``outputPath`` and ``baseName``) and return the writer."""
    checked_option_names(
        NAME, options, FBX_OPTIONS, REFUSED_TEXT, "shapegen writes 'shapegen' as the creator"
    )
    for name, allowed in CHOICES.items():
        if name in options and str(options[name]) not in allowed:
            if name == "fileType" and str(options[name]) == "TEXT":
                raise OptionError(f"{NAME}: fileType TEXT: shapegen writes binary FBX only")
            raise OptionError(f"{NAME}: {name} {options[name]!r}: give {', '.join(allowed)}")
    for name, allowed in ONLY.items():
        if options.get(name, allowed) is not allowed:
            raise OptionError(f"{NAME}: {name} {options[name]!r}: only {allowed} is supported")
    for name in FLAGS:
        if name in options and not isinstance(options[name], bool):
            raise OptionError(f"{NAME}: {name} is a boolean, got {options[name]!r}")
    offset = options.get("globalOffset", [0.0, 0.0, 0.0])
    try:
        zero = len(offset) == 3 and all(float(v) == 0.0 for v in offset)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        zero = False
    if not zero:
        raise OptionError(f"{NAME}: globalOffset {offset!r}: only [0, 0, 0] is supported")
    for name in ("memoryBudget", "maxAtlasDim"):
        value = options.get(name, 0)
        if isinstance(value, bool) or not isinstance(value, int):
            raise OptionError(f"{NAME}: {name} is a whole number, got {value!r}")
    for name in ("vertexPrecision", "normalPrecision", "texcoordPrecision"):
        value = options.get(name, 0.0)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise OptionError(f"{NAME}: {name} is a number, got {value!r}")
    precision = float(options.get("vertexPrecision", VERTEX_PRECISION_M))
    if not 0.0 <= precision <= 1.0:
        raise OptionError(f"{NAME}: vertexPrecision {precision!r} is not between 0 and 1 m")
    merge = precision if options.get("mergeVertices", True) else None
    existing = str(options.get("existingFiles", "OVERWRITE"))
    normals = str(options.get("vertexNormals", "SET_MISSING")) != "NONE"
    materials = options.get("includeMaterials", True)
    uvs = str(options.get("textureCoordinates", "ALL")) != "NONE"
    collect = options.get("collectTextures", True)

    def write(models: list, folder: Path, base: str) -> None:
        from shapegen.export.atomic import atomic_write
        from shapegen.export.fbx import encode_fbx

        target = folder / f"{base}_0.fbx"
        if existing == "SKIP" and target.exists():
            return
        meshes = [
            shape_mesh(model, k, materials=materials, merge=merge, uvs=uvs)
            for k, model in enumerate(models)
        ]
        meshes = [m for m in meshes if m.faces]
        placed = _placed_textures(meshes, folder, collect)
        for mesh in meshes:
            mesh.materials = [(*m[:3], placed.get(m[3])) for m in mesh.materials]
        payload = encode_fbx(meshes, normals=normals)
        with atomic_write(target, "wb") as handle:
            handle.write(payload)

    return write


def _placed_textures(meshes: list, folder: Path, collect: bool) -> dict:
    """Each texture file the meshes' materials name, as the FBX file names it
    (:func:`~shapegen.prt.initial_textures.placed_textures`)."""
    from shapegen.export.fbx import FbxTexture
    from shapegen.prt.initial_textures import placed_textures

    sources = [m[3] for mesh in meshes for m in mesh.materials if m[3] is not None]
    placed = placed_textures(sources, folder, collect)
    return {source: FbxTexture(*names) for source, names in placed.items()}


def shape_mesh(model, index: int, *, materials: bool, merge: float | None = None,
               uvs: bool = True):  # fmt: skip
    """One initial shape's leaves (a :class:`GeneratedModel`'s blocks and surfaces) as one
    :class:`~shapegen.export.fbx.FbxMesh` named ``shape_<index>``: each leaf's faces whole,
    each face's material the leaf's colour and opacity (CityEngine's default white where the
    rule set none). A face lying on a textured face of the initial shape (read from an OBJ
    file: :mod:`shapegen.prt.initial_textures`) takes its texture coordinates (with ``uvs``)
    and its material: the OBJ material's name, its diffuse colour unless the rule set one, and
    its texture (the source file's path, for the writer to place) where the face has
    coordinates. With ``merge`` (metres), vertices closer than it are one (see
    :func:`merged_vertices`)."""
    from shapegen.export.fbx import FbxMesh
    from shapegen.prt.initial_textures import face_look, face_textures

    texture = getattr(model, "initial_texture", None)
    parts, faces, face_materials, face_uvs, looks = [], [], [], [], {}
    base = 0
    for leaf in [*model.model.blocks, *model.model.surfaces]:
        points = np.asarray(leaf.vertices, dtype=float).reshape(-1, 3)
        look = leaf.appearance
        own = look.color if look is not None and look.color is not None else None
        alpha = look.opacity if look is not None else 1.0
        leaf_faces = _leaf_faces(leaf, points)
        for face, (uv, source, _) in zip(
            leaf_faces, face_textures(leaf, leaf_faces, texture), strict=True
        ):
            name, rgb, image = face_look(own, texture, source, uv)
            # faces group by the colour to 1e-6; the material holds the first one's as it is
            key = (name, *(round(float(c), 6) for c in rgb), round(float(alpha), 6), image)
            if key not in looks:
                looks[key] = (len(looks), (name, tuple(float(c) for c in rgb), alpha, image))
            face_materials.append(looks[key][0])
            faces.append([int(i) + base for i in face])
            face_uvs.append(uv if uvs else None)
        parts.append(points)
        base += len(points)
    vertices = np.concatenate(parts) if parts else np.zeros((0, 3))
    table = [
        (f"{name}_mat" if name else f"shape_{index}_material_{k}", rgb, alpha, image)
        for k, (name, rgb, alpha, image) in looks.values()
    ]
    if merge is not None and len(vertices):
        vertices, faces, kept, corners = _merged(vertices, faces, merge)
        face_materials = [face_materials[k] for k in kept]
        face_uvs = [
            None if face_uvs[k] is None else np.asarray(face_uvs[k])[ids]
            for k, ids in zip(kept, corners, strict=True)
        ]
    if not materials:
        table, face_materials = [], []
    if not any(uv is not None for uv in face_uvs):
        face_uvs = []
    return FbxMesh(f"shape_{index}", vertices, faces, face_materials, table, face_uvs)


def _leaf_faces(leaf, points: np.ndarray) -> list:
    """A leaf's faces, each whole; a face with holes as triangles covering it, as CityEngine's
    default ``facesWithHoles`` (TRIANGULATE_FACES_WITH_HOLES) writes it. A leaf with holes
    keeps its faces as CityEngine has them in ``polygons`` and, in ``faces``, polygons without
    holes covering the same surface: those of its ``faces`` that are not among ``polygons``
    are the pieces of a face with holes."""
    polygons = getattr(leaf, "polygons", None)
    if not polygons:
        return list(leaf.faces)
    from shapegen.export.surfaces import face_triangles

    whole = {tuple(int(i) for i in polygon) for polygon in polygons}
    out = []
    for face in leaf.faces:
        if tuple(int(i) for i in face) in whole:
            out.append(face)
        else:
            out.extend(face_triangles(points, [face]).tolist())
    return out


def merged_vertices(
    vertices: np.ndarray, faces: list[list[int]], precision: float
) -> tuple[np.ndarray, list[list[int]], list[int]]:
    """``vertices`` with those within ``precision`` of each other (chains included) made one,
    at the first one's place, as CityEngine's ``mergeVertices`` shares co-incident vertices;
    unused ones dropped. A face's corners that became one are written once; a face left with
    fewer than three corners is dropped. Returns the vertices, the faces and the indices of the
    faces kept."""
    vertices, faces, kept, _ = _merged(vertices, faces, precision)
    return vertices, faces, kept


def _merged(vertices: np.ndarray, faces: list[list[int]], precision: float):
    """:func:`merged_vertices`, and for each face kept the positions in its input ring of the
    corners it keeps (what each corner carries, its texture coordinates, follows them)."""
    from scipy.spatial import cKDTree

    parent = np.arange(len(vertices))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return int(i)

    for i, j in sorted(cKDTree(vertices).query_pairs(precision)):
        a, b = root(i), root(j)
        if a != b:
            parent[max(a, b)] = min(a, b)
    roots = np.array([root(i) for i in range(len(vertices))])
    out_faces, kept, corners = [], [], []
    for k, face in enumerate(faces):
        ring = [int(roots[i]) for i in face]
        stays = [n for n, c in enumerate(ring) if c != ring[n - 1]] if len(set(ring)) > 1 else []
        if len(stays) >= 3:
            out_faces.append([ring[n] for n in stays])
            kept.append(k)
            corners.append(stays)
    used = sorted({i for face in out_faces for i in face})
    number = {old: new for new, old in enumerate(used)}
    return (
        vertices[used],
        [[number[i] for i in face] for face in out_faces],
        kept,
        corners,
    )
