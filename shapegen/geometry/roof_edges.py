"""CityEngine's roof-edge classes for ``comp(e)`` (op_comp, "Roof Edges").

- ``eave``: horizontal border edges on the bottom of the roof, oriented anti-clockwise around
  the roof (as the roof face that holds them runs);
- ``hip``: inside edges connected to at least one eave edge;
- ``valley``: inside edges whose two faces form a concavity;
- ``ridge``: inside edges that are neither hip nor valley.

Hip, valley and ridge edges are oriented upwards (the end is not lower than the start).
"Border" and "inside" are read on the roof's surfaces: faces turned down (a roof's bottom) do
not count, so an edge between a roof plane and the bottom is a border edge, and an edge between
two roof planes (or a roof plane and a gable end) is an inside edge. "On the bottom" is at the
height of the roof's lowest vertex.
"""

from __future__ import annotations

__all__ = ["ROOF_EDGE_CLASSES", "roof_edge_classes"]

import numpy as np

from shapegen.geometry.mesh import unit_face_normals
from shapegen.tolerances import COINCIDENT_M, LEVEL_REL

ROOF_EDGE_CLASSES = ("eave", "hip", "valley", "ridge")
_DOWN = -0.99  # cosine with world up of a face turned down (a bottom)


def roof_edge_classes(
    vertices: np.ndarray, faces, edges: list[tuple[int, int]]
) -> list[tuple[str, bool]]:
    """Per edge ``(a, b)`` of a mesh given in world coordinates (y up): its roof class ("" for
    none) and whether it should be turned around to run as the class says."""
    vertices = np.asarray(vertices, dtype=float)
    faces = [tuple(face) for face in faces]
    normals = unit_face_normals(vertices, faces)
    bottom = [float(n[1]) < _DOWN for n in normals]
    size = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    tolerance = LEVEL_REL * max(size, COINCIDENT_M)
    lowest = float(vertices[:, 1].min()) if len(vertices) else 0.0
    incident: dict[tuple[int, int], list[int]] = {}
    for f, face in enumerate(faces):
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            incident.setdefault((min(a, b), max(a, b)), []).append(f)

    def roof_faces(a: int, b: int) -> list[int]:
        return [f for f in incident.get((min(a, b), max(a, b)), []) if not bottom[f]]

    eave_vertices: set[int] = set()
    kinds: list[str] = []
    for a, b in edges:
        on_roof = roof_faces(a, b)
        ya, yb = vertices[a, 1], vertices[b, 1]
        if len(on_roof) == 1:
            flat = abs(ya - yb) <= tolerance
            kinds.append("eave" if flat and abs(ya - lowest) <= tolerance else "")
            if kinds[-1]:
                eave_vertices.update((a, b))
        else:
            kinds.append("inside" if len(on_roof) == 2 else "")
    out = []
    for (a, b), kind in zip(edges, kinds, strict=True):
        if kind == "eave":
            (f,) = roof_faces(a, b)
            face = faces[f]
            runs_along = any(
                face[j] == a and face[(j + 1) % len(face)] == b for j in range(len(face))
            )
            out.append(("eave", not runs_along))
            continue
        if kind != "inside":
            out.append(("", False))
            continue
        first, second = roof_faces(a, b)
        if _concave(vertices, (a, b), faces[first], normals[first], faces[second], normals[second]):
            kind = "valley"
        elif a in eave_vertices or b in eave_vertices:
            kind = "hip"
        else:
            kind = "ridge"
        out.append((kind, vertices[b, 1] < vertices[a, 1] - tolerance))
    return out


def _concave(vertices, edge, face, normal, other, other_normal) -> bool:
    """Whether ``other`` rises above the plane of ``face`` next to their shared ``edge`` (the two
    form a concavity there; a non-convex face may rise above it elsewhere)."""
    a, b = edge
    n = len(other)
    if not any(other[j] == a and other[(j + 1) % n] == b for j in range(n)):
        a, b = b, a  # as ``other`` runs: its inside is on the left
    start, end = vertices[a], vertices[b]
    inward = np.cross(other_normal, end - start)  # in ``other``'s plane, into it
    length = float(np.linalg.norm(inward))
    if length == 0:
        return False
    step = 1e-3 * float(np.linalg.norm(end - start))
    probe = 0.5 * (start + end) + inward / length * step
    return float((probe - vertices[face[0]]) @ normal) > LEVEL_REL * step
