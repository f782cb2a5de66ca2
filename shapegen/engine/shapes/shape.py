"""Shapes and the scope operations of CGA: extrude, split, comp, t, r, s, center.

A :class:`Shape` is a :class:`~shapegen.model.scope.Scope` plus what fills it: a flat face (the
lot, a ``comp(f)`` face), a mass (after ``extrude``) or an inserted primitive. Its ``geometry`` is
a :class:`~shapegen.geometry.mesh.Mesh` in scope coordinates, or None when the shape fills its
scope (a box, a rectangle: the fast path every bundled rule stays on). The functions here are
pure: they take shapes or scopes and return new ones; the interpreter decides what to do with
them. A wrong use raises ``ValueError`` with a message for the user; the interpreter adds the place
in the grammar file.

Conventions (CGA's):

- a ``(width, depth)`` lot is a rectangle in the x-z plane with a corner at the origin and its
  first edge along +x; its scope axes are the world axes (y up) and its size is
  ``(width, 0, depth)``; a polygon lot's scope has x along its first edge (:func:`lot_shape`);
- ``extrude(h)`` grows a face along its normal (+y for the lot, the scope's +z for a comp face);
  a polygon face becomes a prism, faces numbered as CityEngine does (:func:`extrude_shape`);
- ``comp(f)`` gives each face a scope whose x axis runs along the face's first edge (for a box's
  sides, the bottom edge left to right seen from outside), whose z axis is the outward normal and
  whose z size is 0; a box's faces come in CityEngine's order (:data:`FACE_ORDER`);
- ``split`` slices the scope, and cuts the geometry of a shape that has one
  (:func:`split_piece`);
- ``t``, ``s`` and ``r`` act in the scope's own axes; ``r`` turns about the scope's origin, first
  about its x axis, then y, then z (degrees); the geometry moves with the scope, and ``s``
  scales it to the new size.
"""

from __future__ import annotations

__all__ = [
    "Shape",
    "FACE",
    "MASS",
    "FACE_ORDER",
    "lot_scope",
    "mesh_lot_shape",
    "extrude",
    "split_scope",
    "face_scopes",
    "translate",
    "rotate",
    "resize",
    "center",
    "rotation_matrix",
    "extrude_shape",
    "split_piece",
    "split_pieces",
    "lot_shape",
    "shape_geometry_value",
]

import math
from collections.abc import Sequence

import numpy as np

from shapegen.engine.shapes.boxes import extruded_rectangle
from shapegen.geometry.mesh import Mesh
from shapegen.model.lot import Lot, MeshLot
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL

FACE = "face"
MASS = "mass"

_AXES = {"x": 0, "y": 1, "z": 2}

# Face frames of the unit box in scope coordinates: corner (times the scope size), x, y, z axes
# (z = outward normal) and which scope sizes become the face's (sx, sy).
_FACE_FRAMES = {
    "front": ((0, 0, 1), (1, 0, 0), (0, 1, 0), (0, 0, 1), (0, 1)),
    "right": ((1, 0, 1), (0, 0, -1), (0, 1, 0), (1, 0, 0), (2, 1)),
    "back": ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, 0, -1), (0, 1)),
    "left": ((0, 0, 0), (0, 0, 1), (0, 1, 0), (-1, 0, 0), (2, 1)),
    "top": ((0, 1, 1), (1, 0, 0), (0, 0, -1), (0, 1, 0), (0, 2)),
    # PyPRT starts an extruded lot's bottom on the lot's second vertex: x runs along -x.
    "bottom": ((1, 0, 1), (-1, 0, 0), (0, 0, -1), (0, -1, 0), (0, 2)),
}
FACE_ORDER = ("bottom", "top", "front", "right", "back", "left")
"""The order of a box's faces in ``comp(f)``: the index a numeric selector refers to. It is
CityEngine's for an extruded lot (checked with PyPRT on a 12 x 8 m lot): 0 bottom, 1 top, then
the sides from the lot's first edge, which runs along +x on the lot's +z side."""


