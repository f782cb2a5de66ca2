"""Rigid blocks: convex polyhedra with a density, the unit of the mass model."""

from __future__ import annotations

__all__ = ["Block", "DEFAULT_DENSITY", "compute_mass_properties"]

from collections import defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from shapegen.errors import GeometryError
from shapegen.limits import current_limits, limit_hint
from shapegen.model.appearance import Appearance
from shapegen.model.polygons import CheckedFaces, checked_faces, cross, face_normals
from shapegen.tolerances import (
    COORDINATE_ROUNDOFF_REL,
    COPLANAR_REL,
    DEFAULT,
    DIVISION_FLOOR,
    Tolerances,
)

DEFAULT_DENSITY = 2400.0  # kg/m^3, stone masonry
#: The densest block taken, kg/m^3: 40 times osmium's. It keeps a model's weight and its square
#: (the tension measure, N^2) finite for every size a shape may have (max_coordinate).
MAX_DENSITY = 1e6


def density_is_valid(density: object) -> bool:
    """Whether ``density`` is a block's density: a float in [0, MAX_DENSITY] kg/m^3."""
    return isinstance(density, float | int) and 0 <= density <= MAX_DENSITY


@dataclass(eq=False)
class Block:
    """A convex polyhedral rigid block.

    Parameters
    ----------
    vertices
        ``(k, 3)`` vertex positions, metres (y up).
    faces
        Polygons as vertex-index tuples, counter-clockwise seen from outside (outward normals).
    density
        kg/m^3.
    id
        A name unique within its model.
    tags
        Labels (from ``label(...)`` in a grammar, or a file).
    structural
        False excludes the block from the statics (as the seed paper does for wooden roofs).
    fixed
        A support: it carries any load and needs no equilibrium.
    rule_path
        The chain of rules that produced the block, when it came from a grammar.
    appearance
        Its look (:class:`~shapegen.model.appearance.Appearance`), or None for the default;
        carried to the export, never to the statics.
    body
        The rigid body it is a part of: blocks with the same non-empty ``body`` are one body
        (the convex parts of one non-convex leaf); empty, it is its own body (glued to the
        blocks it overlaps, :mod:`shapegen.statics.bodies`).
    """

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    density: float = DEFAULT_DENSITY
    id: str = ""
    tags: tuple[str, ...] = ()
    structural: bool = True
    fixed: bool = False
    rule_path: tuple[str, ...] = ()
    extras: dict = field(default_factory=dict)
    appearance: Appearance | None = None
    body: str = ""

    def __post_init__(self) -> None:
        self.vertices = np.ascontiguousarray(self.vertices, dtype=float).reshape(-1, 3)
        self.faces = checked_faces(self.faces)
        self.tags = tuple(self.tags)
        self.rule_path = tuple(self.rule_path)
        self.density = float(self.density)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_hull(cls, points: Iterable[Sequence[float]] | np.ndarray, **kwargs) -> Block:
        """The convex hull of ``points`` as a block; coplanar hull triangles merge into polygons."""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        label = kwargs.get("id") or "block"
        if not np.all(np.isfinite(points)):
            raise GeometryError(f"block {label!r}: vertex coordinates must be finite numbers")
        if len(points) < 4:
            raise GeometryError(f"block {label!r}: needs at least 4 vertices, got {len(points)}")
        # qhull's round-off grows with the coordinates' magnitude: work about the centre.
        center = points.mean(axis=0)
        try:
            hull = _convex_hull(points - center)
        except _qhull_error():
            raise GeometryError(
                f"block {label!r}: vertices are flat or collinear (zero volume)"
            ) from None
        vertices, faces = _hull_polygons(points - center, hull)
        vertices = vertices + center
        return cls(vertices, faces, **kwargs)

    @classmethod
    def box(cls, lo: Sequence[float], hi: Sequence[float], **kwargs) -> Block:
        """An axis-aligned box from corner ``lo`` to corner ``hi`` (metres)."""
        x0, y0, z0 = (float(v) for v in lo)
        x1, y1, z1 = (float(v) for v in hi)
        vertices = np.array(
            [
                [x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1],
                [x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1],
            ]
        )  # fmt: skip
        faces = (
            (0, 1, 2, 3),  # bottom, normal -y
            (4, 7, 6, 5),  # top, normal +y
            (0, 4, 5, 1),  # z = z0, normal -z
            (3, 2, 6, 7),  # z = z1, normal +z
            (0, 3, 7, 4),  # x = x0, normal -x
            (1, 5, 6, 2),  # x = x1, normal +x
        )
        return cls(vertices, faces, **kwargs)

    # ------------------------------------------------------------------ geometry
    @cached_property
    def _mass_properties(self) -> tuple[float, np.ndarray]:
        # Divergence theorem: sum of signed tetrahedra (reference point, face fan triangle).
        reference = self.vertices.mean(axis=0)
        tris = self.fan_triangles
        a = tris[:, 0] - reference
        b = tris[:, 1] - reference
        c = tris[:, 2] - reference
        six_v = np.einsum("ij,ij->i", a, cross(b, c))
        volume = six_v.sum() / 6.0
        if abs(volume) == 0.0:
            return 0.0, reference.copy()
        centroid = reference + (six_v[:, None] * (a + b + c)).sum(axis=0) / (24.0 * volume)
        return float(volume), centroid

    @cached_property
    def fan_triangles(self) -> np.ndarray:
        """The block's faces fanned into triangles, ``(t, 3 corners, 3 coordinates)`` (m)."""
        return self.vertices[_fan_indices(self.faces)]

    @property
    def volume(self) -> float:
        """Volume, m^3 (exact for the polyhedron)."""
        return self._mass_properties[0]

    @property
    def centroid(self) -> np.ndarray:
        """Centre of mass for uniform density, metres."""
        return self._mass_properties[1]

    @property
    def mass(self) -> float:
        """kg."""
        return self.density * self.volume

    @cached_property
    def _face_planes(self) -> tuple[np.ndarray, np.ndarray]:
        starts, flat = self._face_index
        return face_normals(self.vertices, flat, starts)

    @property
    def face_normals(self) -> np.ndarray:
        """``(f, 3)`` outward unit normals (Newell's method, robust for slightly warped faces)."""
        return self._face_planes[0]

    @cached_property
    def _face_index(self) -> tuple[np.ndarray, np.ndarray]:
        """Face offsets into one flat array of vertex indices."""
        counts = np.fromiter((len(f) for f in self.faces), dtype=int, count=len(self.faces))
        starts = np.concatenate([[0], np.cumsum(counts)])
        flat = np.fromiter((i for f in self.faces for i in f), dtype=int, count=int(starts[-1]))
        return starts, flat

    @cached_property
    def face_offsets(self) -> np.ndarray:
        """``(f,)`` plane offsets d with n . x = d on each face, metres."""
        normals, centres = self._face_planes
        return np.einsum("ij,ij->i", normals, centres)

    @property
    def bounds(self) -> np.ndarray:
        """``(2, 3)`` axis-aligned bounding box, metres."""
        return np.array([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def face_area(self, k: int) -> float:
        """Area of face ``k``, m^2."""
        p = self.vertices[list(self.faces[k])]
        p = p - p[0]
        return 0.5 * float(np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)))

    # ------------------------------------------------------------------ checks
    def validate(self, tol: Tolerances = DEFAULT) -> None:
        """Raise :class:`GeometryError` naming the block if it is NaN, degenerate or non-convex.

        :func:`~shapegen.model.validation.validate_blocks` gives the same verdicts and messages
        for many blocks at once, much faster.
        """
        name = self.id or "block"
        if not np.all(np.isfinite(self.vertices)):
            raise GeometryError(f"block {name!r}: vertex coordinates must be finite numbers")
        if not density_is_valid(self.density):
            raise GeometryError(
                f"block {name!r}: density must be a number in [0, {MAX_DENSITY:g}] kg/m^3, got "
                f"{self.density}"
            )
        n = len(self.vertices)
        for face in self.faces:
            if len(face) < 3 or min(face) < 0 or max(face) >= n:
                raise GeometryError(
                    f"block {name!r}: face {list(face)} must list at least 3 of its {n} vertices"
                )
        if self.volume <= tol.volume:
            rules = f" (rules: {' -> '.join(self.rule_path)})" if self.rule_path else ""
            if self.volume <= 0:
                raise GeometryError(
                    f"block {name!r}{rules}: zero or negative volume ({self.volume:.3g} m^3)"
                )
            raise GeometryError(
                f"block {name!r}{rules}: volume {self.volume:.3g} m^3 is within the model's "
                f"volume tolerance of zero, {tol.volume:.3g} m^3 ({tol.volume_rel:g} times the "
                f"cube of its size, {tol.size:.4g} m): too small to judge"
            )
        limits = current_limits()
        if len(self.faces) * n > limits.max_face_vertex_pairs:
            raise GeometryError(
                f"block {name!r}: {len(self.faces)} faces and {n} vertices are too many to "
                f"check for convexity " + limit_hint("max_face_vertex_pairs", limits)
            )
        distances = self.vertices @ self.face_normals.T - self.face_offsets
        worst = float(distances.max())
        if worst > tol.convex + COORDINATE_ROUNDOFF_REL * float(np.abs(self.vertices).max()):
            raise GeometryError(
                f"block {name!r}: not convex (a vertex lies {worst:.3g} m outside a face plane)"
            )

    # ------------------------------------------------------------------ conversions
    def to_vertices_and_faces(self) -> tuple[np.ndarray, list[list[int]]]:
        return self.vertices.copy(), [list(f) for f in self.faces]

    def to_dict(self) -> dict:
        """The block as a shapegen-blocks JSON object."""
        out = {
            "id": self.id,
            "vertices": self.vertices.tolist(),
            "faces": [list(f) for f in self.faces],
            "density": self.density,
            "fixed": self.fixed,
            "structural": self.structural,
            "tags": list(self.tags),
        }
        if self.rule_path:
            out["rule_path"] = list(self.rule_path)
        if self.body:
            out["body"] = self.body
        return out

    def with_vertices(self, vertices: np.ndarray) -> Block:
        """A copy with every field but its vertices (m), which ``vertices`` replace."""
        return Block(
            vertices,
            self.faces,
            density=self.density,
            id=self.id,
            tags=self.tags,
            structural=self.structural,
            fixed=self.fixed,
            rule_path=self.rule_path,
            extras=dict(self.extras),
            appearance=self.appearance,
            body=self.body,
        )

    def transformed(self, matrix: np.ndarray, offset: np.ndarray) -> Block:
        """A copy moved by ``x -> matrix @ x + offset`` (a proper rotation keeps faces outward)."""
        out = self.with_vertices(
            self.vertices @ np.asarray(matrix, float).T + np.asarray(offset, float)
        )
        if np.linalg.det(matrix) < 0:
            out.faces = tuple(tuple(reversed(f)) for f in out.faces)
        return out


