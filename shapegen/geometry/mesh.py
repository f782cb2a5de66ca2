"""Polygon meshes: the geometry of a shape, in its scope's coordinates (metres).

A :class:`Mesh` is immutable: ``vertices`` ``(V, 3)`` and ``faces``, a tuple of vertex-index
tuples, each polygon counter-clockwise seen from its front (the outside of a closed mesh).
Faces may be non-convex polygons, and may have holes, as CityEngine's faces do: ``holes`` is
``()`` for a mesh without any, else one tuple per face of its hole rings, each a tuple of
vertex indices wound the other way round (clockwise seen from the face's front), as PyPRT's
``InitialShape(..., holes)`` gives them. A hole is not a face: ``n_faces`` counts the faces,
``n_holes`` the holes (CityEngine's ``geometry.nFaces`` and ``geometry.nHoles``), and a face's
area is its outer ring's less its holes'.

>>> import numpy as np
>>> box = Mesh.box((2.0, 3.0, 4.0))
>>> box.volume(), box.area(), box.is_closed, box.is_convex(), box.n_edges
(24.0, 52.0, True, True, 12)
>>> Mesh.polygon([(0, 0, 0), (2, 0, 0), (2, 1, 0), (0, 1, 0)]).area()
2.0
"""

from __future__ import annotations

__all__ = [
    "Mesh",
    "BOX_FACES",
    "area_vectors",
    "corner_layout",
    "polygon_normal",
    "polygon_area",
    "unit_face_normals",
]

import math
from collections.abc import Sequence
from functools import cached_property

import numpy as np

from shapegen.geometry.face_heights import height_bands
from shapegen.geometry.hole_rings import (
    checked_holes,
    cleaned_rings,
    hole_vectors,
    outer_rings_only,
    reversed_holes,
    turned,
)
from shapegen.model.polygons import CheckedFaces, checked_faces, cross, face_layout, face_normals
from shapegen.tolerances import COINCIDENT_REL, COSINE_SLACK, SIZE_FLOOR_M, ZERO_LENGTH

# The unit box's corners (scope coordinates) and faces in CityEngine's comp(f) order for an
# extruded rectangle lot: 0 bottom, 1 top, then the sides from the lot's first edge (which runs
# along +x at z = depth): front (+z), right (+x), back (-z), left (-x).
_UNIT_BOX = np.array(
    [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]],
    dtype=float,
)
BOX_FACES = CheckedFaces(
    (
        (2, 3, 0, 1),  # bottom (-y): PyPRT starts it on the lot's second vertex
        (7, 6, 5, 4),  # top (+y)
        (3, 2, 6, 7),  # front (+z)
        (2, 1, 5, 6),  # right (+x)
        (1, 0, 4, 5),  # back (-z)
        (0, 3, 7, 4),  # left (-x)
    )
)
"""Faces of :meth:`Mesh.box`, outward, in CityEngine's comp(f) order; each starts on its first
edge (the bottom edge of a side, left to right seen from outside)."""

_FEW_CORNERS = 8  # polygons with no more corners are summed in Python floats
_FEW_FACES = 16  # meshes with no more faces are checked face by face


def polygon_normal(points: np.ndarray) -> np.ndarray:
    """Newell's (area-weighted) normal of a polygon, not normalised: its length is twice the
    area (m^2)."""
    p = np.asarray(points, float)
    if len(p) <= _FEW_CORNERS:
        return _small_polygon_normal(p.tolist())
    p = p - p.mean(axis=0)
    q = np.empty_like(p)  # the next corner of each (np.cross and np.roll cost more than this)
    q[:-1] = p[1:]
    q[-1:] = p[:1]
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    u, v, w = q[:, 0], q[:, 1], q[:, 2]
    return np.array(
        [float((y * w - z * v).sum()), float((z * u - x * w).sum()), float((x * v - y * u).sum())]
    )