class Shape:
    """A shape of the derivation: a scope and what fills it.

    Attributes
    ----------
    scope
        The oriented box (m).
    kind
        :data:`FACE` (flat, no volume: the lot, comp faces), :data:`MASS` (a box filling the
        scope) or ``"insert"`` (a primitive fitted to the scope when the shape becomes a leaf).
    normal_axis
        For a face: the scope axis (0, 1, 2) along which it is flat and extrudes.
    insert
        For an inserted primitive: ``(name, params)``.
    geometry
        The shape's polygon mesh in scope coordinates (m), or None when the shape fills its
        scope (a box for :data:`MASS`, a rectangle for :data:`FACE`: the fast path). A scope
        operation (t, r) moves the geometry with the scope; s() scales it to the new size.
    tags
        The component tags of :meth:`mesh` (a
        :class:`~shapegen.engine.shapes.tags.ComponentTags`, or a
        :class:`~shapegen.engine.shapes.tags.Pending` carry from the shape it was made of,
        read through :func:`~shapegen.engine.shapes.tags.resolved_tags`), or None: no tag
        (most shapes). The operations that keep the components keep them.
    """

    __slots__ = ("scope", "kind", "normal_axis", "insert", "geometry", "tags")

    def __init__(
        self,
        scope: Scope,
        kind: str = MASS,
        normal_axis: int = 2,
        insert=None,
        geometry: Mesh | None = None,
        tags=None,
    ):
        self.scope = scope
        self.kind = kind
        self.normal_axis = normal_axis
        self.insert = insert
        self.geometry = geometry
        self.tags = tags

    @classmethod
    def with_geometry(cls, scope: Scope, mesh: Mesh, kind: str = MASS, normal_axis: int = 2):
        """A shape made of ``mesh`` (scope coordinates, m) in ``scope``."""
        return cls(scope, kind, normal_axis, None, mesh)

    def with_scope(self, scope: Scope) -> Shape:
        """The same shape in another scope (its geometry keeps its scope coordinates)."""
        return Shape(scope, self.kind, self.normal_axis, self.insert, self.geometry, self._kept())

    def copy(self) -> Shape:
        return Shape(
            self.scope, self.kind, self.normal_axis, self.insert, self.geometry, self._kept()
        )

    def _kept(self):
        """The tags of a shape made of these very components (moved, scaled)."""
        tags = self.tags
        if tags is None:
            return None
        from shapegen.engine.shapes.tags import kept_tags

        return kept_tags(self)

    def with_tags(self, tags) -> Shape:
        """The same shape with the component tags ``tags`` (None: none)."""
        return Shape(self.scope, self.kind, self.normal_axis, self.insert, self.geometry, tags)

    def mesh(self) -> Mesh:
        """The geometry in scope coordinates, made from the scope when the shape fills it."""
        if self.geometry is not None:
            return self.geometry
        if self.kind == FACE:
            return Mesh.rectangle(self.scope.d, self.normal_axis)
        return Mesh.box(self.scope.d)

    def world_mesh(self) -> Mesh:
        """The geometry in world coordinates (m)."""
        return self.mesh().transformed(self.scope.rotation, self.scope.origin)

    def resized(self, size) -> Shape:
        """The shape with scope size ``size`` (m), its geometry scaled along each scope axis to
        fill the new size as it filled the old one (CityEngine's ``s()``). A negative size
        mirrors the geometry along that axis within the scope of the size's magnitude (op_s:
        "negative sizes result in mirroring"; the faces stay outward, as ``mirror`` keeps
        them, so the block stays a solid)."""
        geometry = self.geometry
        if geometry is None and len(size) == 3:  # a box or a rectangle: floats only
            scope = resize(self.scope, [abs(float(v)) for v in size])
            return Shape(scope, self.kind, self.normal_axis, self.insert, None, self._kept())
        signed = np.asarray(size, float)
        scope = resize(self.scope, np.abs(signed))
        if geometry is not None:
            old = self.scope.size
            factors = np.divide(scope.size, old, out=np.ones(3), where=old > 0)
            flips = signed < 0
            geometry = geometry.scaled(np.where(flips, -factors, factors))
            if flips.any():
                geometry = geometry.moved_to(geometry.vertices + np.where(flips, scope.size, 0.0))
        return Shape(scope, self.kind, self.normal_axis, self.insert, geometry, self._kept())


