"""OBJ polygons: the vertices and the faces of an OBJ text, each face kept whole.

One reader for every OBJ file shapegen takes as polygons: an asset (``i("window.obj")``), a lot
(``--lot lot.obj``, its first face) and a PyPRT initial shape. Faces stay polygons: a library
reader fans them into triangles, and a fan of a face that is not convex covers more than the
face. Materials, groups, texture coordinates and normals are skipped (``f 1/2/3`` is vertex 1);
a negative index counts back from the last vertex read; a line ending in a backslash goes on
on the next line (the OBJ format's continuation: envelope2002's glass_door.obj has long faces
written so). Mesh models (blocks from OBJ, glTF, PLY, STL) are :mod:`shapegen.readers.meshes`',
through trimesh.
"""

from __future__ import annotations

__all__ = ["obj_polygons"]

import numpy as np

from shapegen.errors import InputFormatError


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
    vertices: list[list[float]] = []
    faces: list[list[int]] = []
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
        elif fields[0] == "f":
            face = []
            for item in fields[1:]:
                try:
                    index = int(item.split("/")[0])
                except ValueError:
                    raise InputFormatError(f"{where}:{number}: bad face corner {item!r}") from None
                position = index - 1 if index > 0 else len(vertices) + index
                if not 0 <= position < len(vertices):
                    raise InputFormatError(
                        f"{where}:{number}: the face names vertex {index}, which is not defined"
                    )
                face.append(position)
            faces.append(face)
    return np.array(vertices, dtype=float).reshape(-1, 3), faces


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