def _fan_indices(faces) -> np.ndarray:
    """``(T, 3)`` vertex numbers of the faces' fan triangles, kept on ``faces``: the blocks
    moved from one shape (a kept decomposition's pieces, a hull placed many times) share it."""
    kept = faces.__dict__ if type(faces) is CheckedFaces else {}  # a plain tuple keeps none
    fan = kept.get("fan")
    if fan is None:
        tris = [(face[0], face[i], face[i + 1]) for face in faces for i in range(1, len(face) - 1)]
        fan = kept["fan"] = np.array(tris, dtype=int).reshape(-1, 3)
        fan.setflags(write=False)
    return fan


def _convex_hull(points: np.ndarray):
    # scipy.spatial takes 0.4 s to import: loaded when a hull is first needed, not with the model
    from scipy.spatial import ConvexHull

    return ConvexHull(points)


def _qhull_error() -> type[Exception]:
    from scipy.spatial import QhullError

    return QhullError


def _hull_polygons(points: np.ndarray, hull) -> tuple[np.ndarray, tuple]:
    """The hull's faces as outward polygons over its vertices.

    qhull returns triangles; triangles of one face are recognised by the set of hull vertices
    lying on their plane (within round-off), so a face is never merged with a merely
    almost-coplanar neighbour (which would make the block slightly non-convex).
    """
    used = np.unique(hull.simplices)
    vertices = points[used]
    scale = max(float(np.ptp(vertices, axis=0).max()), DIVISION_FLOOR)
    normals, offsets = hull.equations[:, :3], hull.equations[:, 3]  # n.x + e = 0, n outward
    on_plane = np.abs(vertices @ normals.T + offsets).T <= COPLANAR_REL * scale  # (facets, v.)
    _, first, group = np.unique(on_plane, axis=0, return_index=True, return_inverse=True)
    faces = []
    for g in np.argsort(first):  # faces in qhull's order, for determinism
        ids = np.flatnonzero(on_plane[first[g]])
        normal = normals[first[g]]
        p = vertices[ids]
        center = p.mean(axis=0)
        u = p[np.argmax(np.linalg.norm(p - center, axis=1))] - center
        u /= np.linalg.norm(u)
        v = np.cross(normal, u)
        angles = np.arctan2((p - center) @ v, (p - center) @ u)
        faces.append(tuple(int(i) for i in ids[np.argsort(angles)]))
    del group
    return vertices, tuple(faces)


