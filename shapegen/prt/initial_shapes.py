"""PyPRT's ``InitialShape``: the geometry a rule starts on, from coordinates or from a file.

PyPRT's constructors, with its argument order and types:

- ``InitialShape(vertex_coordinates)``: one face, ``[x0, y0, z0, x1, y1, z1, ...]`` in metres,
  y up;
- ``InitialShape(vertex_coordinates, indices, face_counts)``: faces by vertex indices;
- ``InitialShape(vertex_coordinates, indices, face_counts, holes)``: ``holes`` lists
  ``[face, hole face, ...]`` groups, each naming faces of ``face_counts`` by their index: the
  hole faces are not faces of the shape but holes of the first (a courtyard);
- ``InitialShape(initial_shape_path, max_dir_recursion_depth=0)``: a geometry file.

A shape of one level face (and its holes), given by coordinates or read from a file, becomes a
polygon lot at the face's height, with those holes (:func:`footprint`). A shape of several
faces, or of one that is not level, is one start shape made of all its faces, as PyPRT makes it
(:func:`start_of`: a :class:`~shapegen.model.lot.MeshLot`). Files are read as CityEngine's
runtime reads them: OBJ by shapegen's reader, cleaned as an asset is
(:mod:`shapegen.geometry.asset_cleanup`); glTF and GLB by trimesh, as triangles; FBX by ufbx
(:mod:`shapegen.readers.fbx`), its faces whole. ``max_dir_recursion_depth`` is how deep PyPRT
looks below the file's folder for the files it names (materials, textures): an OBJ file's
texture coordinates and materials are read with it (:mod:`shapegen.prt.initial_textures`).
What shapegen cannot start on (holes in a shape of several faces, other formats) is refused
with one line when the model is generated, as PyPRT reports an initial shape it cannot use.

>>> shape = InitialShape([0, 0, 0, 0, 0, 10, 10, 0, 10, 10, 0, 0])
>>> shape.get_vertex_count(), shape.get_index_count(), shape.get_face_counts_count()
(12, 4, 1)
>>> footprint(shape).points
((0.0, 0.0), (0.0, 10.0), (10.0, 10.0), (10.0, 0.0))
"""

from __future__ import annotations

__all__ = ["Footprint", "InitialShape", "footprint", "start_of"]

import contextlib
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError, LotError
from shapegen.geometry.asset_cleanup import cleaned_polygons
from shapegen.model.lot import MeshLot
from shapegen.readers.files import read_input_bytes
from shapegen.readers.obj import obj_polygons
from shapegen.tolerances import LEVEL_M

READABLE_SUFFIXES = (".obj", ".gltf", ".glb", ".fbx")
"""Geometry files an initial shape is read from (OBJ by shapegen, glTF by trimesh, FBX by
ufbx)."""


class InitialShape:
    """The geometry on which a rule is applied (PyPRT's ``pyprt.InitialShape``)."""

    def __init__(self, *args, **kwargs):
        names = ("vertex_coordinates", "indices", "face_counts", "holes")
        if args and isinstance(args[0], str | Path) or "initial_shape_path" in kwargs:
            path = args[0] if args else kwargs.pop("initial_shape_path")
            depth = args[1] if len(args) > 1 else kwargs.pop("max_dir_recursion_depth", 0)
            if len(args) > 2 or kwargs:
                raise TypeError("InitialShape(initial_shape_path, max_dir_recursion_depth=0)")
            self._path = str(path)
            self._depth = int(depth)
            self._coordinates: list[float] = []
            self._indices: list[int] = []
            self._face_counts: list[int] = []
            self._holes: list[list[int]] = []
            return
        values = dict(zip(names, args, strict=False))
        for name in names:
            if name in kwargs:
                values[name] = kwargs.pop(name)
        if kwargs or len(args) > len(names) or "vertex_coordinates" not in values:
            raise TypeError(
                "InitialShape(vertex_coordinates, indices=None, face_counts=None, holes=None)"
                " or InitialShape(initial_shape_path, max_dir_recursion_depth=0)"
            )
        self._path = ""
        self._depth = 0
        self._coordinates = _listed(values["vertex_coordinates"], "vertex_coordinates", float)
        count = len(self._coordinates) // 3
        indices = values.get("indices")
        face_counts = values.get("face_counts")
        self._indices = list(range(count)) if indices is None else _listed(indices, "indices")
        self._face_counts = [count] if face_counts is None else _listed(face_counts, "face_counts")
        self._holes = [_listed(hole, "holes") for hole in values.get("holes") or []]

    def get_vertex_count(self) -> int:
        """The number of vertex coordinates (three per vertex); 0 for a shape read from a file."""
        return len(self._coordinates)

    def get_index_count(self) -> int:
        """The length of the vertex index list; 0 for a shape read from a file."""
        return len(self._indices)

    def get_face_counts_count(self) -> int:
        """The number of faces; 0 for a shape read from a file."""
        return len(self._face_counts)

    def get_path(self) -> str:
        """The file the shape is read from, or ``""``."""
        return self._path

    def __repr__(self) -> str:
        if self._path:
            return f"InitialShape({self._path!r})"
        return (
            f"InitialShape({len(self._face_counts)} faces, {len(self._coordinates) // 3} vertices)"
        )