def lot_scope(width: float, depth: float) -> Scope:
    """The start shape's scope: ``width`` (m) along +x, ``depth`` (m) along +z, y up, flat;
    the sizes of a checked lot (:class:`~shapegen.model.lot.Lot`, or ``@Lot``'s)."""
    return Scope.of_floats((0.0, 0.0, 0.0), _EYE, (float(width), 0.0, float(depth)))


_EYE = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)

# The scope operations below work on the scope's Python floats (Scope.o, .r, .d): a handful
# of numbers each, which numpy's per-call cost (about a microsecond) would dominate.


def extrude(scope: Scope, axis: int, height: float) -> Scope:
    """Grow a flat scope by ``height`` (m) along its scope ``axis`` (negative grows backwards)."""
    if not math.isfinite(height):
        raise ValueError(f"extrude height must be a finite number, got {height}")
    size = list(scope.d)
    size[axis] = abs(height)
    origin = scope.o
    if height < 0:
        r = scope.r
        origin = (
            origin[0] + r[axis] * height,
            origin[1] + r[3 + axis] * height,
            origin[2] + r[6 + axis] * height,
        )
    return Scope.of_floats(origin, scope.r, tuple(size))


def split_scope(scope: Scope, axis: int, start: float, size: float) -> Scope:
    """The slice ``[start, start + size]`` (m) of ``scope`` along its scope ``axis``."""
    new_size = list(scope.d)
    new_size[axis] = size
    r, (ox, oy, oz) = scope.r, scope.o
    origin = (ox + r[axis] * start, oy + r[3 + axis] * start, oz + r[6 + axis] * start)
    return Scope.of_floats(origin, r, tuple(new_size))


def face_scopes(scope: Scope) -> list[tuple[str, Scope]]:
    """The six faces of the box ``scope`` in :data:`FACE_ORDER`, each with its CGA face scope."""
    out = []
    size = scope.size
    for name in FACE_ORDER:
        corner, x, y, z, dims = _FACE_FRAMES[name]
        frame = np.array([x, y, z], dtype=float).T  # columns = face axes in scope coordinates
        origin = scope.to_world(np.asarray(corner, float) * size)
        rotation = scope.rotation @ frame
        out.append((name, Scope(origin, rotation, np.array([size[dims[0]], size[dims[1]], 0.0]))))
    return out


def translate(scope: Scope, offset: Sequence[float]) -> Scope:
    """Move the scope by ``offset`` (m) along its own axes."""
    if len(offset) != 3:
        raise ValueError(f"an offset has 3 coordinates, got {np.shape(offset)}")
    x, y, z = (float(v) for v in offset)
    return Scope.of_floats(scope.point(x, y, z), scope.r, scope.d)


def rotation_matrix(angles: Sequence[float]) -> np.ndarray:
    """Rotation by ``angles`` (degrees) about x, then y, then z (axes fixed during the turn)."""
    return np.array(rotation_entries(angles)).reshape(3, 3)


