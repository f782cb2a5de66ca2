"""Boxes in closed form: a rectangle extruded either way, and the faces ``comp(f)`` gives them.

Most masses of a building's rules are boxes: a lot or a comp face extruded, the reveal of a
window extruded backwards (candler's ``extrude(-depth) comp(f) {...}``). Their scopes, meshes
and faces follow from the scope's origin, axes and size without fitting a scope to points,
which is what the general mesh path does (:func:`~shapegen.engine.shapes.shape.extrude_shape`
through :func:`~shapegen.geometry.extrude.extrude_faces`, ``comp(f)`` through
:func:`~shapegen.geometry.scope_frames.fitted_face_scopes`): the same numbers up to round-off (the
fitted path's ~1e-15 m), tested against it.

Two layouts, each a table of unit corners and faces in comp(f) order:

- the box filling its scope (a shape without geometry, kind ``mass``): faces in
  :data:`~shapegen.geometry.mesh.BOX_FACES` order, 0 bottom (-y), 1 top (+y), then the sides;
- the *backward box*, a rectangle extruded by a negative depth: the prism of op_extrude turned
  inside out, so face 0 is the original face (+y of the new scope, still facing where the face
  faced), face 1 the face moved back (-y), then the sides +z, +x, -z, -x, each starting where
  :func:`~shapegen.geometry.extrude.prism` starts it. Its mesh is kept (the leaf is that mesh,
  as before), marked so that ``comp(f)`` takes the closed form.

A box thinner than :data:`~shapegen.tolerances.COINCIDENT_REL` of its extent (or of 1 m) along
any axis takes the general path, whose degenerate faces and sizes snapped to 0 these tables do
not model.
"""

from __future__ import annotations

__all__ = [
    "BoxFaces",
    "box_faces_of",
    "extruded_backwards",
    "extruded_rectangle",
    "mark_extruded_backwards",
]

import math

import numpy as np

from shapegen.geometry.mesh import BOX_FACES, Mesh
from shapegen.geometry.scope_frames import frame_keeping_x
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_REL

_MARK = "box_faces"  # the key of a mesh's __dict__ that holds its BoxFaces table
_BACKWARDS = "extruded_backwards"  # the key of a mesh's __dict__ marking a backward prism