def _listed(values: object, name: str, kind: type = int) -> list:
    """``values`` as a list of floats (or whole numbers), or one line naming ``name``: a
    string or a 1.5 given as an index is not read as something else."""
    try:
        items = list(values)  # type: ignore[call-overload]
        if isinstance(values, str | bytes) or not all(
            isinstance(v, int | float | np.integer | np.floating) and not isinstance(v, bool)
            for v in items
        ):
            raise TypeError
        if kind is float:
            return [float(v) for v in items]
        if not all(float(v).is_integer() for v in items):
            raise TypeError
        return [int(v) for v in items]
    except (TypeError, ValueError, OverflowError):
        wanted = "numbers" if kind is float else "whole numbers"
        raise InputFormatError(
            f"InitialShape: {name} must be a list of {wanted}, got {_shown(values)}"
        ) from None


def _shown(values: object) -> str:
    text = repr(values)
    return text if len(text) <= 60 else text[:57] + "..."


@dataclass(frozen=True)
class Footprint:
    """A starting face as shapegen derives on it: ``(x, z)`` corners (metres) counter-clockwise
    seen from above, the height y (m), and whether the face as given faces down.

    A face given clockwise seen from above faces down, and CityEngine derives on it with the
    scope's y along that normal. shapegen derives on the face turned half a turn about its
    first edge (the same corners, counter-clockwise, facing up) and turns the model back
    (:meth:`place`): the scope is the same, so is the model.
    """

    points: tuple[tuple[float, float], ...]
    height: float
    faces_down: bool = False
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()
    """The face's holes, ``(x, z)`` rings (m) wound against :attr:`points`."""

    def lot(self):
        """The :class:`~shapegen.model.lot.Lot` shapegen derives on."""
        from shapegen.model.lot import Lot

        return Lot.polygon(self.points, self.holes)

    def place(self, points: np.ndarray) -> np.ndarray:
        """``(n, 3)`` points of the model derived on :attr:`points` where CityEngine has them."""
        placed = np.array(points, dtype=float)
        if self.faces_down:
            (x0, z0), (x1, z1) = self.points[0], self.points[1]
            axis = np.array([x1 - x0, 0.0, z1 - z0])
            axis /= np.linalg.norm(axis)
            relative = placed - np.array([x0, 0.0, z0])
            placed = 2.0 * np.outer(relative @ axis, axis) - relative + np.array([x0, 0.0, z0])
        placed[:, 1] += self.height
        return placed


def start_of(shape: InitialShape) -> Footprint | MeshLot:
    """Where a rule starts on ``shape``: its one level face as a :class:`Footprint`, else all
    its faces as a :class:`~shapegen.model.lot.MeshLot` (world coordinates, m, y up); an
    :class:`InputFormatError` saying why neither."""
    path = Path(shape.get_path()) if shape.get_path() else None
    if path is not None:
        vertices, faces = _read_mesh(path)
        coordinates = vertices.ravel().tolist()
        indices = [i for face in faces for i in face]
        face_counts = [len(face) for face in faces]
    else:
        coordinates, indices, face_counts = shape._coordinates, shape._indices, shape._face_counts
    where = shape.get_path() or "initial shape"
    _check(where, coordinates, indices, face_counts)
    if path is None and shape._holes:  # a face with its holes: a lot with holes
        hole_faces = _hole_faces(shape._holes, len(face_counts), where)
        inside = {k for inner in hole_faces.values() for k in inner}
        if hole_faces and len(face_counts) - len(inside) != 1:
            raise InputFormatError(
                f"{where}: {len(face_counts) - len(inside)} faces with holes; shapegen starts a"
                " rule on one face with holes"
            )
        if hole_faces:
            return footprint(shape)
    heights = [coordinates[3 * i + 1] for i in indices]
    if len(face_counts) == 1 and max(heights) - min(heights) <= LEVEL_M:
        return footprint(shape)
    level = max(coordinates[1::3]) - min(coordinates[1::3]) <= LEVEL_M
    if level and path is not None and path.suffix.lower() in (".gltf", ".glb"):
        with contextlib.suppress(InputFormatError):  # triangles of one level polygon: its lot
            return footprint(shape)
    vertices = np.array(coordinates, dtype=float).reshape(-1, 3)
    starts = np.cumsum([0, *face_counts])
    faces = [indices[a:b] for a, b in zip(starts[:-1], starts[1:], strict=True)]
    try:
        return MeshLot(vertices, tuple(tuple(face) for face in faces))
    except LotError as exc:
        raise InputFormatError(f"{where}: {exc}") from None