def rotation_entries(angles: Sequence[float]) -> tuple:
    """:func:`rotation_matrix`'s 9 entries row by row, as Python floats."""
    ax, ay, az = (math.radians(float(a)) for a in angles)
    cx, sx, cy, sy, cz, sz = (
        math.cos(ax),
        math.sin(ax),
        math.cos(ay),
        math.sin(ay),
        math.cos(az),
        math.sin(az),
    )
    # rz @ ry @ rx, multiplied out
    return (
        cz * cy,
        cz * sy * sx - sz * cx,
        cz * sy * cx + sz * sx,
        sz * cy,
        sz * sy * sx + cz * cx,
        sz * sy * cx - cz * sx,
        -sy,
        cy * sx,
        cy * cx,
    )


def _times(a: tuple, b: tuple) -> tuple:
    """The product of two 3x3 matrices given as 9 floats row by row."""
    return tuple(
        a[i] * b[j] + a[i + 1] * b[j + 3] + a[i + 2] * b[j + 6]
        for i in (0, 3, 6)
        for j in (0, 1, 2)
    )


def rotate(scope: Scope, angles: Sequence[float], about_center: bool = False) -> Scope:
    """Turn the scope by ``angles`` (degrees) about its own axes through its origin (or centre)."""
    turn = _times(scope.r, rotation_entries(angles))
    origin = scope.o
    if about_center:
        hx, hy, hz = (v / 2 for v in scope.d)
        cx, cy, cz = scope.point(hx, hy, hz)
        origin = (
            cx - (turn[0] * hx + turn[1] * hy + turn[2] * hz),
            cy - (turn[3] * hx + turn[4] * hy + turn[5] * hz),
            cz - (turn[6] * hx + turn[7] * hy + turn[8] * hz),
        )
    return Scope.of_floats(origin, turn, scope.d)


def resize(scope: Scope, size: Sequence[float]) -> Scope:
    """The scope with a new ``size`` (m), its origin and axes kept."""
    if isinstance(size, np.ndarray):
        size = size.tolist()
    values = [float(v) for v in size]
    if not all(math.isfinite(v) and v >= 0 for v in values):
        raise ValueError(f"scope sizes must be finite numbers >= 0, got {values}")
    if len(values) != 3:
        return Scope(scope.origin, scope.rotation, values)  # its check names the shape
    return Scope.of_floats(scope.o, scope.r, tuple(values))


def center(scope: Scope, reference: Scope, axes: str) -> Scope:
    """Move ``scope`` so that its centre lines up with ``reference``'s along ``axes`` ("xz"...),
    measured along ``reference``'s axes."""
    here = scope.point(*(v / 2 for v in scope.d))
    there = reference.point(*(v / 2 for v in reference.d))
    delta = (there[0] - here[0], there[1] - here[1], there[2] - here[2])
    shift = [0.0, 0.0, 0.0]
    for name in axes:
        direction = reference.axis(_AXES[name])
        along = direction[0] * delta[0] + direction[1] * delta[1] + direction[2] * delta[2]
        shift[0] += direction[0] * along
        shift[1] += direction[1] * along
        shift[2] += direction[2] * along
    o = scope.o
    return Scope.of_floats((o[0] + shift[0], o[1] + shift[1], o[2] + shift[2]), scope.r, scope.d)


def axis_index(name: str) -> int:
    """0, 1, 2 for "x", "y", "z"."""
    return _AXES[name]


def _box_corners(shape: Shape) -> np.ndarray | None:
    """The corners of ``shape``'s geometry in units of its scope's size, when the geometry is
    the box filling its scope with its faces in another order than
    :data:`~shapegen.geometry.mesh.BOX_FACES` (or another first corner); None otherwise."""
    mesh, size = shape.geometry, shape.scope.size
    if mesh is None or mesh.holes or size.min() <= 0:
        return None
    if not _is_scope_box(mesh.vertices, size, mesh.n_faces) or _box_fills(mesh, size):
        return None
    return np.round(mesh.vertices / size)


