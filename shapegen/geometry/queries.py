"""What CGA's ``geometry.*`` functions and component selectors ask of a shape's geometry.

:func:`geometry_value` answers ``geometry.<name>(args...)`` for a mesh in its scope (see its
docstring for the names); :func:`face_matches` tells whether a face normal matches a ``comp``
selector (``front``, ``world.up``, ``vertical``...). Both are pure functions of the mesh (scope
coordinates), the scope's rotation (columns: its axes in world coordinates) and, for
``object.*``, the initial shape's rotation.
"""

from __future__ import annotations

__all__ = [
    "FACE_SELECTORS",
    "GEOMETRY_FUNCTIONS",
    "PARTIAL_GEOMETRY",
    "TEXTURE_BOUNDS",
    "face_matches",
    "geometry_value",
    "slope_class",
]

import math

import numpy as np

from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.geometry.scope_frames import quadrant
from shapegen.tolerances import ROUNDOFF_REL, SIZE_FLOOR_M

_SCOPE_QUADRANTS = ("front", "back", "left", "right", "top", "bottom")
_WORLD = {
    "world.up": "top",
    "world.down": "bottom",
    "world.south": "front",
    "world.north": "back",
    "world.east": "right",
    "world.west": "left",
}

FACE_SELECTORS: tuple[str, ...] = (
    *_SCOPE_QUADRANTS,
    "side",
    "vertical",
    "horizontal",
    "aslant",
    "nutant",
    "all",
    "border",
    "inside",
    *(f"object.{name}" for name in (*_SCOPE_QUADRANTS, "side")),
    *_WORLD,
    "world.side",
    *(f"street.{name}" for name in ("front", "back", "left", "right", "side")),
    *("streetSide", "streetFront", "noStreetSide"),
)
"""Every face selector :func:`face_matches` knows. ``street.*`` falls back to ``object.*``, as
CityEngine does when the lot has no street widths."""


def slope_class(normal: np.ndarray) -> str:
    """``horizontal`` (> 78.75 deg above or below the xz-plane), ``aslant`` (11.25-78.75 above),
    ``vertical`` (within 11.25) or ``nutant`` (11.25-78.75 below) of a unit normal in scope
    coordinates (op_comp's classes)."""
    angle = math.degrees(math.asin(max(-1.0, min(1.0, float(normal[1])))))
    if abs(angle) > 78.75:
        return "horizontal"
    if angle > 11.25:
        return "aslant"
    if angle >= -11.25:
        return "vertical"
    return "nutant"


def face_matches(
    selector: str,
    normal_scope: np.ndarray,
    normal_world: np.ndarray,
    normal_object: np.ndarray,
    border: bool = True,
) -> bool:
    """Whether a face with these unit normals (in the shape's scope, world and object frames)
    matches ``selector`` (one of :data:`FACE_SELECTORS`); ``border``: the face has an edge no
    other face shares."""
    if selector == "all":
        return True
    if selector in _SCOPE_QUADRANTS:
        return quadrant(normal_scope) == selector
    if selector == "side":
        return slope_class(normal_scope) != "horizontal"
    if selector in ("vertical", "horizontal", "aslant", "nutant"):
        return slope_class(normal_scope) == selector
    if selector == "border":
        return border
    if selector == "inside":
        return not border
    if selector in ("streetSide", "streetFront"):  # deprecated: the street side, the front
        selector = "street.front"
    elif selector == "noStreetSide":
        return quadrant(normal_object) not in ("front", "top", "bottom")
    if selector.startswith("street."):
        selector = "object." + selector.removeprefix("street.")
    if selector.startswith("object."):
        name = selector.removeprefix("object.")
        if name == "side":
            return quadrant(normal_object) not in ("top", "bottom")
        return quadrant(normal_object) == name
    if selector == "world.side":
        return quadrant(normal_world) not in ("top", "bottom")
    if selector in _WORLD:
        return quadrant(normal_world) == _WORLD[selector]
    raise ValueError(f"unknown face selector {selector!r}")


