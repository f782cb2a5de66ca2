"""What an initial shape read from an OBJ file carries for texturing, and its faces' share.

PyPRT's ``InitialShape(path, max_dir_recursion_depth)`` reads an OBJ file's texture coordinates
(``vt``) and its materials (``mtllib``, ``usemtl``; the library's ``Kd`` and ``map_Kd``), and
the encoders write them: PyPRT 1.12's FBX encoder, on an identity rule, writes the OBJ's
coordinates as the mesh's UV layer and its material with the diffuse texture, and copies the
texture beside the file. The files an OBJ names are found as CityEngine's runtime finds them:
in the OBJ's folder or in a folder at most ``max_dir_recursion_depth`` folders below it
(measured: PyPRT's ``OBJ-Bonnland-nested`` test file, whose library is two folders down,
finds it with depth 2 and warns "Could not resolve material" with 0 or 1); a texture name is
relative to its library's folder and must lie within the same reach. What is not found is a
warning and the faces go on without it, as there.

A derived face takes the coordinates (and material) of the initial face it lies on, or over
(an extrusion's top and sides, as CityEngine's runtime gives them:
:func:`~shapegen.geometry.texture_transfer.carried_uvs`); a leaf whose rule set its own texture
or texture coordinates (``texture``, ``setupProjection``...) takes none, as shapegen does not
compute those. :func:`texture_warning` says how many faces of a model are left without the
coordinates they would carry in CityEngine.
"""

from __future__ import annotations

__all__ = ["InitialTexture", "SurfaceMaterial", "face_look", "face_textures", "initial_texture",
           "moving_operations", "placed_textures", "texture_warning"]  # fmt: skip

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.geometry.asset_cleanup import cleaned_polygons_and_corners
from shapegen.readers.files import read_input_bytes


@dataclass(frozen=True)
class SurfaceMaterial:
    """An OBJ material as the encoders write it: its name, diffuse colour ``(r, g, b)`` (0..1,
    as the library gives it) and its diffuse texture file (None: none, or not found)."""

    name: str
    diffuse: tuple[float, float, float]
    texture: Path | None


@dataclass(frozen=True)
class InitialTexture:
    """An initial shape's faces as texturing sees them: each face's corners ``(k, 3)`` (m, where
    the model is derived), its corners' texture coordinates ``(k, 2)`` (None: the file gives
    none) and its material (an index into ``materials``, or None)."""

    faces: list[np.ndarray]
    uvs: list[np.ndarray | None]
    face_materials: list[int | None]
    materials: list[SurfaceMaterial]
    #: :func:`face_textures`' answers by leaf and faces: the warning and the encoders ask alike
    memo: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def has_uvs(self) -> bool:
        return any(uv is not None for uv in self.uvs)


def initial_texture(path: Path, depth: int) -> tuple[InitialTexture | None, list[str]]:
    """The texturing of the OBJ file ``path`` (None for another format, or an OBJ with neither
    texture coordinates nor materials) and the warnings for what it names but is not found.
    Its faces are cleaned as :func:`~shapegen.prt.initial_shapes.start_of` cleans them."""
    from shapegen.readers.obj import obj_surface

    if path.suffix.lower() != ".obj":
        return None, []
    text = read_input_bytes(path, "initial shape file").decode("utf-8", errors="replace")
    surface = obj_surface(text, str(path))
    if not surface.libraries and all(uv is None for uv in surface.face_uvs):
        return None, []
    vertices, faces, corners = cleaned_polygons_and_corners(surface.vertices, surface.faces)
    warnings: list[str] = []
    library = _materials(path, surface.libraries, depth, warnings)
    named = sorted({name for name in surface.face_materials if name in library})
    materials = [library[name] for name in named]
    number = {name: k for k, name in enumerate(named)}
    missing = sorted({m for m in surface.face_materials if m and m not in library})
    if missing and surface.libraries and len(library):
        warnings.append(f"{path}: no material {', '.join(map(repr, missing))} in its libraries")
    # each cleaned face's source face: the one its first corner came from
    starts = np.cumsum([0, *(len(face) for face in surface.faces)])
    corner_uvs = [
        uv if uv is not None else np.full((len(face), 2), np.nan)
        for face, uv in zip(surface.faces, surface.face_uvs, strict=True)
    ]
    flat_uvs = np.concatenate(corner_uvs) if corner_uvs else np.zeros((0, 2))
    out_faces, out_uvs, out_materials = [], [], []
    for face, ids in zip(faces, corners, strict=True):
        source = int(np.searchsorted(starts, ids[0], side="right") - 1)
        uv = flat_uvs[ids]
        out_faces.append(vertices[face])
        out_uvs.append(None if np.isnan(uv).any() else uv)
        out_materials.append(number.get(surface.face_materials[source]))
    texture = InitialTexture(out_faces, out_uvs, out_materials, materials)
    if not texture.has_uvs and not materials:
        return None, warnings
    return texture, warnings


