"""OBJ polygons: the vertices and the faces of an OBJ text, each face kept whole.

One reader for every OBJ file shapegen takes as polygons: an asset (``i("window.obj")``), a lot
(``--lot lot.obj``, its first face) and a PyPRT initial shape. Faces stay polygons: a library
reader fans them into triangles, and a fan of a face that is not convex covers more than the
face. :func:`obj_polygons` gives the positions only (``f 1/2/3`` is vertex 1);
:func:`obj_surface` also each face corner's texture coordinates (``vt``), each face's material
(``usemtl``) and the material libraries (``mtllib``) the file names, which an initial shape
carries (:mod:`shapegen.readers.mtl` reads the libraries); normals and groups are skipped. A
negative index counts back from the last vertex (or texture coordinate) read; a line ending in
a backslash goes on on the next line (the OBJ format's continuation: envelope2002's
glass_door.obj has long faces written so). Mesh models (blocks from OBJ, glTF, PLY, STL) are
:mod:`shapegen.readers.meshes`', through trimesh.
"""

from __future__ import annotations

__all__ = ["ObjSurface", "obj_polygons", "obj_surface"]

from dataclasses import dataclass

import numpy as np

from shapegen.errors import InputFormatError


@dataclass(frozen=True)
class ObjSurface:
    """An OBJ text's polygons with what they carry for texturing.

    Attributes
    ----------
    vertices
        ``(n, 3)`` positions, the file's units.
    faces
        Each face's vertex indices (0-based), as the file turns it.
    face_uvs
        Per face its corners' ``(u, v)`` texture coordinates, ``(k, 2)``, or None for a face
        given without them (``f 1 2 3`` or ``f 1//1 ...``).
    face_materials
        Per face the name its ``usemtl`` line gave, or ``""`` before any.
    libraries
        The file names of its ``mtllib`` lines, as written (relative to the OBJ's folder).
    """

    vertices: np.ndarray
    faces: list[list[int]]
    face_uvs: list[np.ndarray | None]
    face_materials: list[str]
    libraries: list[str]


def obj_polygons(text: str, where: str) -> tuple[np.ndarray, list[list[int]]]:
    """The ``(n, 3)`` vertices and the faces (0-based vertex indices) of the OBJ ``text``.

    Raises
    ------
    InputFormatError
        ``{where}:{line}: ...``: a vertex without three numbers, a face corner that is not a
        number or names a vertex not defined before it.

    >>> vertices, faces = obj_polygons("v 0 0 0\\nv 1 0 0\\nv 1 0 1\\nf 1 2/5 -1\\n", "a.obj")
    >>> vertices.shape, faces
    ((3, 3), [[0, 1, 2]])
    """
    surface = obj_surface(text, where, texture_coordinates=False)
    return surface.vertices, surface.faces


def obj_surface(text: str, where: str, *, texture_coordinates: bool = True) -> ObjSurface:
    """The OBJ ``text``'s polygons with their texture coordinates and materials.

    Raises
    ------
    InputFormatError
        ``{where}:{line}: ...``: as :func:`obj_polygons`, and (with ``texture_coordinates``) a
        ``vt`` without two numbers or a corner naming one not defined before it.

    >>> text = "mtllib a.mtl\\nv 0 0 0\\nv 1 0 0\\nv 1 0 1\\nvt 0 0\\nvt 1 0\\nvt 1 1\\n"
    >>> surface = obj_surface(text + "usemtl brick\\nf 1/1 2/2 3/-1\\n", "a.obj")
    >>> surface.face_uvs[0].tolist(), surface.face_materials, surface.libraries
    ([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], ['brick'], ['a.mtl'])
    """
    vertices: list[list[float]] = []
    uvs: list[tuple[float, float]] = []
    faces: list[list[int]] = []
    face_uvs: list[np.ndarray | None] = []
    face_materials: list[str] = []
    libraries: list[str] = []
    material = ""
    for number, line in _logical_lines(text):
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "v":
            try:
                vertex = [float(v) for v in fields[1:4]]
            except ValueError:
                vertex = []
            if len(vertex) != 3:
                raise InputFormatError(f"{where}:{number}: a vertex needs x y z numbers")
            vertices.append(vertex)
        elif fields[0] == "vt" and texture_coordinates:
            try:  # a third number (w) may follow; textures are flat
                u, v = (float(value) for value in (fields[1:3] + ["0"])[:2])
            except ValueError:
                raise InputFormatError(
                    f"{where}:{number}: a texture coordinate needs u v numbers"
                ) from None
            uvs.append((u, v))
        elif fields[0] == "f":
            face, corners = [], []
            for item in fields[1:]:
                parts = item.split("/")
                face.append(_index(parts[0], len(vertices), "vertex", where, number, item))
                if texture_coordinates and len(parts) > 1 and parts[1]:
                    corners.append(_index(parts[1], len(uvs), "texture coordinate", where,
                                          number, item))  # fmt: skip
            faces.append(face)
            complete = texture_coordinates and len(corners) == len(face)
            face_uvs.append(np.array([uvs[k] for k in corners], dtype=float) if complete else None)
            face_materials.append(material)
        elif fields[0] == "usemtl" and texture_coordinates:
            material = line.split(None, 1)[1].strip() if len(fields) > 1 else ""
        elif fields[0] == "mtllib" and texture_coordinates:
            libraries.extend(fields[1:])
    return ObjSurface(
        np.array(vertices, dtype=float).reshape(-1, 3), faces, face_uvs, face_materials, libraries
    )


def _index(field: str, count: int, what: str, where: str, number: int, item: str) -> int:
    """The 0-based index an OBJ face corner's ``field`` names among ``count`` read so far."""
    try:
        index = int(field)
    except ValueError:
        raise InputFormatError(f"{where}:{number}: bad face corner {item!r}") from None
    position = index - 1 if index > 0 else count + index
    if not 0 <= position < count:
        raise InputFormatError(
            f"{where}:{number}: the face names {what} {index}, which is not defined"
        )
    return position


def _logical_lines(text: str):
    """``(number, line)`` for each line of ``text``, a line ending in ``\\`` joined to the
    next; the number is that of the line's first physical line."""
    pending: list[str] = []
    first = 0
    for number, line in enumerate(text.splitlines(), start=1):
        if not pending:
            first = number
        stripped = line.rstrip()
        if stripped.endswith("\\"):
            pending.append(stripped[:-1])
            continue
        yield first, " ".join([*pending, line])
        pending = []
    if pending:
        yield first, " ".join(pending)