#: func_geometry's texture-coordinate bounds: shapegen keeps no texture coordinates, so they
#: are the scope's, as a facade's ``setupProjection(0, scope.xy, ...)`` lays them: u along the
#: scope's x, v along its y (its z for a flat shape), 0 to 1 in uvSpace.
TEXTURE_BOUNDS = ("uMin", "uMax", "vMin", "vMax")

GEOMETRY_FUNCTIONS: tuple[str, ...] = (
    "area",
    "volume",
    "height",
    "nVertices",
    "nFaces",
    "nEdges",
    "nHoles",
    "isClosedSurface",
    "isConcave",
    "isPlanar",
    "isRectangular",
    "isOriented",
    "angle",
    "boundaryLength",
    "du",
    "dv",
    *TEXTURE_BOUNDS,
)
"""The ``geometry.*`` names :func:`geometry_value` answers."""

#: Those answered with a difference from the reference (func_geometry), in a few words.
PARTIAL_GEOMETRY: dict[str, str] = {
    "du": "uvSpace is 1, the scope's extent, with a warning: no texture coordinates",
    "dv": "uvSpace is 1, the scope's extent, with a warning: no texture coordinates",
    **{
        name: "0 or 1 over the scope, with a warning: no texture coordinates"
        for name in TEXTURE_BOUNDS
    },
}


def geometry_value(
    mesh: Mesh,
    rotation: np.ndarray,
    name: str,
    *args,
    size: np.ndarray | None = None,
    object_rotation: np.ndarray | None = None,
):
    """The value of ``geometry.<name>(*args)`` for ``mesh`` (scope coordinates, m) in a scope
    with axes ``rotation``.

    Names (CityEngine's func_geometry):

    - ``area()``, ``area(selector)``: total face area, m^2 (only the faces matching a face
      selector such as ``top``, ``world.up``, ``object.side``: see :data:`FACE_SELECTORS`);
    - ``volume()``: enclosed volume, m^3 (0 for an open mesh);
    - ``height()``: extent along world y, m;
    - ``nVertices()``, ``nFaces()``, ``nEdges()``, ``nHoles()`` as floats;
    - ``isClosedSurface()``, ``isConcave()`` (a face is concave), ``isPlanar(tolerance_deg)``
      (every face planar), ``isRectangular(tolerance_deg)``, ``isOriented(selector)``;
    - ``angle(maxSlope | azimuth | zenith)``: degrees; the steepest face relative to the world
      xz-plane, the azimuth (clockwise from north = -z, seen from above) of its downhill
      direction, 90 - maxSlope;
    - ``boundaryLength()``: summed length of edges used by one face only, m;
    - ``du(uvSet, unitSpace)``, ``dv(uvSet, unitSpace)``: the scope's x and y sizes (m), the
      extent of a scope-aligned projection (pass ``size``); ``uvSpace`` is refused.

    Raises ``ValueError`` with a message for an unknown name or argument.
    """
    rotation = np.asarray(rotation, float)
    if name == "area":
        if not args:
            return mesh.area()
        (selector,) = args
        return float(
            sum(mesh.face_area(k) for k in _selected(mesh, rotation, selector, object_rotation))
        )
    if name == "volume":
        return mesh.volume()
    if name == "height":
        if mesh.n_vertices == 0:
            return 0.0
        heights = mesh.vertices @ rotation[1]
        return float(heights.max() - heights.min())
    if name == "nVertices":
        return float(mesh.n_vertices)
    if name == "nFaces":
        # an edge's line (comp(e), comp(fe): two corners) is no polygon: CityEngine counts 0
        return float(mesh.n_faces) if mesh.n_vertices >= 3 else 0.0
    if name == "nEdges":
        return float(mesh.n_edges)
    if name == "nHoles":
        return float(mesh.n_holes)
    if name == "isClosedSurface":
        return bool(mesh.is_closed)
    if name == "isConcave":
        return any(not mesh.face(k).is_convex() for k in range(mesh.n_faces))
    if name == "isPlanar":
        tolerance = float(args[0]) if args else 0.25
        return mesh.n_faces > 0 and all(
            _face_planar(mesh.face_points(k), tolerance) for k in range(mesh.n_faces)
        )
    if name == "isRectangular":
        tolerance = float(args[0]) if args else 0.0
        return mesh.is_rectangular(tolerance)
    if name == "isOriented":
        (selector,) = args
        return bool(_selected(mesh, rotation, selector, object_rotation))
    if name == "angle":
        (kind,) = args
        return _angle(mesh, rotation, str(kind))
    if name == "boundaryLength":
        return _boundary_length(mesh)
    if name in ("du", "dv"):
        space = str(args[1]) if len(args) > 1 else "uvSpace"
        if space != "unitSpace":
            return 1.0  # the scope's extent, 0 to 1 in uvSpace (TEXTURE_BOUNDS)
        if size is None:
            low, high = mesh.bounds()
            size = high - low
        return float(size[0] if name == "du" else size[1])
    if name in TEXTURE_BOUNDS:
        return 1.0 if name.endswith("Max") else 0.0
    raise ValueError(f"geometry.{name}() is not supported by shapegen")