def _box_fills(mesh: Mesh, size: np.ndarray) -> bool:
    """Whether ``mesh`` (scope coordinates) is the box filling a scope of ``size``, its faces in
    :data:`~shapegen.geometry.mesh.BOX_FACES` order (so the fast path gives the same comp)."""
    if mesh.n_vertices != 8 or mesh.n_faces != 6 or any(len(f) != 4 for f in mesh.faces):
        return False
    box = Mesh.box(size)
    mine, its = mesh.vertices[np.array(mesh.faces)], box.vertices[np.array(box.faces)]
    slack = COINCIDENT_REL * max(float(size.max()), COINCIDENT_M)  # and 1e-5 relative, as
    return bool((np.abs(mine - its) <= slack + 1e-5 * np.abs(its)).all())  # np.allclose


def extrude_shape(
    shape: Shape, height: float, cityengine_scope: bool, kind: str = "face.normal"
) -> Shape:
    """The mass of ``shape`` (a face) extruded by ``height`` (m) along its normal; a 3D shape
    (a ``.cga`` rule's) has every face extruded along its own normal, as op_extrude does
    ("each face polygon ... is taken and extruded"), the scope's y along the first face's.

    Its scope follows CityEngine's op_extrude (x kept as far as possible, y along the
    extrusion, z normal to both, fitted to the geometry) when ``cityengine_scope`` or the face
    is flat along its y axis (the lot); otherwise (a comp face in a ``.grammar`` rule) the face's
    own scope grows along its z axis, as shapegen always did. A face filling its scope stays on
    the fast path (a box, no geometry). ``kind`` is op_extrude's extrusion type: ``face.normal``
    (the default), ``world.up`` (along world y; the scope's y too) or ``world.up.flatTop``."""
    if not math.isfinite(height):
        raise ValueError(f"extrude height must be a finite number, got {height}")
    scope = shape.scope
    solid = shape.kind != FACE  # op_extrude: every face of a 3D shape along its own normal
    cityengine_scope = cityengine_scope or solid
    world_up = kind.startswith("world.up")
    lying = not solid and shape.normal_axis == 1  # a face flat along its scope's y
    if world_up and lying and np.allclose(scope.rotation[:, 1], [0, 1, 0]):
        world_up = kind == "world.up.flatTop" and shape.geometry is not None
    fast = not solid and shape.geometry is None and (lying or not cityengine_scope)
    if not world_up and fast:
        return Shape(extrude(scope, shape.normal_axis, height), MASS)
    if not world_up and not solid and shape.geometry is None and shape.normal_axis == 2:
        boxed = extruded_rectangle(scope, height)  # a comp face: a box in closed form
        if boxed is not None:
            return Shape(boxed[0], MASS, 2, None, boxed[1])
    from shapegen.geometry.extrude import extrude_faces
    from shapegen.geometry.scope_frames import fitted_scope, rotation_keeping_x

    face = shape.mesh()
    if face.n_faces == 0:
        raise ValueError("extrude() of a shape without faces")
    up = scope.rotation.T @ np.array([0.0, 1.0, 0.0])  # world y in scope coordinates
    if world_up:
        prism = extrude_faces(face, height, up, flat_top=kind == "world.up.flatTop")
    else:
        prism = extrude_faces(face, height)
    if prism.n_faces == 0:
        raise ValueError("extrude() of a face with no area")
    world = scope.to_world(prism.vertices)
    if world_up:
        rotation = rotation_keeping_x(scope.rotation[:, 0], np.array([0.0, 1.0, 0.0]))
    elif not solid and shape.geometry is None and shape.normal_axis == 2:  # a rectangle: +z
        rotation = rotation_keeping_x(scope.rotation[:, 0], scope.rotation[:, 2])
    elif shape.normal_axis == 1 or cityengine_scope:
        normal = scope.rotation @ face.lone_face_normal(0)
        rotation = rotation_keeping_x(scope.rotation[:, 0], normal)
    else:
        rotation = scope.rotation
    new_scope, local = fitted_scope(world, rotation)
    mesh = Mesh.of_valid_faces(local, prism.faces, holes=prism.holes)
    if not mesh.holes and _box_fills(mesh, new_scope.size):
        return Shape(new_scope, MASS)
    if height < 0 and not solid and not world_up:
        from shapegen.engine.shapes.boxes import mark_extruded_backwards

        mark_extruded_backwards(mesh)  # comp(f)'s top is the face moved back (boxes.py)
    return Shape.with_geometry(new_scope, mesh, MASS)