def _check(where: str, coordinates, indices, face_counts) -> None:
    if len(coordinates) % 3:
        raise InputFormatError(
            f"{where}: {len(coordinates)} vertex coordinates, not x, y, z triples"
        )
    if not all(math.isfinite(v) for v in coordinates):
        raise InputFormatError(f"{where}: a vertex coordinate is not a finite number")
    count = len(coordinates) // 3
    if sum(face_counts) != len(indices) or any(n < 3 for n in face_counts):
        raise InputFormatError(
            f"{where}: face counts {face_counts} do not add up to the {len(indices)} indices"
        )
    if any(not 0 <= i < count for i in indices):
        raise InputFormatError(f"{where}: a vertex index is outside the {count} vertices")


def footprint(shape: InitialShape) -> Footprint:
    """The one horizontal face of ``shape``, or an :class:`InputFormatError` saying why not."""
    if shape.get_path():
        coordinates, indices, face_counts, holes = _read_file(Path(shape.get_path()))
    else:
        coordinates, indices, face_counts = shape._coordinates, shape._indices, shape._face_counts
        holes = shape._holes
    where = shape.get_path() or "initial shape"
    _check(where, coordinates, indices, face_counts)
    rings = _rings(indices, face_counts)
    hole_faces = _hole_faces(holes, len(face_counts), where)
    inside = {k for inner in hole_faces.values() for k in inner}
    faces = [k for k in range(len(face_counts)) if k not in inside]
    if len(faces) != 1:
        raise InputFormatError(f"{where}: {len(faces)} faces; shapegen starts a rule on one face")
    hole_rings = [rings[k] for k in hole_faces.get(faces[0], ())]
    corners = [coordinates[3 * i : 3 * i + 3] for i in rings[faces[0]]]
    inner = [[coordinates[3 * i : 3 * i + 3] for i in ring] for ring in hole_rings]
    heights = [y for _, y, _ in corners] + [y for ring in inner for _, y, _ in ring]
    if max(heights) - min(heights) > LEVEL_M:
        raise InputFormatError(
            f"{where}: the face is not horizontal (its corners lie between y = {min(heights):g}"
            f" and {max(heights):g} m); shapegen starts a rule on a level face"
        )
    ring = [(x, z) for x, _, z in corners]
    holes_xz = [[(x, z) for x, _, z in hole] for hole in inner]
    faces_down = _signed_area(ring) > 0.0
    if faces_down:  # the half turn about the first edge keeps its corners, reverses the ring
        holes_xz = [_half_turn(hole, ring[:2]) for hole in holes_xz]
        ring = _half_turn(ring)
    return Footprint(tuple(ring), heights[0], faces_down, tuple(tuple(hole) for hole in holes_xz))


def _rings(indices: list[int], face_counts: list[int]) -> list[list[int]]:
    """The vertex indices of each face of ``face_counts``."""
    out, first = [], 0
    for count in face_counts:
        out.append(indices[first : first + count])
        first += count
    return out


def _hole_faces(holes: list[list[int]], n_faces: int, where: str) -> dict[int, list[int]]:
    """PyPRT's ``holes`` (``[face, hole face, ...]`` groups of face indices) as ``face -> its
    hole faces``, or one line saying what is wrong (CityEngine's runtime reports an illegal
    hole index): an index outside the faces, a face that is its own hole or a hole twice."""
    out: dict[int, list[int]] = {}
    seen: set[int] = set()
    for group in holes:
        if len(group) < 2:
            continue  # a face with no hole
        face, *inner = group
        if any(not 0 <= k < n_faces for k in group):
            raise InputFormatError(
                f"{where}: holes {group}: a face index outside the {n_faces} faces"
            )
        if face in inner or len(set(inner)) != len(inner) or seen & {face, *inner}:
            raise InputFormatError(
                f"{where}: holes {group}: illegal hole index (a face used twice)"
            )
        seen.update(group)
        out[face] = inner
    return out


def _signed_area(ring: list[tuple[float, float]]) -> float:
    """Twice the signed area in (x, z): negative for a ring counter-clockwise seen from above
    (+y), as z points towards the viewer when x points right."""
    return sum(
        x0 * z1 - x1 * z0 for (x0, z0), (x1, z1) in zip(ring, ring[1:] + ring[:1], strict=True)
    )


def _half_turn(ring: list[tuple[float, float]], edge=None) -> list[tuple[float, float]]:
    """The ring turned half a turn about its first edge (or ``edge``, two corners): each corner
    mirrored across the edge's line (the turn's effect in the ground plane)."""
    (x0, z0), (x1, z1) = edge if edge is not None else ring[:2]
    ex, ez = x1 - x0, z1 - z0
    norm = math.hypot(ex, ez)
    ex, ez = ex / norm, ez / norm
    out = []
    for x, z in ring:
        along = (x - x0) * ex + (z - z0) * ez
        out.append((2 * (x0 + along * ex) - x, 2 * (z0 + along * ez) - z))
    return out


