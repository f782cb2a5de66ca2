"""The polygon mesh a roof, taper or envelope is built as (:class:`RoofMesh`, in a flat face's
frame), and what builds one: :class:`Welder` (one index per distinct point) and the pieces
every roof starts from (its bottom face, its holes as clockwise rings, its planes' slope).
"""

from __future__ import annotations

__all__ = ["RoofMesh", "Welder", "bottom_face", "clockwise_rings", "roof_slope"]

import math
from dataclasses import dataclass

import numpy as np

from shapegen.errors import GeometryError
from shapegen.geometry.polygon2d import signed_area
from shapegen.tolerances import DEFAULT, DIVISION_FLOOR


@dataclass(frozen=True)
class RoofMesh:
    """A polygon mesh in a face's frame.

    Attributes
    ----------
    vertices
        ``(m, 3)`` points ``(x, y, h)``, metres; ``h`` along the face's normal.
    faces
        Vertex-index tuples, counter-clockwise seen from outside.
    tags
        One CityEngine component tag per face (``roof.bottom``, ``roof.top``, ``roof.side``...).
    holes
        ``()``, or per face its hole rings (:attr:`~shapegen.geometry.mesh.Mesh.holes`).
    """

    vertices: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    tags: tuple[str, ...]
    holes: tuple = ()
    punch_failed: bool = False  # envelope: its holes not punched (:func:`envelope`)

    def volume(self) -> float:
        """Enclosed volume (m³) by the divergence theorem (meaningful for a closed mesh)."""
        total = 0.0
        for face in self.faces:
            p = self.vertices[list(face)]
            for k in range(1, len(p) - 1):
                total += float(np.dot(p[0], np.cross(p[k], p[k + 1]))) / 6.0
        return total


class Welder:
    """Collects points and faces, one index per distinct point."""

    _NEAR = [(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]

    def __init__(self, size: float):
        self.eps = DEFAULT.merge_rel * max(size, DIVISION_FLOOR) * 10
        self.points: list[np.ndarray] = []
        self.faces: list[tuple[int, ...]] = []
        self.tags: list[str] = []
        self.holes: list[tuple[tuple[int, ...], ...]] = []
        self.cells: dict[tuple[int, int, int], list[int]] = {}  # grid of cell size eps

    def index(self, point) -> int:
        point = np.asarray(point, dtype=float)
        cell = tuple(int(c) for c in np.floor(point / self.eps))
        for di, dj, dk in self._NEAR:  # a point within eps lies in this cell or a neighbour
            for k in self.cells.get((cell[0] + di, cell[1] + dj, cell[2] + dk), ()):
                if np.abs(self.points[k] - point).max() <= self.eps:
                    return k
        self.points.append(point)
        self.cells.setdefault(cell, []).append(len(self.points) - 1)
        return len(self.points) - 1

    def ring(self, points) -> tuple[int, ...]:
        ids: list[int] = []
        for p in points:
            k = self.index(p)
            if not ids or ids[-1] != k:
                ids.append(k)
        while len(ids) > 1 and ids[0] == ids[-1]:
            ids.pop()
        return tuple(ids)

    def face(self, points, tag: str, holes=()) -> None:
        ids = self.ring(points)
        if len(ids) >= 3:
            self.faces.append(ids)
            self.tags.append(tag)
            rings = (self.ring(hole) for hole in holes)
            self.holes.append(tuple(r for r in rings if len(r) >= 3))

    def mesh(self) -> RoofMesh:
        holes = tuple(self.holes) if any(self.holes) else ()
        return RoofMesh(
            np.array(self.points).reshape(-1, 3), tuple(self.faces), tuple(self.tags), holes
        )


def bottom_face(welder: Welder, polygon: np.ndarray, tag: str, holes=()) -> None:
    welder.face([(x, y, 0.0) for x, y in polygon[::-1]], tag,
                [[(x, y, 0.0) for x, y in ring[::-1]] for ring in holes])  # fmt: skip


def clockwise_rings(holes) -> list[np.ndarray]:
    """A face's holes as clockwise ``(k, 2)`` rings (m)."""
    out = []
    for ring in holes:
        ring = np.asarray(ring, dtype=float).reshape(-1, 2)
        out.append(ring[::-1] if signed_area(ring) > 0 else ring)
    return out


def roof_slope(angle: float | None, height: float | None, reach: float) -> float:
    """tan of the roof planes: from an angle (degrees) or from a height over ``reach`` (m)."""
    if height is not None:
        if not math.isfinite(height):
            raise GeometryError(f"a roof height must be a finite number, got {height}")
        return height / reach if reach > 0 else 0.0
    if angle is None or not math.isfinite(angle) or not -90 < angle < 90:
        raise GeometryError(f"a roof angle must be between -90 and 90 degrees, got {angle}")
    return math.tan(math.radians(angle))