def split_piece(
    shape: Shape, axis: int, start: float, size: float, adjust: bool = True
) -> Shape | None:
    """The piece ``[start, start + size]`` (m) along scope ``axis`` of ``shape``: the scope slice
    for a shape filling its scope, else its geometry cut by the two planes with the scope fitted
    to what is left (op_split's default ``adjust``) or, with ``adjust`` False (``noAdjust``),
    the scope slice itself; None when nothing is left. An edge (comp(e), comp(fe)) is cut into
    the part of its segments between the planes."""
    if shape.geometry is None:
        return Shape(split_scope(shape.scope, axis, start, size), shape.kind, shape.normal_axis)
    from shapegen.geometry.cut import clip_slab

    geometry = shape.geometry
    if geometry.n_faces and all(len(face) == 2 for face in geometry.faces):
        piece = _clip_segments(geometry, axis, start, start + size)
    else:
        piece = clip_slab(geometry, axis, start, start + size)
    if piece is None:
        return None
    if shape.kind == FACE:
        piece = _begun_as(piece, shape.geometry)
    scope = shape.scope
    if adjust:
        low, high = piece.bounds()
        new_scope = Scope(scope.origin + scope.rotation @ low, scope.rotation, high - low)
    else:
        new_scope = split_scope(scope, axis, start, size)
        low = np.zeros(3)
        low[axis] = start
    local = piece.vertices - low
    if (
        shape.kind == MASS
        and adjust
        and not piece.holes
        and _is_scope_box(local, new_scope.size, piece.n_faces)
    ):
        corners = _box_corners(shape)
        if corners is None:
            return Shape(new_scope, MASS)  # a box filling its scope: back on the fast path
        # a piece of a box whose faces are in another order than the fast path's keeps them,
        # each begun at the same corner: PyPRT's comp(f) of a split piece lists its sides in
        # its parent's order (envelope2002's floors on the L lot, their vertical greenery)
        mesh = Mesh(corners * new_scope.size, shape.geometry.faces)
        return Shape.with_geometry(new_scope, mesh, MASS)
    return Shape.with_geometry(
        new_scope,
        Mesh.of_valid_faces(local, piece.faces, holes=piece.holes),
        shape.kind,
        shape.normal_axis,
    )


def _clip_segments(mesh: Mesh, axis: int, low: float, high: float) -> Mesh | None:
    """The parts of the segments of ``mesh`` (two-vertex faces: an edge's geometry) with
    ``low <= coordinate[axis] <= high`` (m); None when none has a length left. A segment lying
    across the slab's side keeps its part inside; one lying in a plane of the cut is kept."""
    vertices: list[np.ndarray] = []
    faces: list[tuple[int, int]] = []
    for a, b in mesh.faces:
        p, q = mesh.vertices[a], mesh.vertices[b]
        u, v = float(p[axis]), float(q[axis])
        if u == v:
            if not low - COINCIDENT_M <= u <= high + COINCIDENT_M:
                continue
            t0, t1 = 0.0, 1.0
        else:
            t0, t1 = sorted(((low - u) / (v - u), (high - u) / (v - u)))
            t0, t1 = max(t0, 0.0), min(t1, 1.0)
        if t1 - t0 <= 0.0:
            continue
        start, end = p + (q - p) * t0, p + (q - p) * t1
        if float(np.linalg.norm(end - start)) <= COINCIDENT_M:
            continue
        faces.append((len(vertices), len(vertices) + 1))
        vertices += [start, end]
    if not faces:
        return None
    return Mesh(np.array(vertices), faces)