class BoxFaces:
    """A box layout: unit corners ``(8, 3)``, faces (tuples of corner indices, outward, in
    comp(f) order) and, per face, its frame in the box's scope coordinates (corner in units of
    the size, x along the face's first edge, y = z x x, z the outward normal) and which scope
    sizes become the face's (sx, sy)."""

    __slots__ = (
        "corners",
        "faces",
        "normals",
        "origins",
        "frames",
        "dims",
        "spans",
        "border",
        "_columns",
    )

    def __init__(self, corners, faces, spans=(0, 1, 2), border=False):
        self.corners = np.array(corners, dtype=float)
        self.faces = faces
        self.spans = spans  # the scope axes that must have a size (a rectangle's two)
        self.border = border  # whether each face has an edge no other face shares
        origins, frames, dims, normals = [], [], [], []
        for face in faces:
            first, second, last = (self.corners[face[k]] for k in (0, 1, -1))
            x, y = second - first, last - first
            z = np.cross(x, y)
            origins.append(first)
            frames.append(np.column_stack([x, y, z]))
            dims.append((int(np.flatnonzero(x)[0]), int(np.flatnonzero(y)[0])))
            normals.append(z)
        self.origins = np.array(origins)  # (6, 3) face corners, in units of the box's size
        self.frames = np.array(frames)  # (6, 3, 3): columns x, y, z in box scope coordinates
        self.dims = np.array(dims)  # (6, 2)
        self.normals = np.array(normals)  # (6, 3) outward unit normals, scope coordinates
        # per face: its corner (units of the size), its dims, and each frame column as the box
        # axis it runs along and the sign, for the faces' scopes in Python floats
        self._columns = [
            (
                tuple(self.origins[f].tolist()),
                tuple(int(k) for k in self.dims[f]),
                tuple(
                    (int(np.flatnonzero(column)[0]), float(column[np.flatnonzero(column)[0]]))
                    for column in self.frames[f].T
                ),
            )
            for f in range(len(faces))
        ]

    def mesh(self, size) -> Mesh:
        """The box of ``size`` (m) in its scope's coordinates, marked as this layout."""
        mesh = Mesh.of_valid_faces(self.corners * np.asarray(size, float), self.faces)
        mesh.__dict__[_MARK] = self
        if self is BACKWARD:
            mark_extruded_backwards(mesh)
        return mesh

    def merged(self, scope: Scope, faces: list[int]) -> tuple[Scope, Mesh]:
        """The scope and mesh (its coordinates) of the faces ``faces`` taken as one, in the
        first one's frame (comp(f)'s ``sel = X``): the corners in that frame are the box's
        corners times the frame, whose axes are box axes, so no world point is projected."""
        used: dict[int, int] = {}
        subset = tuple(tuple(used.setdefault(i, len(used)) for i in self.faces[k]) for k in faces)
        frame = self.frames[faces[0]]
        points = (self.corners[list(used)] * scope.size) @ frame
        low = points.min(axis=0)
        rotation = scope.rotation @ frame
        merged = Scope.of_arrays(scope.origin + rotation @ low, rotation, points.max(axis=0) - low)
        return merged, Mesh.of_valid_faces(points - low, subset)

    def face_scopes(self, scope: Scope) -> list[Scope]:
        """Each face's scope as comp(f) sets it: its origin the face's first corner (world, m),
        its axes x along the face's first edge, z outward, its size (m, sz = 0). The frames
        are box axes, so each is the box's axes taken in another order, some turned round."""
        (ox, oy, oz), r, size = scope.o, scope.r, scope.d
        out = []
        for corner, (dx, dy), columns in self._columns:
            x, y, z = corner[0] * size[0], corner[1] * size[1], corner[2] * size[2]
            origin = (
                ox + r[0] * x + r[1] * y + r[2] * z,
                oy + r[3] * x + r[4] * y + r[5] * z,
                oz + r[6] * x + r[7] * y + r[8] * z,
            )
            (a, sa), (b, sb), (c, sc) = columns
            rotation = (
                sa * r[a], sb * r[b], sc * r[c],
                sa * r[3 + a], sb * r[3 + b], sc * r[3 + c],
                sa * r[6 + a], sb * r[6 + b], sc * r[6 + c],
            )  # fmt: skip
            out.append(Scope.of_floats(origin, rotation, (size[dx], size[dy], 0.0)))
        return out


FILLING = BoxFaces(
    [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
    tuple(BOX_FACES),
)
"""The box filling its scope (:meth:`~shapegen.geometry.mesh.Mesh.box`)."""

BACKWARD = BoxFaces(
    [[0, 1, 1], [1, 1, 1], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0], [0, 0, 0]],
    ((0, 1, 2, 3), (5, 4, 7, 6), (1, 0, 4, 5), (2, 1, 5, 6), (3, 2, 6, 7), (0, 3, 7, 4)),
)
"""A rectangle extruded by a negative depth: corners 0-3 the rectangle (its scope's y = the
depth), 4-7 the rectangle moved back, faces the prism's turned around (each starting on its
second corner, :func:`~shapegen.geometry.hole_rings.turned`)."""


RECTANGLES = {
    axis: BoxFaces(corners, ((0, 1, 2, 3),), spans, border=True)
    for axis, corners, spans in (
        (0, [[0, 0, 1], [0, 0, 0], [0, 1, 0], [0, 1, 1]], (1, 2)),
        (1, [[0, 0, 1], [1, 0, 1], [1, 0, 0], [0, 0, 0]], (0, 2)),
        (2, [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], (0, 1)),
    )
}
"""The rectangle filling a flat scope, by the axis it is flat along
(:meth:`~shapegen.geometry.mesh.Mesh.rectangle`): one face, all of its edges on the border."""


