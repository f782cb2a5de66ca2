"""FBX polygons: every mesh of an FBX file placed in the scene, in metres, its faces kept whole.

Read through ufbx (``pip install 'shapegen[fbx]'``), the FBX loader of Samuli Raivio, in its
author's Python bindings: wheels for Linux, macOS and Windows, no system library, and it gives
faces as the file has them (quads, n-gons), as CityEngine's runtime reads them: the test file
of PyPRT (``EmbeddedTextures.fbx``) reads as 188 vertices and 57 faces (54 quads, two hexagons, a
heptagon) in both. Assimp's Python bindings were the other candidate; they hand out triangles
only. Each mesh is placed by its node's geometry-to-world transform, in a scene turned y up
and into metres (the file's ``UnitScaleFactor`` is centimetres in most files), as CityEngine
places it.
"""

from __future__ import annotations

__all__ = ["fbx_polygons"]

from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError

MISSING = "reading FBX needs the ufbx package: pip install 'shapegen[fbx]'"


def fbx_polygons(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    """The ``(n, 3)`` vertices (metres, y up) and the faces (0-based indices) of the FBX file.

    Raises
    ------
    InputFormatError
        ``{path}: ...``: ufbx is not installed, or the file is not a readable FBX file.
    """
    try:
        import ufbx
    except ImportError:
        raise InputFormatError(f"{path}: {MISSING}") from None
    try:
        # y up and metres, as CityEngine places an FBX file (ufbx turns the root node)
        scene = ufbx.load_file(
            str(path), target_axes=ufbx.axes_right_handed_y_up, target_unit_meters=1.0
        )
    except Exception as exc:  # ufbx raises its own error kinds for a broken file
        raise InputFormatError(f"{path}: not a readable FBX file ({exc})") from None
    parts: list[np.ndarray] = []
    faces: list[list[int]] = []
    try:
        base = 0
        for node in scene.nodes:
            mesh = node.mesh
            if mesh is None:
                continue
            m = node.geometry_to_world
            affine = np.array(
                [[m.c0.x, m.c1.x, m.c2.x, m.c3.x],
                 [m.c0.y, m.c1.y, m.c2.y, m.c3.y],
                 [m.c0.z, m.c1.z, m.c2.z, m.c3.z]]
            )  # fmt: skip
            points = np.array([[v.x, v.y, v.z] for v in mesh.vertices], dtype=float)
            points = points.reshape(-1, 3) @ affine[:, :3].T + affine[:, 3]
            corners = np.array(list(mesh.vertex_indices), dtype=np.int64) + base
            for face in mesh.faces:
                if face.num_indices >= 3:
                    start = face.index_begin
                    faces.append(corners[start : start + face.num_indices].tolist())
            parts.append(points)
            base += len(points)
            del mesh, m  # nothing may point into the scene when it is freed
    finally:
        scene.free()
    vertices = np.concatenate(parts) if parts else np.zeros((0, 3))
    return vertices, faces