def _begun_as(piece: Mesh, face: Mesh) -> Mesh:
    """The polygons of a split ``piece`` of the one-polygon ``face``, each begun at its corner
    nearest the face's first corner: so a piece's first edge runs as the face's does, as the
    pieces of a shape filling its scope (a rectangle's) begin at their lower corner on its
    first edge. PyPRT's pieces of a facade cut by split(y) begin so (envelope2002's vertical
    greenery, whose images take their scope from that edge); the clip itself would begin a
    middle piece at the cut on the face's last edge."""
    if face.n_faces != 1 or not face.faces[0]:
        return piece
    fx, fy, fz = face.vertices[face.faces[0][0]].tolist()
    rows = piece.vertices.tolist()  # in Python floats: a few short polygons
    faces = []
    for polygon in piece.faces:
        if len(polygon) < 3:  # a segment (an edge's geometry) keeps its direction
            faces.append(tuple(polygon))
            continue
        distance = []
        for i in polygon:
            x, y, z = rows[i]
            x, y, z = x - fx, y - fy, z - fz
            distance.append(math.sqrt(x * x + y * y + z * z))
        begin = distance.index(min(distance))  # the first of equal ones, as argmin's
        faces.append(tuple(polygon[begin:]) + tuple(polygon[:begin]))
    return Mesh.of_valid_faces(piece.vertices, tuple(faces), holes=piece.holes)


def split_pieces(
    shape: Shape, axis: int, spans: list[tuple[float, float]], bound: float, adjust: bool = True
) -> tuple[list[Shape | None], bool]:
    """:func:`split_piece` for each ``(start, size)`` of ``spans`` (m). The pieces of a shape
    filling its scope are sliced together, their scopes in Python floats; the flag
    says that every piece's scope is then known to be finite and within ``bound`` (m)."""
    if shape.geometry is not None or not spans:
        return [split_piece(shape, axis, start, size, adjust) for start, size in spans], False
    scope = shape.scope
    r, (ox, oy, oz), size = scope.r, scope.o, scope.d
    ax, ay, az = r[axis], r[3 + axis], r[6 + axis]
    kind, normal_axis = shape.kind, shape.normal_axis
    within = all(abs(v) <= bound for v in size)  # a NaN fails every comparison
    pieces = []
    for start, extent in spans:
        origin = (ox + ax * start, oy + ay * start, oz + az * start)
        sizes = list(size)
        sizes[axis] = extent
        within = (
            within
            and abs(origin[0]) <= bound
            and abs(origin[1]) <= bound
            and abs(origin[2]) <= bound
            and abs(extent) <= bound
        )
        pieces.append(Shape(Scope.of_floats(origin, r, tuple(sizes)), kind, normal_axis))
    return pieces, within


def _is_scope_box(local: np.ndarray, size: np.ndarray, n_faces: int) -> bool:
    """Whether the points are the 8 corners of the box ``[0, size]`` (a six-faced closed mesh
    with these corners is that box)."""
    if len(local) != 8 or n_faces != 6 or size.min() <= 0:
        return False
    slack = COINCIDENT_REL * float(size.max())
    at_low = np.abs(local) <= slack
    at_high = np.abs(local - size) <= slack
    if not np.all(at_low | at_high):
        return False
    corners = {tuple(row) for row in at_high.tolist()}
    return len(corners) == 8