def _solid(scope: Scope, spans=(0, 1, 2)) -> bool:
    """Whether every side ``spans`` of ``scope`` is clearly more than round-off of its extent,
    and its axes a right-handed frame (a mirror's faces are turned: the general path)."""
    size = scope.d
    o = scope.o
    reach = max(1.0, max(abs(o[0]), abs(o[1]), abs(o[2])) + max(size))
    if min(size[k] for k in spans) <= COINCIDENT_REL * reach:
        return False
    r = scope.r
    # the determinant: x . (y x z) with x, y, z the columns
    return (
        r[0] * (r[4] * r[8] - r[7] * r[5])
        - r[3] * (r[1] * r[8] - r[7] * r[2])
        + r[6] * (r[1] * r[5] - r[4] * r[2])
    ) > 0


def box_faces_of(shape) -> BoxFaces | None:
    """The closed-form layout of ``shape`` (a :class:`~shapegen.engine.shapes.shape.Shape`)
    when it has one, else None: a mass filling its scope, a face filling its flat scope, or a
    marked backward box."""
    geometry = shape.geometry
    if geometry is None:
        if shape.kind == "mass":
            layout = FILLING
        elif shape.kind == "face":
            layout = RECTANGLES.get(shape.normal_axis)
        else:
            layout = None
    else:
        layout = geometry.__dict__.get(_MARK)
    if layout is None or not _solid(shape.scope, layout.spans):
        return None
    return layout


def mark_extruded_backwards(mesh: Mesh) -> Mesh:
    """Mark ``mesh`` as a face extruded by a negative distance (its scope's y along the face's
    normal, the prism on its -y side): see :func:`extruded_backwards`."""
    mesh.__dict__[_BACKWARDS] = True
    return mesh


def extruded_backwards(shape) -> bool:
    """Whether ``shape``'s geometry is a face extruded by a negative distance, which
    CityEngine's runtime scopes with a negative ``scope.sy`` (``extrude(-3)`` of a lot: sy -3,
    axes kept, measured with PyPRT 1.12), so that ``comp(f)`` takes the face moved back as
    ``top`` and the original face as ``bottom`` (the balconies' slabs of envelope2002,
    ``extrude(-0.3) comp(f){top: ...}``: PyPRT's top is the slab's upper face). shapegen's
    scope keeps sizes positive (y along the face's normal, the origin moved back), so comp(f)
    classes such a shape's faces with the scope's y turned round."""
    geometry = shape.geometry
    return geometry is not None and geometry.__dict__.get(_BACKWARDS, False)


def extruded_rectangle(scope: Scope, height: float):
    """``(scope, mesh)`` of the rectangle filling the flat ``scope`` (flat along its z, a comp
    face) extruded by ``height`` (m) along its normal, with op_extrude's scope (x kept, y along
    the extrusion, z = x x y, fitted): mesh None for a positive height (the box filling its
    scope), the marked backward box for a negative one. None when the closed form does not
    apply (a zero height or side, axes that are not a right-handed orthonormal frame): the
    caller takes the general path."""
    if height == 0 or not math.isfinite(height):
        return None
    r = scope.r
    x_old, y_old, z_old = (r[0], r[3], r[6]), (r[1], r[4], r[7]), (r[2], r[5], r[8])
    rotation = frame_keeping_x(x_old, z_old)
    # x kept, y the face's normal, z its -y: only then are the fitted box's corners these
    x_kept = rotation[0] * x_old[0] + rotation[3] * x_old[1] + rotation[6] * x_old[2]
    z_down = rotation[2] * y_old[0] + rotation[5] * y_old[1] + rotation[8] * y_old[2]
    if x_kept < 1.0 - COINCIDENT_REL or z_down > -1.0 + COINCIDENT_REL:
        return None
    sx, sy = scope.d[0], scope.d[1]
    depth = abs(height)
    ox, oy, oz = scope.o
    ox, oy, oz = ox + y_old[0] * sy, oy + y_old[1] * sy, oz + y_old[2] * sy
    if height < 0:
        ox, oy, oz = ox + z_old[0] * height, oy + z_old[1] * height, oz + z_old[2] * height
    box = Scope.of_floats((ox, oy, oz), rotation, (sx, depth, sy))
    if not _solid(box):
        return None
    return box, (BACKWARD.mesh(box.d) if height < 0 else None)