def _selected(mesh: Mesh, rotation, selector, object_rotation) -> list[int]:
    selector = str(selector)
    if selector == "surface":
        selector = "all"
    if selector not in FACE_SELECTORS:
        raise ValueError(f"unknown face selector {selector!r}")
    normals = mesh.face_normals()
    world = normals @ rotation.T
    obj = world if object_rotation is None else world @ np.asarray(object_rotation, float)
    borders = border_faces(mesh)
    return [
        k
        for k in range(mesh.n_faces)
        if face_matches(selector, normals[k], world[k], obj[k], borders[k])
    ]


def border_faces(mesh: Mesh) -> list[bool]:
    """Per face: does it have an edge that no other face uses?"""
    uses: dict[tuple[int, int], int] = {}
    for face in mesh.faces:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            key = (a, b) if a < b else (b, a)
            uses[key] = uses.get(key, 0) + 1
    return [
        any(
            uses[(a, b) if a < b else (b, a)] == 1
            for a, b in zip(face, face[1:] + face[:1], strict=True)
        )
        for face in mesh.faces
    ]


def _face_planar(points: np.ndarray, tolerance_deg: float) -> bool:
    """op's test: the face normal against the edges' cross product at every vertex."""
    if len(points) <= 3:
        return True
    normal = polygon_normal(points)
    length = float(np.linalg.norm(normal))
    if length == 0:
        return True
    normal = normal / length
    following = np.roll(points, -1, axis=0) - points
    preceding = np.roll(points, 1, axis=0) - points
    local = np.cross(following, preceding)
    lengths = np.linalg.norm(local, axis=1)
    keep = lengths > ROUNDOFF_REL * max(float(np.ptp(points, axis=0).max()), SIZE_FLOOR_M) ** 2
    cosines = np.abs(local[keep] @ normal) / lengths[keep]
    return bool(np.all(cosines >= math.cos(math.radians(tolerance_deg)) - ROUNDOFF_REL))


def _angle(mesh: Mesh, rotation: np.ndarray, kind: str) -> float:
    if kind not in ("maxSlope", "azimuth", "zenith"):
        raise ValueError(f"geometry.angle takes maxSlope, azimuth or zenith, got {kind!r}")
    world = mesh.face_normals() @ rotation.T
    if len(world) == 0:
        return 0.0
    slopes = np.degrees(np.arccos(np.clip(np.abs(world[:, 1]), 0.0, 1.0)))
    k = int(np.argmax(slopes))
    slope = float(slopes[k])
    if kind == "maxSlope":
        return slope
    if kind == "zenith":
        return 90.0 - slope
    # azimuth of the direction the steepest face looks (its normal's horizontal part)
    east, south = float(world[k, 0]), float(world[k, 2])
    if abs(east) < ROUNDOFF_REL and abs(south) < ROUNDOFF_REL:
        return 0.0
    return math.degrees(math.atan2(east, -south)) % 360.0


def _boundary_length(mesh: Mesh) -> float:
    uses: dict[tuple[int, int], int] = {}
    for face in mesh.faces:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            key = (a, b) if a < b else (b, a)
            uses[key] = uses.get(key, 0) + 1
    v = mesh.vertices
    return float(sum(np.linalg.norm(v[a] - v[b]) for (a, b), n in uses.items() if n == 1))