def _materials(path: Path, names: list[str], depth: int, warnings: list[str]) -> dict:
    """The materials of the libraries ``names`` (relative to the OBJ's folder), each found
    within ``depth`` folders below it; a warning for each library or texture not found."""
    from shapegen.readers.mtl import mtl_materials

    out: dict[str, SurfaceMaterial] = {}
    root = path.parent
    for name in names:
        library = _found(root, root, name, depth)
        if library is None:
            warnings.append(
                f"{path}: could not resolve material library {name!r} within"
                f" {depth} folder(s) below the file's (max_dir_recursion_depth): unavailable"
            )
            continue
        text = read_input_bytes(library, "material library").decode("utf-8", errors="replace")
        try:
            materials = mtl_materials(text, str(library))
        except InputFormatError as exc:
            warnings.append(f"{exc}: the library is not read")
            continue
        for material in materials.values():
            texture = None
            if material.texture:
                texture = _found(library.parent, root, material.texture, depth)
                if texture is None:
                    warnings.append(
                        f"{library}: could not resolve texture {material.texture!r} of material"
                        f" {material.name!r} within {depth} folder(s) below {root}: unavailable"
                    )
            out.setdefault(material.name, SurfaceMaterial(material.name, material.diffuse, texture))
    return out


def _found(folder: Path, root: Path, name: str, depth: int) -> Path | None:
    """The file ``name`` (relative to ``folder``) if it exists in ``root`` or at most ``depth``
    folders below it, else None."""
    target = (folder / name.replace("\\", "/")).resolve()
    try:
        inside = target.relative_to(root.resolve())
    except ValueError:
        return None
    if len(inside.parts) - 1 > max(depth, 0) or not target.is_file():
        return None
    return target


def face_textures(leaf, faces, texture: InitialTexture | None) -> list[tuple]:
    """For each face of ``leaf`` (``faces``: vertex-index tuples over ``leaf.vertices``) its
    texture coordinates ``(k, 2)`` or None, its material (an index into
    ``texture.materials``) or None, and whether it lies on an initial face. A leaf whose rule
    set its own texture or texture coordinates takes none of the initial shape's."""
    from shapegen.geometry.texture_transfer import carried_uvs

    if texture is None:
        return [(None, None, False)] * len(faces)
    look = leaf.appearance
    if look is not None and (look.texture is not None or look.uv):
        return [(None, None, False)] * len(faces)
    key = (id(leaf), tuple(tuple(int(i) for i in face) for face in faces))
    if key in texture.memo:
        return texture.memo[key][1]
    found = carried_uvs(
        np.asarray(leaf.vertices, dtype=float),
        faces,
        texture.faces,
        [uv if uv is not None else np.zeros((len(f), 2)) for f, uv in
         zip(texture.faces, texture.uvs, strict=True)],
    )  # fmt: skip
    out = []
    for match in found:
        if match is None:
            only = 0 if len(texture.materials) == 1 else None
            out.append((None, only, False))  # the shape's one material, without coordinates
            continue
        k, uv = match
        coordinates = uv if texture.uvs[k] is not None else None
        out.append((coordinates, texture.face_materials[k], True))
    texture.memo[key] = (leaf, out)  # the leaf held, so that its id is not another's
    return out


