"""Leaves placed together: the world corners of a derivation's box and rectangle leaves, and
the leaves with geometry (a merged ``comp(f)`` selection, a cut face, an asset) with their
areas.

A model's leaves that fill their scopes (a box after ``extrude``, a face after ``split``) are
placed in world coordinates as one stacked array operation per kind, not one mesh at a time:
their scopes' origins, rotations and sizes stacked, the unit shape scaled and turned for all
of them at once.
"""

from __future__ import annotations

__all__ = [
    "BOX_LEAF_FACES",
    "box_corners",
    "geometry_leaves",
    "placed_meshes",
    "rectangle_corners",
]

import numpy as np

from shapegen.engine.shapes.boxes import FILLING, RECTANGLES
from shapegen.engine.shapes.shape import FACE, MASS
from shapegen.geometry.convex import hole_free
from shapegen.geometry.mesh import Mesh, area_vectors, corner_layout

BOX_LEAF_FACES = (
    (0, 1, 2, 3),
    (4, 7, 6, 5),
    (0, 4, 5, 1),
    (3, 2, 6, 7),
    (0, 3, 7, 4),
    (1, 5, 6, 2),
)
"""The outward faces of a box leaf's corners (:func:`box_corners`, the unit box of
:data:`~shapegen.engine.shapes.boxes.FILLING` placed), as :meth:`Block.box
<shapegen.model.block.Block.box>` gives them: bottom, top, -z, +z, -x, +x."""


# The rectangle filling a flat scope, per flat axis, in Mesh.rectangle's corner order.
_UNIT_RECTANGLES = {axis: rectangle.corners for axis, rectangle in RECTANGLES.items()}
# The two sides a rectangle flat along an axis spans.
_SIDES = {0: (1, 2), 1: (0, 2), 2: (0, 1)}


def _placed(unit: np.ndarray, scopes: list) -> tuple[np.ndarray, np.ndarray]:
    """The corners ``unit`` (k, 3) scaled to each scope's size and placed in world coordinates
    ``(n, k, 3)``, and the scopes' sizes ``(n, 3)``."""
    origins = np.array([s.o for s in scopes])
    rotations = np.array([s.r for s in scopes]).reshape(-1, 3, 3)
    sizes = np.array([s.d for s in scopes])
    local = unit[None, :, :] * sizes[:, None, :]
    return origins[:, None, :] + np.einsum("nij,nkj->nki", rotations, local), sizes


def box_corners(scopes: list) -> np.ndarray:
    """The 8 world corners ``(n, 8, 3)`` (m) of the boxes filling ``scopes``."""
    return _placed(FILLING.corners, scopes)[0]


def rectangle_corners(scopes: list, axis: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rectangles filling flat ``scopes`` (flat along scope ``axis``): their 4 world
    corners ``(n, 4, 3)`` (m), as ``Mesh.rectangle(size, axis)`` placed by the scope gives
    them; their areas ``(n,)`` (m^2); and whether each scope is a mirror (its face then turned,
    as :meth:`~shapegen.geometry.mesh.Mesh.transformed` turns it)."""
    corners, sizes = _placed(_UNIT_RECTANGLES[axis], scopes)
    first, second = _SIDES[axis]
    areas = sizes[:, first] * sizes[:, second]
    mirrored = np.linalg.det(np.array([s.r for s in scopes]).reshape(-1, 3, 3)) < 0
    return corners, areas, mirrored


def placed_meshes(
    scopes: list, meshes: list[Mesh], measured: list[bool]
) -> tuple[list[Mesh], np.ndarray]:
    """Each mesh (scope coordinates) placed by its scope in world coordinates, as
    :meth:`~shapegen.geometry.mesh.Mesh.transformed` places it (a mirror's faces turned to face
    out), and the total face area (m^2) of those ``measured`` (0 for the others), all meshes in
    one stacked pass."""
    counts = np.array([m.n_vertices for m in meshes])
    rotations = np.array([s.r for s in scopes]).reshape(-1, 3, 3)
    origins = np.array([s.o for s in scopes])
    owner = np.repeat(np.arange(len(meshes)), counts)
    world = np.einsum("nij,nj->ni", rotations[owner], np.concatenate([m.vertices for m in meshes]))
    world += origins[owner]
    mirrored = (np.linalg.det(rotations) < 0).tolist()
    placed = []
    corners, starts, owners = [], [], []
    offset = corner_offset = 0
    for k, (mesh, count, mirror) in enumerate(zip(meshes, counts.tolist(), mirrored, strict=True)):
        faces = mesh.faces
        if measured[k] and faces:
            own_corners, own_start = corner_layout(faces)
            corners.append(own_corners + offset)
            starts.append(own_start[:-1] + corner_offset)
            owners.append(np.full(len(faces), k))
            corner_offset += len(own_corners)
        if mirror:
            faces = tuple((f[0],) + tuple(reversed(f[1:])) for f in faces)
        moved = Mesh.of_valid_faces(world[offset : offset + count], faces)
        if "is_closed" in mesh.__dict__:
            moved.__dict__["is_closed"] = mesh.is_closed  # turning every face keeps it
        placed.append(moved)
        offset += count
    totals = np.zeros(len(meshes))
    if corners:
        start = np.append(np.concatenate(starts), corner_offset)
        vectors = area_vectors(world, np.concatenate(corners), start)
        np.add.at(totals, np.concatenate(owners), 0.5 * np.linalg.norm(vectors, axis=1))
    return placed, totals


def geometry_leaves(leaves: list) -> dict[int, tuple]:
    """``{id(state): (world mesh, area m^2)}`` of the leaves with geometry (faces and masses),
    placed and measured together (:func:`placed_meshes`)."""
    states = [s for s in leaves if s.shape.kind in (FACE, MASS) and s.shape.geometry is not None]
    if not states:
        return {}
    # a face's holes are kept to the leaf, whose geometry is made of polygons without holes
    # covering the same surface: what blocks, exports and the statics' cut take
    meshes = [hole_free(s.shape.geometry) for s in states]
    # an area decides whether a face or an open shell is drawn; a closed solid's is not asked
    measured = [
        s.shape.kind == FACE or not m.is_closed for s, m in zip(states, meshes, strict=True)
    ]
    meshes, areas = placed_meshes([s.shape.scope for s in states], meshes, measured)
    return {id(s): (meshes[k], float(areas[k])) for k, s in enumerate(states)}
