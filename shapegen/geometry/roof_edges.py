"""CityEngine's roof-edge classes for ``comp(e)`` (op_comp, "Roof Edges").

op_comp's words, and what CityEngine's runtime (PyPRT 1.12) does with them, measured edge by
edge with comp(e) on roofs, extrusions, tapers, cubes and flat lots:

- ``eave``: "horizontal border edges on the bottom of the roof": a border edge (one face)
  within 10 degrees of the horizontal whose face looks up, its normal at least 10 degrees
  above the horizontal. Its height does not count: a shed roof's high edge is an eave, and so
  are the level edges of a hole through a roof; a gable end's foot, a wall's top and a bottom
  face's edges are not. op_comp orients it "anti-clockwise around the original face": PyPRT's
  eaves run against their face, its inside on their right, along an outline and a hole alike.
- ``valley``: an inside edge (two faces) where the faces form a concavity;
- ``hip``: another inside edge with an end on an eave;
- ``ridge``: the other inside edges: an extruded lot's level edges (top and bottom), a taper's
  sloping ones.

An inside edge within 10 degrees of the vertical has no class (a box's upright edges, a
courtyard's concave corners). Hip, valley and ridge edges run upwards. "Up", "horizontal" and
"vertical" are the shape's scope y and xz-plane (a flat lot rotated by ``rotateScope`` loses
the eaves its scope turned; ``r()`` turns the geometry with the scope and keeps them), as
op_comp's other selectors read them.

"Border" and "inside" follow CityEngine's topology: a roof's bottom, slopes and walls are
separate sheets, surfaces that share no edge (:attr:`~shapegen.geometry.mesh.Mesh.sheets`), so
an edge where two of them meet is a border edge of each (a slope's foot is an eave; a gable
end's slanting edges are nothing), where shapegen's mesh joins them. The 10 degrees: a shed
roof's sloping sides are eaves at 9.9 degrees and not at 10; its slope's edges are eaves up to
a slope of 80 degrees and not from 80.05; a taper's edges lose their ridge class at 8.9 degrees
from the vertical and keep it at 10.03.
"""

from __future__ import annotations

__all__ = ["ROOF_EDGE_CLASSES", "roof_edge_classes"]

import math

import numpy as np

from shapegen.geometry.mesh import unit_face_normals
from shapegen.tolerances import COINCIDENT_M, LEVEL_REL, ROUNDOFF_REL

ROOF_EDGE_CLASSES = ("eave", "hip", "valley", "ridge")
_LEVEL = math.sin(math.radians(10.0))  # an edge at most this steep (sine) is horizontal
_UPRIGHT = math.cos(math.radians(10.0))  # an edge at least this steep (sine) is vertical
# a face whose normal rises this much looks up (one at 10 degrees, less its round-off, too)
_UP = math.sin(math.radians(10.0)) - ROUNDOFF_REL


def roof_edge_classes(
    vertices: np.ndarray,
    faces,
    edges: list[tuple[int, int]],
    holes=(),
    sheets=(),
    edge_sheets=None,
) -> list[tuple[str, bool]]:
    """Per edge ``(a, b)`` of a mesh given in its scope's coordinates (y up), each as the first
    ring that meets it runs it (comp(e)'s order): its roof class ("" for none) and whether it
    should be turned around to run as CityEngine's runtime runs it: an eave against its face, a
    sloping hip, valley or ridge upwards, and any other edge (a level ridge, an edge of no
    class) against the ring that met it first.
    ``holes`` and ``sheets`` as :class:`~shapegen.geometry.mesh.Mesh`'s: a hole's edges
    bound its face; faces of different sheets are not joined. ``edge_sheets``: per edge, the
    sheet it is listed for (comp(e) lists an edge where sheets meet once for each), which
    reads only that sheet's faces; None reads every face along the edge."""
    vertices = np.asarray(vertices, dtype=float)
    faces = [tuple(face) for face in faces]
    normals = unit_face_normals(vertices, faces)
    sheet = list(sheets) if sheets else [0] * len(faces)
    size = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    level = LEVEL_REL * max(size, COINCIDENT_M)  # a level ridge keeps its direction
    # each face's edges as it runs, its inside on the left (a hole's ring is wound against
    # its face): (a, b) -> [(face, runs a to b, on a hole)]
    incident: dict[tuple[int, int], list[tuple[int, bool, bool]]] = {}
    for f, face in enumerate(faces):
        rings = [(face, False)] + [(ring, True) for ring in (holes[f] if holes else ()) or ()]
        for ring, hole in rings:
            for a, b in zip(ring, ring[1:] + ring[:1], strict=True):
                incident.setdefault((min(a, b), max(a, b)), []).append((f, a < b, hole))

    def rise(a: int, b: int) -> float:
        """The sine of the edge's angle with the horizontal plane."""
        d = vertices[b] - vertices[a]
        length = float(np.linalg.norm(d))
        return abs(float(d[1])) / length if length > 0 else 0.0

    kinds: list[tuple[str, list]] = []
    eave_vertices: set[int] = set()
    for k, (a, b) in enumerate(edges):
        around = incident.get((min(a, b), max(a, b)), [])
        if edge_sheets is not None:
            around = [s for s in around if sheet[s[0]] == edge_sheets[k]]
        joined = [s for s in around if sum(sheet[t[0]] == sheet[s[0]] for t in around) == 2]
        if len(around) <= 2 and len(joined) == 2:
            kinds.append(("inside", joined))
            continue
        # a border edge of each face it bounds (of a sheet that meets no other there)
        up = [s for s in around if s not in joined and float(normals[s[0]][1]) >= _UP]
        if up and rise(a, b) < _LEVEL:
            kinds.append(("eave", up))
            eave_vertices.update((a, b))
        else:
            kinds.append(("", []))
    out = []
    for (a, b), (kind, held) in zip(edges, kinds, strict=True):
        if kind == "eave":
            # against its face (PyPRT's eaves have the face's inside on their right, along
            # the outline and along a hole alike)
            _, forward, _ = held[0]
            out.append(("eave", (a < b) == forward))
            continue
        if kind != "inside" or rise(a, b) >= _UPRIGHT:
            out.append(("", True))
            continue
        (first, _, _), (second, forward, _) = held
        start, end = (a, b) if (a < b) == forward else (b, a)  # as ``second`` runs
        if _concave(vertices, (start, end), faces[first], normals[first], normals[second]):
            kind = "valley"
        elif a in eave_vertices or b in eave_vertices:
            kind = "hip"
        else:
            kind = "ridge"
        if abs(float(vertices[b, 1] - vertices[a, 1])) <= level:
            out.append((kind, True))  # a level one: against its first ring, as any other
        else:
            out.append((kind, bool(vertices[b, 1] < vertices[a, 1])))
    return out


def _concave(vertices, edge, face, normal, other_normal) -> bool:
    """Whether the face of ``other_normal``, which runs along ``edge`` (its inside on the
    left), rises above the plane of ``face`` next to their shared ``edge`` (the two form a
    concavity there; a non-convex face may rise above it elsewhere)."""
    start, end = vertices[edge[0]], vertices[edge[1]]
    inward = np.cross(other_normal, end - start)  # in the other face's plane, into it
    length = float(np.linalg.norm(inward))
    if length == 0:
        return False
    step = 1e-3 * float(np.linalg.norm(end - start))
    probe = 0.5 * (start + end) + inward / length * step
    return float((probe - vertices[face[0]]) @ normal) > LEVEL_REL * step