def _small_polygon_normal(points: list[list[float]]) -> np.ndarray:
    """:func:`polygon_normal` of a few corners, in Python floats (numpy's calls cost more than
    the arithmetic there)."""
    count = len(points)
    if count == 0:
        return np.zeros(3)
    cx = sum(p[0] for p in points) / count
    cy = sum(p[1] for p in points) / count
    cz = sum(p[2] for p in points) / count
    centred = [(x - cx, y - cy, z - cz) for x, y, z in points]
    nx = ny = nz = 0.0
    for (x, y, z), (u, v, w) in zip(centred, centred[1:] + centred[:1], strict=True):
        nx += y * w - z * v
        ny += z * u - x * w
        nz += x * v - y * u
    return np.array([nx, ny, nz])


def unit_face_normals(vertices: np.ndarray, faces) -> list[np.ndarray]:
    """Each face's unit normal (Newell's); a zero vector for a face without area."""
    normals = []
    for face in faces:
        normal = polygon_normal(vertices[list(face)])
        length = float(np.linalg.norm(normal))
        normals.append(normal / length if length > 0 else normal)
    return normals


def polygon_area(points: np.ndarray) -> float:
    """Area of a planar polygon (m^2), convex or not."""
    return 0.5 * float(np.linalg.norm(polygon_normal(points)))


def _tail_sum(rows, k: int) -> float:
    """The ``k``-th entries of ``rows`` (at least one) summed one after the other."""
    total = rows[0][k]
    for row in rows[1:]:
        total += row[k]
    return total


def corner_layout(faces: Sequence[Sequence[int]]) -> tuple[np.ndarray, np.ndarray]:
    """The faces (tuples of ints) as flat arrays: every face's corners one after the other, and
    the ``(F + 1,)`` offsets where each face starts (the last is the number of corners)."""
    return face_layout(faces if type(faces) is CheckedFaces else CheckedFaces(faces))