def face_look(own, texture: InitialTexture | None, source, uv) -> tuple[str, tuple, str | None]:
    """A face's material as the encoders write it, ``(name, rgb, image)``: on a textured face of
    the initial shape (``source``, its material index from :func:`face_textures`) the OBJ
    material's name, the rule's colour ``own`` over its diffuse colour, and its texture where
    the face has coordinates ``uv``; elsewhere no name (``""``), ``own`` or white, no image."""
    if source is None:
        return "", own if own is not None else (1.0, 1.0, 1.0), None
    material = texture.materials[source]
    rgb = own if own is not None else material.diffuse
    return material.name, rgb, material.texture if uv is not None else None


def texture_warning(model, texture: InitialTexture | None) -> str | None:
    """One line saying how many faces of ``model`` are left without the texture coordinates of
    the initial shape (None when every face that would carry them does)."""
    if texture is None or not texture.has_uvs:
        return None
    lost = total = 0
    own = 0
    for leaf in [*model.blocks, *model.surfaces]:
        faces = list(leaf.faces)
        total += len(faces)
        look = leaf.appearance
        if look is not None and (look.texture is not None or look.uv):
            own += len(faces)
            continue
        lost += sum(not on for _, _, on in face_textures(leaf, faces, texture))
    if not lost and not own:
        return None
    parts = []
    if lost:
        parts.append(
            f"{lost} of {total} faces are neither on nor over the initial shape's faces"
            " (moved across them, or made by an operation that does not keep them in place):"
            " shapegen carries texture coordinates only to faces lying on or over the initial"
            " faces"
        )
    if own:
        parts.append(
            f"{own} faces were given their own texture or texture coordinates, which shapegen"
            " does not compute"
        )
    return "texture coordinates: " + "; ".join(parts) + "; those faces have none"


def placed_textures(sources, folder: Path, collect: bool = True) -> dict:
    """Each texture file of ``sources`` as an encoder's file names it, ``path -> (absolute
    path, path from folder)``: copied into ``folder`` under its own name (``collect``,
    CityEngine's default; a second file of the same name and other bytes as ``name_1.png``...),
    else where it is. Each copy is written atomically."""
    import os

    from shapegen.export.atomic import atomic_write

    out, taken = {}, {}
    for source in sorted(set(sources)):
        if not collect:
            relative = os.path.relpath(source, folder).replace(os.sep, "/")
            out[source] = (str(source), relative)
            continue
        data = Path(source).read_bytes()
        name, n = Path(source).name, 0
        while name in taken and taken[name] != data:
            n += 1
            name = f"{Path(source).stem}_{n}{Path(source).suffix}"
        if name not in taken:
            taken[name] = data
            with atomic_write(folder / name, "wb") as handle:
                handle.write(data)
        out[source] = (str((folder / name).resolve()), name)
    return out


#: the operations after which a face's texture coordinates are not those of where it lies: the
#: moves carry a face's coordinates with its corners in CityEngine (t, r, s, center, translate,
#: rotate, mirror), an inserted asset or primitive has its own, a roof its own faces
_MOVING_NODES = {"Translate": "t", "Rotate": "r", "Scale": "s", "Center": "center",
                 "Insert": "i"}  # fmt: skip
_MOVING_OPERATIONS = ("translate", "rotate", "mirror", "insertAlongUV", "primitive", "roof")


def moving_operations(rule_file) -> list[str]:
    """The operations of ``rule_file`` (a grammar AST) after which shapegen's texture
    coordinates, carried by where faces lie, may not be CityEngine's, in order of first use."""
    from shapegen.grammar.tree import walk

    found: dict[str, None] = {}
    for node in walk(rule_file):
        kind = type(node).__name__
        if kind in _MOVING_NODES:
            found.setdefault(_MOVING_NODES[kind], None)
        elif kind == "Operation" and str(node.name).startswith(_MOVING_OPERATIONS):
            found.setdefault(str(node.name), None)
    return list(found)