def lot_shape(lot) -> tuple[Shape, dict]:
    """The start shape of a derivation and what the model's metadata records of its lot.

    ``lot`` is a :class:`~shapegen.model.lot.Lot` (or what :meth:`Lot.of
    <shapegen.model.lot.Lot.of>` takes): a rectangle fills its scope (the fast path), a polygon
    is a face whose scope has x along its first edge; a
    :class:`~shapegen.model.lot.MeshLot` is its faces (see :func:`mesh_lot_shape`). Raises
    :class:`~shapegen.errors.LotError` for what cannot be a lot."""
    if isinstance(lot, MeshLot):
        return mesh_lot_shape(lot)
    lot = Lot.of(lot)
    if lot.size is not None:
        width, depth = lot.size
        return Shape(lot_scope(width, depth), FACE, 1), {"lot": [width, depth]}
    from shapegen.geometry.scope_frames import lot_polygon

    scope, mesh = lot_polygon(lot)
    shape = Shape.with_geometry(scope, mesh, FACE, 1)
    if _rectangle_fills(mesh, scope.size):
        shape = Shape(scope, FACE, 1)
    world = scope.to_world(mesh.vertices)
    outer = world[list(mesh.faces[0])]
    metadata = {
        "lot": [float(scope.size[0]), float(scope.size[2])],
        "lot_polygon": [[float(p[0]), float(p[2])] for p in outer],
    }
    if mesh.holes:
        metadata["lot_holes"] = [
            [[float(p[0]), float(p[2])] for p in world[list(ring)]] for ring in mesh.holes[0]
        ]
    return shape, metadata


def mesh_lot_shape(lot: MeshLot) -> tuple[Shape, dict]:
    """The start shape of a :class:`~shapegen.model.lot.MeshLot`: its faces, in a scope with
    x along the first face's first edge and y along that face's normal (a level face's scope is
    a polygon lot's), the bounding box of every vertex in that frame. It is a face when the
    faces lie in one plane of the scope, else a mass; the model's metadata records the scope's
    size as ``lot`` and the mesh's counts as ``initial_mesh``."""
    from shapegen.geometry.scope_frames import face_rotation, fitted_scope

    first = lot.vertices[list(lot.faces[0])]
    frame = face_rotation(first)
    x, normal = frame[:, 0], frame[:, 2]
    rotation = np.column_stack([x, normal, np.cross(x, normal)])
    scope, local = fitted_scope(lot.vertices, rotation)
    mesh = Mesh(local, [list(face) for face in lot.faces])
    lo, hi = mesh.bounds()
    flat = [
        k
        for k in range(3)
        if hi[k] - lo[k] <= COINCIDENT_REL * max(float((hi - lo).max()), COINCIDENT_M)
    ]
    shape = (
        Shape.with_geometry(scope, mesh, FACE, flat[0])
        if flat
        else Shape.with_geometry(scope, mesh, MASS)
    )
    counts = {"vertices": int(mesh.n_vertices), "faces": int(mesh.n_faces)}
    return shape, {"lot": [float(scope.size[0]), float(scope.size[2])], "initial_mesh": counts}


def _rectangle_fills(mesh: Mesh, size: np.ndarray) -> bool:
    rectangle = Mesh.rectangle(size, 1)
    slack = COINCIDENT_REL * max(float(size.max()), COINCIDENT_M)
    return mesh.n_vertices == 4 and np.allclose(mesh.vertices, rectangle.vertices, atol=slack)


def shape_geometry_value(state, name: str, *args):
    """``geometry.<name>(*args)`` of the shape of ``state`` (a
    :class:`~shapegen.engine.derivation.state.ShapeState`); the names are those of
    :func:`shapegen.geometry.queries.geometry_value` (area, volume, height, nVertices, nFaces,
    nEdges, nHoles, isClosedSurface, isConcave, isPlanar, isRectangular, isOriented, angle,
    boundaryLength, du, dv). Raises ``ValueError`` with a message for the user."""
    from shapegen.geometry.queries import geometry_value

    shape = state.shape
    return geometry_value(
        shape.mesh(),
        shape.scope.rotation,
        name,
        *args,
        size=shape.scope.size,
        object_rotation=getattr(state.run, "object_rotation", None),
    )