def _fan(faces) -> np.ndarray:
    return np.array(
        [(face[0], face[i], face[i + 1]) for face in faces for i in range(1, len(face) - 1)],
        dtype=int,
    ).reshape(-1, 3)


def compute_mass_properties(blocks: Iterable[Block]) -> None:
    """Compute the volume and centroid of many blocks at once (what :attr:`Block.volume` and
    :attr:`Block.centroid` compute one block at a time, by the same formula): blocks of one face
    layout (all the boxes of a wall) are done together, so a 10 000-block model costs a few
    array operations instead of 10 000 small ones. Blocks that have them already are skipped."""
    groups: dict[tuple, list[Block]] = defaultdict(list)
    for block in blocks:
        if "_mass_properties" not in block.__dict__:
            faces = block.faces
            key = faces if isinstance(faces, tuple) else tuple(map(tuple, faces))
            groups[(len(block.vertices), key)].append(block)
    for (_, faces), members in groups.items():
        if len(members) == 1:
            continue  # computed when read
        vertices = np.stack([b.vertices for b in members])  # (k, n, 3)
        reference = vertices.mean(axis=1)  # (k, 3)
        corners = vertices[:, _fan(faces)] - reference[:, None, None, :]  # (k, t, 3, 3)
        a, b, c = corners[:, :, 0], corners[:, :, 1], corners[:, :, 2]
        bc = np.stack(
            [
                b[..., 1] * c[..., 2] - b[..., 2] * c[..., 1],
                b[..., 2] * c[..., 0] - b[..., 0] * c[..., 2],
                b[..., 0] * c[..., 1] - b[..., 1] * c[..., 0],
            ],
            axis=-1,
        )
        six_v = np.einsum("kti,kti->kt", a, bc)
        volumes = six_v.sum(axis=1) / 6.0
        moments = (six_v[..., None] * (a + b + c)).sum(axis=1)  # (k, 3)
        for k, block in enumerate(members):
            volume = float(volumes[k])
            if volume == 0.0:
                block.__dict__["_mass_properties"] = (0.0, reference[k].copy())
            else:
                centroid = reference[k] + moments[k] / (24.0 * volume)
                block.__dict__["_mass_properties"] = (volume, centroid)