def _readable_suffix(path: Path) -> str:
    """The suffix of a geometry file shapegen reads as initial shapes (lower case), or the
    error naming what it reads, or that the file is not there."""
    suffix = path.suffix.lower()
    if suffix not in READABLE_SUFFIXES:
        raise InputFormatError(
            f"{path}: initial shapes are read from {', '.join(READABLE_SUFFIXES)} files;"
            f" {suffix or 'a file without a suffix'} is not supported by shapegen"
        )
    if not path.is_file():
        raise InputFormatError(f"{path}: no such file")
    return suffix


def _read_file(path: Path) -> tuple[list[float], list[int], list[int], list[list[int]]]:
    """Coordinates, indices, face counts and holes (PyPRT's lists) of a geometry file."""
    suffix = _readable_suffix(path)
    if suffix == ".obj":  # OBJ has no holes: each face is a polygon
        return (*_read_obj(path), [])
    if suffix == ".fbx":
        vertices, faces = _read_mesh(path)
        flat = vertices.ravel().tolist()
        return flat, [i for f in faces for i in f], [len(f) for f in faces], []
    return _read_gltf(path)


def _read_mesh(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    """All the faces of a geometry file, as CityEngine's runtime reads them as an initial
    shape: OBJ and FBX faces whole and cleaned (as assets are), glTF as its triangles."""
    suffix = _readable_suffix(path)
    if suffix == ".obj":
        text = read_input_bytes(path, "initial shape file").decode("utf-8", errors="replace")
        vertices, faces = obj_polygons(text, str(path))
    elif suffix == ".fbx":
        from shapegen.readers.fbx import fbx_polygons

        read_input_bytes(path, "initial shape file")  # the size limit, as for the others
        vertices, faces = fbx_polygons(path)
    else:
        vertices, faces = _gltf_triangles(path)
    vertices, faces = cleaned_polygons(vertices, faces)
    if not faces:
        raise InputFormatError(f"{path}: the file holds no face with an area")
    return vertices, faces


def _gltf_triangles(path: Path) -> tuple[np.ndarray, list[list[int]]]:
    mesh = _gltf_mesh(path)
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces).tolist()


def _gltf_mesh(path: Path):
    """The triangles of a glTF file as trimesh reads them (its buffers found beside it)."""
    import trimesh

    data = read_input_bytes(path, "initial shape file")
    try:
        mesh = trimesh.load(
            io.BytesIO(data),
            file_type=path.suffix.lower().lstrip("."),
            resolver=trimesh.resolvers.FilePathResolver(str(path.resolve())),
            force="mesh",
            process=False,
        )
    except Exception as exc:  # trimesh raises many kinds for a broken file
        raise InputFormatError(f"{path}: not a readable glTF file ({exc})") from None
    return mesh


def _read_obj(path: Path) -> tuple[list[float], list[int], list[int]]:
    """Vertices and polygon faces of an OBJ file (:func:`~shapegen.readers.obj.obj_polygons`:
    faces kept whole, a lot is one polygon)."""
    text = read_input_bytes(path, "initial shape file").decode("utf-8", errors="replace")
    vertices, faces = obj_polygons(text, str(path))
    return vertices.ravel().tolist(), [i for face in faces for i in face], [len(f) for f in faces]


def _read_gltf(path: Path) -> tuple[list[float], list[int], list[int], list[list[int]]]:
    """The outline of a glTF file's faces (trimesh reads it as triangles; coplanar triangles
    are merged back into their polygon), its inner rings the polygon's holes."""
    import shapely

    mesh = _gltf_mesh(path)
    vertices = mesh.vertices
    triangles = [shapely.Polygon(vertices[face][:, [0, 2]]) for face in mesh.faces]
    outline = shapely.unary_union(triangles)
    if not isinstance(outline, shapely.Polygon):
        raise InputFormatError(f"{path}: its faces do not form one polygon")
    height = float(vertices[:, 1].mean())
    rings = []
    for k, boundary in enumerate([outline.exterior, *outline.interiors]):
        ring = list(boundary.coords)[:-1]
        # (x, z) counter-clockwise is clockwise seen from above (+y); holes the other way
        if boundary.is_ccw == (k == 0):
            ring.reverse()
        rings.append(ring)
    coordinates = [value for ring in rings for x, z in ring for value in (x, height, z)]
    counts = [len(ring) for ring in rings]
    holes = [list(range(len(rings)))] if len(rings) > 1 else []
    return coordinates, list(range(sum(counts))), counts, holes