def area_vectors(vertices: np.ndarray, corners: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Newell's vector of each face (about its corner mean), ``(F, 3)``: normal to the face,
    its length twice the face's area (m^2); the faces given as by :func:`corner_layout`."""
    count = start[1:] - start[:-1]
    if len(count) == 0:
        return np.empty((0, 3))
    p = vertices[corners]
    centre = np.add.reduceat(p, start[:-1], axis=0) / count[:, None]
    p -= np.repeat(centre, count, axis=0)
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = start[:-1]  # a face's last corner wraps to its first
    return np.add.reduceat(cross(p, p[successor]), start[:-1], axis=0)


class Mesh:
    """An immutable polygon mesh.

    Parameters
    ----------
    vertices
        ``(V, 3)`` points, metres.
    faces
        Polygons as tuples of vertex indices, counter-clockwise seen from the front.
    holes
        ``()`` (no holes), or per face a tuple of its hole rings (vertex-index tuples wound
        against the face).
    sheets
        ``()`` (the faces are joined wherever they share an edge), or per face the name of
        the sheet it belongs to: CityEngine builds a roof's bottom, its slopes and its walls
        as sheets, surfaces that share no edge though their corners meet (an edge between
        two sheets is a border edge of each for ``comp(e)``'s roof-edge classes). Kept by the
        copies that keep the faces (moved, scaled, mirrored); a new mesh starts joined.
    """

    __slots__ = ("vertices", "faces", "holes", "sheets", "__dict__")

    def __init__(self, vertices, faces: Sequence[Sequence[int]], holes=(), sheets=()):
        v = np.array(vertices, dtype=float).reshape(-1, 3)
        v.setflags(write=False)
        self.vertices = v
        self.faces = checked_faces(faces)
        self.holes = checked_holes(holes, len(self.faces), len(v)) if holes else ()
        if sheets and len(sheets) != len(self.faces):
            raise ValueError(f"{len(sheets)} sheets given for {len(self.faces)} faces")
        self.sheets = tuple(sheets)
        if len(self.faces) <= _FEW_FACES:  # a face or a box: plain Python is quicker than arrays
            count = len(v)
            for face in self.faces:
                if len(face) < 2 or min(face) < 0 or max(face) >= count:
                    raise ValueError(f"a mesh face {face} does not index its {count} vertices")
            return
        corners, start = face_layout(self.faces)
        short = np.flatnonzero((start[1:] - start[:-1]) < 2)
        if len(short):
            bad = short[0]
        elif corners.min() < 0 or corners.max() >= len(v):
            bad = np.flatnonzero(_faces_out_of_range(corners, start, len(v)))[0]
        else:
            return
        raise ValueError(f"a mesh face {self.faces[bad]} does not index its {len(v)} vertices")

    @classmethod
    def of_valid_faces(
        cls, vertices: np.ndarray, faces: tuple, layout=None, holes=(), sheets=()
    ) -> Mesh:
        """A mesh of faces known to be valid (tuples of ints indexing ``vertices``), made by
        shapegen's own cuts: no conversion and no check. ``layout`` is the faces'
        :func:`corner_layout` when the caller has it; ``holes`` and ``sheets`` as
        :attr:`holes` and :attr:`sheets`, valid."""
        mesh = cls.__new__(cls)
        v = np.array(vertices, dtype=float).reshape(-1, 3)
        v.setflags(write=False)
        mesh.vertices = v
        mesh.faces = faces if type(faces) is CheckedFaces else CheckedFaces(faces)
        mesh.holes = holes
        mesh.sheets = sheets
        if layout is not None and "layout" not in mesh.faces.__dict__:
            mesh.faces.__dict__["layout"] = layout
        return mesh

    # ------------------------------------------------------------------ constructors
    @classmethod
    def box(cls, size: Sequence[float]) -> Mesh:
        """The box ``[0, sx] x [0, sy] x [0, sz]`` (m), faces in :data:`BOX_FACES` order."""
        return cls.of_valid_faces(_UNIT_BOX * np.asarray(size, float), BOX_FACES)

    @classmethod
    def polygon(cls, points) -> Mesh:
        """One polygon face through ``points`` ``(n, 3)`` in order."""
        points = np.asarray(points, float).reshape(-1, 3)
        if len(points) < 2:
            return cls(points, (tuple(range(len(points))),))  # refused with the usual message
        return cls.of_valid_faces(points, (tuple(range(len(points))),))

    @classmethod
    def rectangle(cls, size: Sequence[float], normal_axis: int) -> Mesh:
        """The face that fills a flat scope of ``size`` (m), flat along ``normal_axis``.

        For ``normal_axis`` 1 (a lot) it is ``(0, sz) (sx, sz) (sx, 0) (0, 0)`` in (x, z): first
        edge along +x, counter-clockwise seen from +y. For 2 (a comp face) it is ``(0, 0) (sx, 0)
        (sx, sy) (0, sy)`` in (x, y), seen from +z; for 0, ``(0, 0) (0, sy) (0, sy, sz)...``
        seen from +x.
        """
        sx, sy, sz = (float(s) for s in size)
        if normal_axis == 1:
            points = [(0, 0, sz), (sx, 0, sz), (sx, 0, 0), (0, 0, 0)]
        elif normal_axis == 2:
            points = [(0, 0, 0), (sx, 0, 0), (sx, sy, 0), (0, sy, 0)]
        else:
            points = [(0, 0, sz), (0, 0, 0), (0, sy, 0), (0, sy, sz)]
        return cls.polygon(points)

    # ------------------------------------------------------------------ counts
    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    @property
    def n_faces(self) -> int:
        return len(self.faces)

    @property
    def n_holes(self) -> int:
        """The number of holes of all faces (CityEngine's ``geometry.nHoles``)."""
        return sum(len(rings) for rings in self.holes)

    def rings(self) -> list[tuple[int, ...]]:
        """Every boundary ring: the faces, then the faces' holes in face order."""
        return [*self.faces, *(ring for rings in self.holes for ring in rings)]

    def without_holes(self) -> Mesh:
        """The mesh with every hole closed: each face its outer ring alone, the vertices only
        the holes used removed (CityEngine's ``deleteHoles``)."""
        if not self.holes:
            return self
        order, faces = outer_rings_only(self.faces)
        return Mesh.of_valid_faces(self.vertices[order], CheckedFaces(faces))

    @cached_property
    def edges(self) -> tuple[tuple[int, int], ...]:
        """The undirected edges ``(a, b)``, in the order they first appear around the faces
        (and their holes)."""
        seen: dict[tuple[int, int], None] = {}
        for face in self.rings() if self.holes else self.faces:
            for a, b in zip(face, face[1:] + face[:1], strict=True):
                if a != b:
                    seen.setdefault((a, b) if a < b else (b, a), None)
        return tuple(seen)

    @property
    def n_edges(self) -> int:
        return len(self.edges)

    # ------------------------------------------------------------------ measures
    def face_points(self, index: int) -> np.ndarray:
        """The corners of face ``index``, ``(k, 3)`` m."""
        return self.vertices[list(self.faces[index])]

    @property
    def corner_layout(self) -> tuple[np.ndarray, np.ndarray]:
        """The faces' :func:`corner_layout`: flat corners and ``(F + 1,)`` start offsets."""
        return face_layout(self.faces)

    @cached_property
    def normals_and_centres(self) -> tuple[np.ndarray, np.ndarray]:
        """The faces' unit normals ``(F, 3)`` and centres ``(F, 3)`` (m), computed once."""
        corners, start = self.corner_layout
        return face_normals(self.vertices, corners, start)

    def face_areas(self) -> np.ndarray:
        """Each face's area, ``(F,)`` m^2 (its holes' taken off)."""
        if self.holes:
            holed = hole_vectors(self.vertices, self.holes, len(self.faces))
            vectors = area_vectors(self.vertices, *self.corner_layout) + holed
            return 0.5 * np.linalg.norm(vectors, axis=1)
        if len(self.faces) <= 2:  # a face: numpy's calls would cost more than the sums
            return np.array([polygon_area(self.face_points(k)) for k in range(len(self.faces))])
        return 0.5 * np.linalg.norm(area_vectors(self.vertices, *self.corner_layout), axis=1)

    def face_normals(self) -> np.ndarray:
        """Unit normals ``(F, 3)`` (zero for a degenerate face)."""
        return self.normals_and_centres[0]

    def face_normal(self, index: int) -> np.ndarray:
        return self.normals_and_centres[0][index]

    def lone_face_normal(self, index: int) -> np.ndarray:
        """:meth:`face_normal` for a caller that asks one face of a new mesh (an alignment to
        a face, an extrusion): that face's sums alone in Python floats, not the whole mesh's
        arrays. The same products and sums as :func:`~shapegen.model.polygons.face_normals`,
        in the order its ``reduceat`` takes them for a face of up to 8 corners (the first
        term plus the sum of the others), so the same bits; a larger face takes the arrays."""
        cached = self.__dict__.get("normals_and_centres")
        face = self.faces[index]
        count = len(face)
        if cached is not None or not 1 < count <= _FEW_CORNERS:
            return self.face_normals()[index]
        rows = self.vertices[list(face)].tolist()
        first, *rest = rows
        cx = (first[0] + _tail_sum(rest, 0)) / count
        cy = (first[1] + _tail_sum(rest, 1)) / count
        cz = (first[2] + _tail_sum(rest, 2)) / count
        centred = [(p[0] - cx, p[1] - cy, p[2] - cz) for p in rows]
        crosses = []
        for k, (a0, a1, a2) in enumerate(centred):
            b0, b1, b2 = centred[k + 1 if k + 1 < count else 0]
            crosses.append((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0))
        first, *rest = crosses
        nx = first[0] + _tail_sum(rest, 0)
        ny = first[1] + _tail_sum(rest, 1)
        nz = first[2] + _tail_sum(rest, 2)
        length = math.sqrt(nx * nx + ny * ny + nz * nz)
        if not length > 0:
            return np.zeros(3)
        return np.array([nx / length, ny / length, nz / length])

    def face_area(self, index: int) -> float:
        if self.holes and self.holes[index]:
            return float(self.face_areas()[index])
        return polygon_area(self.face_points(index))

    def area(self) -> float:
        """Total area of the faces, m^2."""
        return float(self.face_areas().sum()) if self.faces else 0.0

    def volume(self) -> float:
        """Enclosed volume (m^3) by the divergence theorem; 0 for a mesh that is not closed."""
        return abs(self.signed_volume())

    def signed_volume(self) -> float:
        """The enclosed volume (m^3), negative when the faces look inwards; 0 when not closed."""
        if not self.is_closed:
            return 0.0
        centre = self.vertices.mean(axis=0)
        if self.holes:  # every ring's cone, the holes' wound the other way round
            corners, start = face_layout(CheckedFaces(self.rings()))
        else:
            corners, start = self.corner_layout
        # each face's cone from the mesh's centre: its first corner . its Newell vector
        first = self.vertices[corners[start[:-1]]] - centre
        cones = np.einsum("fk,fk->f", first, area_vectors(self.vertices - centre, corners, start))
        cones[(start[1:] - start[:-1]) < 3] = 0.0
        return float(cones.sum()) / 6.0

    def size(self) -> float:
        """The diagonal of the bounding box, m (0 for no vertices)."""
        size = self.__dict__.get("_size")
        if size is None:  # the vertices are read-only: kept (a trim asks it once per plane)
            if self.n_vertices == 0:
                size = 0.0
            else:
                low, high = self.bounds()
                size = float(np.linalg.norm(high - low))
            self.__dict__["_size"] = size
        return size

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(low, high)`` corners of the axis-aligned bounding box, m."""
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    # ------------------------------------------------------------------ predicates
    @cached_property
    def is_closed(self) -> bool:
        """Every edge is shared by exactly two faces, once in each direction (a watertight,
        consistently oriented surface)."""
        if not self.faces:
            return False
        if self.holes:  # a hole's ring borders the inner walls as a face's does the outer
            return _closed(face_layout(CheckedFaces(self.rings())), len(self.vertices))
        # the faces alone decide it: kept on them, for the meshes that share them (an asset
        # fitted into every scope it is inserted in, a mesh turned to be cut)
        kept = self.faces.__dict__.get("is_closed")
        if kept is None:
            kept = self.faces.__dict__["is_closed"] = _closed(
                self.corner_layout, len(self.vertices)
            )
        return kept

    def is_planar(self, tolerance: float = 0.0) -> bool:
        """All vertices lie in one plane within ``tolerance`` (m, plus a round-off margin)."""
        if self.n_vertices <= 3:
            return True
        slack = tolerance + COINCIDENT_REL * max(self.size(), SIZE_FLOOR_M)
        centred = self.vertices - self.vertices.mean(axis=0)
        normal = np.linalg.svd(centred, full_matrices=False)[2][-1]
        return float(np.abs(centred @ normal).max()) <= slack

    def is_convex(self, tolerance: float = 0.0) -> bool:
        """For a closed mesh: no vertex lies in front of any face's plane (by more than
        ``tolerance`` m). For an open mesh: each face is a convex polygon."""
        slack = tolerance + COINCIDENT_REL * max(self.size(), SIZE_FLOOR_M)
        if self.holes:
            return False  # a face with a hole is not convex, nor a solid with a hole through it
        if self.is_closed:
            return all(band.max(initial=0.0) <= slack for band in self._height_bands())
        return all(self._face_is_convex(k, slack) for k in range(self.n_faces))

    def heights_above_faces(self, slack: float = np.inf) -> np.ndarray:
        """``(F, V)``: how far each vertex lies in front of each face's plane (m), measured from
        the face's centre. With a finite ``slack`` (m) it stops at the first band of faces
        with a vertex more than ``slack`` in front, leaving the later rows at 0.

        Raises
        ------
        GeometryError
            More than ``max_face_vertex_pairs`` faces times vertices (a work limit).
        """
        bands = self._height_bands()
        out = np.zeros((self.n_faces, self.n_vertices))
        low = 0
        for band in bands:
            out[low : low + len(band)] = band
            low += len(band)
            if band.max(initial=0.0) > slack:
                break
        return out

    def _height_bands(self):
        """:meth:`heights_above_faces` a band of faces at a time
        (:func:`~shapegen.geometry.face_heights.height_bands`)."""
        return height_bands(*self.normals_and_centres, self.vertices)

    def _face_is_convex(self, index: int, slack: float) -> bool:
        p = self.face_points(index)
        if len(p) <= 3:
            return True
        normal = self.face_normal(index)
        turns = np.cross(
            np.roll(p, -1, axis=0) - p, np.roll(p, -2, axis=0) - np.roll(p, -1, axis=0)
        )
        return bool((turns @ normal).min() >= -slack * max(self.size(), SIZE_FLOOR_M))

    def is_rectangular(self, tolerance_degrees: float = 0.0) -> bool:
        """Every face is a quadrilateral whose corners are right angles within
        ``tolerance_degrees`` (CityEngine's ``geometry.isRectangular``)."""
        if not self.faces:
            return False
        limit = np.cos(np.radians(90.0 - tolerance_degrees)) + COSINE_SLACK
        for k in range(self.n_faces):
            p = self.face_points(k)
            if len(p) != 4:
                return False
            a = np.roll(p, -1, axis=0) - p
            b = np.roll(p, 1, axis=0) - p
            norms = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
            if np.any(norms <= 0):
                return False
            if np.any(np.abs(np.einsum("ij,ij->i", a, b)) / norms > limit):
                return False
        return True

    # ------------------------------------------------------------------ new meshes
    def transformed(self, rotation: np.ndarray | None = None, offset=None) -> Mesh:
        """``rotation @ v + offset`` for every vertex (a mirror flips the faces' order so they
        still face out)."""
        v = self.vertices
        faces = self.faces
        holes = self.holes
        layout = None
        if rotation is not None:
            rotation = np.asarray(rotation, float)
            v = v @ rotation.T
            if np.linalg.det(rotation) < 0:
                faces = tuple(_reversed(f) for f in faces)
                holes = reversed_holes(holes)
                layout = None
        if offset is not None:
            v = v + np.asarray(offset, float)
        moved = Mesh.of_valid_faces(v, faces, layout, holes, self.sheets)
        if "is_closed" in self.__dict__:
            moved.__dict__["is_closed"] = self.is_closed  # reversing every face keeps it
        return moved

    def scaled(self, factors: Sequence[float]) -> Mesh:
        """Each coordinate times ``factors`` (about the origin); a negative factor mirrors."""
        factors = np.asarray(factors, float)
        if np.prod(np.sign(factors)) < 0:
            return Mesh.of_valid_faces(
                self.vertices * factors,
                tuple(_reversed(f) for f in self.faces),
                holes=reversed_holes(self.holes),
                sheets=self.sheets,
            )
        return Mesh.of_valid_faces(
            self.vertices * factors, self.faces, holes=self.holes, sheets=self.sheets
        )

    def moved_to(self, vertices) -> Mesh:
        """The same faces and holes on other ``vertices`` ``(V, 3)`` (m), one per vertex."""
        return Mesh(vertices, self.faces, self.holes, self.sheets)

    def reversed(self) -> Mesh:
        """The same mesh with every face turned around (CityEngine's ``reverseNormals``)."""
        return Mesh.of_valid_faces(
            self.vertices,
            tuple(_reversed(f) for f in self.faces),
            holes=reversed_holes(self.holes),
            sheets=self.sheets,
        )

    def face(self, index: int) -> Mesh:
        """Face ``index`` alone, with only its own vertices (and its holes)."""
        if self.holes and self.holes[index]:
            return self.subset([index])
        return Mesh.polygon(self.face_points(index))

    def subset(self, indices: Sequence[int]) -> Mesh:
        """The faces ``indices`` (in that order), with only the vertices they use (their holes
        kept)."""
        used: dict[int, int] = {}
        faces = []
        holes = []
        for k in indices:
            faces.append(tuple(used.setdefault(i, len(used)) for i in self.faces[k]))
            if self.holes:
                holes.append(
                    tuple(tuple(used.setdefault(i, len(used)) for i in r) for r in self.holes[k])
                )
        return Mesh(self.vertices[list(used)] if used else np.empty((0, 3)), faces, holes)

    def cleaned(self, tolerance: float = 0.0) -> Mesh:
        """Vertices closer than ``tolerance`` (m, plus round-off) merged, repeated corners and
        faces with fewer than three corners dropped, unused vertices removed."""
        slack = tolerance + COINCIDENT_REL * max(self.size(), SIZE_FLOOR_M)
        keys = np.round(self.vertices / max(slack, ZERO_LENGTH)).astype(np.int64)
        if not self.faces:
            return Mesh(np.empty((0, 3)), ())
        if self.holes:
            return self._cleaned_with_holes(keys)
        corners, start = self.corner_layout
        order = np.lexsort(keys.T)
        twins = (keys[order[1:]] == keys[order[:-1]]).all(axis=1)
        if not twins.any() and self._plain(corners, start):
            return self  # nothing to merge or drop
        first: dict[tuple, int] = {}
        remap = [first.setdefault(key, k) for k, key in enumerate(map(tuple, keys.tolist()))]
        faces = []
        for face in self.faces:
            ring = []
            for i in face:
                j = remap[i]
                if not ring or ring[-1] != j:
                    ring.append(j)
            while len(ring) > 1 and ring[0] == ring[-1]:
                ring.pop()
            if len(ring) >= 3:
                faces.append(tuple(ring))
        used: dict[int, int] = {}
        faces = [tuple(used.setdefault(i, len(used)) for i in f) for f in faces]
        return Mesh(self.vertices[list(used)] if used else np.empty((0, 3)), faces)

    def _cleaned_with_holes(self, keys: np.ndarray) -> Mesh:
        """:meth:`cleaned` of a mesh with holes (:func:`~shapegen.geometry.hole_rings.
        cleaned_rings`)."""
        first: dict[tuple, int] = {}
        remap = [first.setdefault(key, k) for k, key in enumerate(map(tuple, keys.tolist()))]
        used, faces, holes = cleaned_rings(remap, self.faces, self.holes)
        return Mesh(self.vertices[used] if used else np.empty((0, 3)), faces, holes)

    def _plain(self, corners: np.ndarray, start: np.ndarray) -> bool:
        """Every face has three corners or more, none repeated next to itself, and every
        vertex is used."""
        if int((start[1:] - start[:-1]).min()) < 3:
            return False
        successor = np.arange(1, len(corners) + 1)
        successor[start[1:] - 1] = start[:-1]
        if bool((corners == corners[successor]).any()):
            return False
        used = np.zeros(len(self.vertices), dtype=bool)
        used[corners] = True
        return bool(used.all())

    def to_vertices_and_faces(self) -> tuple[np.ndarray, tuple[tuple[int, ...], ...]]:
        return self.vertices, self.faces

    def __repr__(self) -> str:
        holes = f", {self.n_holes} holes" if self.holes else ""
        return f"Mesh({self.n_vertices} vertices, {self.n_faces} faces{holes})"


def _faces_out_of_range(corners: np.ndarray, start: np.ndarray, count: int) -> np.ndarray:
    """``(F,)``: the faces with a corner outside ``0 .. count - 1``."""
    bad = ((corners < 0) | (corners >= count)).astype(np.intp)
    return np.add.reduceat(bad, start[:-1]) > 0


_reversed = turned  # a face turned around starts on its second vertex


def _closed(layout: tuple[np.ndarray, np.ndarray], n: int) -> bool:
    """:attr:`Mesh.is_closed` of the faces ``layout`` over ``n`` vertices."""
    corners, start = layout
    successor = np.arange(1, len(corners) + 1)
    successor[start[1:] - 1] = start[:-1]
    edges = corners * n + corners[successor]
    edges.sort()
    if len(edges) > 1 and bool((edges[1:] == edges[:-1]).any()):
        return False  # a directed edge used twice
    reverse = (edges % n) * n + edges // n
    found = np.searchsorted(edges, reverse)
    found[found == len(edges)] = 0
    return bool((edges[found] == reverse).all())
