"""The city as OGC 3D Tiles 1.1: a ``tileset.json`` whose leaf tiles each hold the buildings of
a group of lots as one ``.glb``, placed on the WGS84 ellipsoid.

Tiles. The built lots are grouped by a quadtree over their centres (east, north): a square
cell of more than ``lots_per_tile`` lots is cut into four, down to cells of at most that many
(or to lots that share a centre). Cells with lots are tiles; a leaf tile's content is the
``.glb`` of its lots' buildings, one node per building named by its lot id, as in ``city.glb``.
Every tile's bounding volume is a ``box`` holding all its content; refinement is ``ADD``.
A leaf's ``geometricError`` is 0 (its content is the buildings themselves); a tile above
them has no content, so drawing it instead of its children leaves out everything in it: its
error is its box's diagonal (m), as is the tileset's.

Frames. shapegen's local frame is y-up (east +x, up +y, north -z), as glTF is. 3D Tiles is
z-up: a client turns glTF content z-up by the rotation ``(x, y, z) -> (x, -z, y)`` (3D Tiles
1.1, "glTF transforms"), which makes the local frame east, north, up (ENU). The root tile's
``transform`` takes ENU at the city's origin (its ``origin_lonlat``, at ellipsoid height
``height``) to earth-centred, earth-fixed coordinates (EPSG:4978). Bounding volumes and
contents are in the root's ENU frame.

Each building on its own ground. A city's lots are read in the tangent plane at its origin
(:func:`shapegen.readers.projection.east_north`), whose lengths over a lot differ from the
ground's by less than ``(d / R)^2 / 6`` (3e-7 at 10 km), but the plane rises ``d^2 / 2R`` above
the ellipsoid and its up leans ``d / R`` away from the local vertical at a distance ``d`` (2 m
and 0.04 degrees at 5 km). So every building is set on its own place before it is written:
the point of the ellipsoid (at ``height``) under its centre is found, and the building, turned
from the origin's east-north-up to that point's, stands there. A corner then goes back to its
longitude/latitude and height to well under a millimetre, however wide the city.

Heights are above the ellipsoid, not above sea level or terrain: at Cluny the geoid is some
50 m above the ellipsoid, so on a globe with terrain pass ``height`` (the ground's ellipsoidal
height at the origin).
"""

from __future__ import annotations

__all__ = ["TILES_FOLDER", "Tileset", "enu_to_ecef", "tileset_from_scene", "write_tiles"]

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.export.atomic import atomic_write
from shapegen.readers.projection import WGS84_A, WGS84_F
from shapegen.tolerances import COINCIDENT_M

TILES_FOLDER = "tiles"
LOTS_PER_TILE = 16
_MIN_HALF_M = 0.01  # a box's smallest half extent, m (flat content still has a volume)
_Y_UP_TO_Z_UP = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], dtype=float)  # (x, y, z) -> (x, -z, y)


@dataclass(frozen=True)
class Tileset:
    """What :func:`write_tiles` wrote: the ``tileset.json`` path, the leaf tiles (content
    files), the buildings in them, and the tree's depth."""

    path: Path
    tiles: int
    buildings: int
    depth: int


def enu_to_ecef(lon_deg: float, lat_deg: float, height_m: float = 0.0) -> np.ndarray:
    """``(4, 4)`` the transform from east, north, up (m) at a WGS84 point to earth-centred,
    earth-fixed coordinates (m)."""
    lam, phi = math.radians(lon_deg), math.radians(lat_deg)
    e2 = WGS84_F * (2.0 - WGS84_F)
    prime_vertical = WGS84_A / math.sqrt(1.0 - e2 * math.sin(phi) ** 2)
    origin = np.array(
        [
            (prime_vertical + height_m) * math.cos(phi) * math.cos(lam),
            (prime_vertical + height_m) * math.cos(phi) * math.sin(lam),
            (prime_vertical * (1.0 - e2) + height_m) * math.sin(phi),
        ]
    )
    east = np.array([-math.sin(lam), math.cos(lam), 0.0])
    north = np.array(
        [-math.sin(phi) * math.cos(lam), -math.sin(phi) * math.sin(lam), math.cos(phi)]
    )
    up = np.array([math.cos(phi) * math.cos(lam), math.cos(phi) * math.sin(lam), math.sin(phi)])
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2], matrix[:3, 3] = east, north, up, origin
    return matrix


def write_tiles(
    folder: str | Path,
    city,
    *,
    scene=None,
    lots_per_tile: int = LOTS_PER_TILE,
    height: float = 0.0,
) -> Tileset:
    """Write ``folder/tiles/tileset.json`` and its ``.glb`` tiles from the city's buildings.

    Parameters
    ----------
    folder
        A city run's output folder.
    city
        The :class:`~shapegen.city.City` run (its ``origin_lonlat`` places the tiles).
    scene
        The city's trimesh scene, as ``city.glb`` holds it (a node per building named by its
        lot id, y-up local metres); default: the folder's ``city.glb``.
    lots_per_tile
        The most lots in one tile.
    height
        The local ground's height above the WGS84 ellipsoid, m.

    Raises
    ------
    InputFormatError
        A city in local metres (no place on the earth), or no ``city.glb`` to tile.
    """
    folder = Path(folder)
    if getattr(city, "origin_lonlat", None) is None:
        raise InputFormatError(
            f"{city.source or 'the city'}: 3D Tiles need the lots' place on the earth; its"
            " coordinates are local metres (name their system: --crs EPSG:NNNN)"
        )
    if not (isinstance(lots_per_tile, int) and lots_per_tile >= 1):
        raise InputFormatError(f"lots per tile must be a whole number >= 1, got {lots_per_tile!r}")
    if scene is None:
        import trimesh

        glb = folder / "city.glb"
        if not glb.is_file():
            raise InputFormatError(f"{glb}: no city to tile (the run wrote no city.glb)")
        scene = trimesh.load(glb, file_type="glb", force="scene")
        if not any(True for _ in _buildings(scene)):
            raise InputFormatError(f"{glb}: holds no building to tile")
    document, contents, depth = tileset_from_scene(
        scene, city.origin_lonlat, lots_per_tile=lots_per_tile, height=height
    )
    out = folder / TILES_FOLDER
    out.mkdir(parents=True, exist_ok=True)
    for name, data in contents.items():
        with atomic_write(out / name, "wb") as handle:
            handle.write(data)
    path = out / "tileset.json"
    with atomic_write(path) as handle:
        json.dump(document, handle, indent=1)
        handle.write("\n")
    buildings = sum(1 for _ in _buildings(scene))
    return Tileset(path, len(contents), buildings, depth)


def _buildings(scene):
    """``(lot id, mesh)`` of every building of a city scene, its node's transform applied."""
    for node in scene.graph.nodes_geometry:
        transform, geometry = scene.graph[node]
        mesh = scene.geometry[geometry]
        if len(mesh.faces) == 0:
            continue
        if not np.allclose(transform, np.eye(4)):
            mesh = mesh.copy()
            mesh.apply_transform(transform)
        yield str(node), mesh


def tileset_from_scene(scene, origin_lonlat, *, lots_per_tile=LOTS_PER_TILE, height=0.0):
    """The tileset document, its contents ``{file name: glb bytes}`` and the tree's depth, of a
    city scene (y-up local metres) whose origin is ``origin_lonlat`` ``(lon, lat)`` degrees."""
    buildings = list(_buildings(scene))
    if not buildings:
        raise InputFormatError("no building to tile: the city's scene holds none")
    # east and north of each building's centre (glTF z is south)
    bounds = np.array([mesh.bounds for _, mesh in buildings])  # (n, 2, 3)
    centres = 0.5 * (bounds[:, 0] + bounds[:, 1])
    en = np.column_stack([centres[:, 0], -centres[:, 2]])
    buildings = _seated(buildings, en, origin_lonlat, height)
    contents: dict[str, bytes] = {}
    root, depth = _tile(buildings, en, np.arange(len(buildings)), "t", contents, lots_per_tile)
    root["refine"] = "ADD"
    root["transform"] = [float(v) for v in enu_to_ecef(*origin_lonlat, height).T.reshape(-1)]
    document = {
        "asset": {"version": "1.1", "generator": "shapegen city"},
        "geometricError": root["geometricError"],
        "root": root,
    }
    return document, contents, depth


def _seated(buildings, en, origin_lonlat, height):
    """The buildings, each moved from the origin's tangent plane onto its own place: the
    ellipsoid's point at ``height`` under its centre ``en`` (east, north of the origin, m), with
    that point's vertical as its up (see the module's documentation)."""
    import pyproj

    root = enu_to_ecef(*origin_lonlat, height)
    root_turn, root_origin = root[:3, :3], root[:3, 3]
    to_geodetic = pyproj.Transformer.from_crs("EPSG:4978", "EPSG:4979", always_xy=True)
    radius = WGS84_A
    up = -(en[:, 0] ** 2 + en[:, 1] ** 2) / (2.0 * radius)  # the plane's height over the ground
    for _ in range(3):  # the up that puts each centre at ``height``; converges in two
        ecef = root_origin + np.column_stack([en, up]) @ root_turn.T
        lon, lat, above = to_geodetic.transform(ecef[:, 0], ecef[:, 1], ecef[:, 2])
        up = up - (np.asarray(above) - height)
    seated = []
    for k, (lot_id, mesh) in enumerate(buildings):
        own = enu_to_ecef(float(lon[k]), float(lat[k]), height)
        # building ENU about its centre -> ECEF at its own place -> the root's ENU
        turn = root_turn.T @ own[:3, :3]
        shift = root_turn.T @ (own[:3, 3] - root_origin)
        local = mesh.vertices @ _Y_UP_TO_Z_UP.T - np.array([en[k, 0], en[k, 1], 0.0])
        placed = (local @ turn.T + shift) @ _Y_UP_TO_Z_UP  # back to y-up
        mesh = mesh.copy()
        mesh.vertices = placed
        seated.append((lot_id, mesh))
    return seated


def _tile(buildings, en, members, name, contents, lots_per_tile, level=0):
    """A tile (and its children) over the buildings ``members``; its depth below it."""
    lo, hi = en[members].min(axis=0), en[members].max(axis=0)
    if len(members) <= lots_per_tile or np.all(hi - lo < COINCIDENT_M):
        contents[f"{name}.glb"] = _glb([buildings[k] for k in members])
        tile = {
            "boundingVolume": {"box": _box([buildings[k][1] for k in members])},
            "geometricError": 0.0,
            "content": {"uri": f"{name}.glb"},
        }
        return tile, 0
    # a square cell, cut at its middle into four
    middle = 0.5 * (lo + hi)
    east_half, north_half = en[members, 0] >= middle[0], en[members, 1] >= middle[1]
    children, depth = [], 0
    for quadrant, (e, n) in enumerate([(False, False), (True, False), (False, True), (True, True)]):
        inside = members[(east_half == e) & (north_half == n)]
        if len(inside):
            child, below = _tile(
                buildings, en, inside, f"{name}{quadrant}", contents, lots_per_tile, level + 1
            )
            children.append(child)
            depth = max(depth, below + 1)
    box = _box([buildings[k][1] for k in members])
    diagonal = 2.0 * float(np.linalg.norm(np.array(box[3:]).reshape(3, 3).sum(axis=0)))
    return {"boundingVolume": {"box": box}, "geometricError": diagonal, "children": children}, depth


def _box(meshes) -> list[float]:
    """A 3D Tiles ``box`` (centre, then three half-axes) in the ENU frame holding ``meshes``
    (y-up local metres)."""
    points = np.concatenate([mesh.bounds for mesh in meshes]) @ _Y_UP_TO_Z_UP.T
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre = 0.5 * (lo + hi)
    half = np.maximum(0.5 * (hi - lo), _MIN_HALF_M)
    axes = np.diag(half)
    return [float(v) for v in np.concatenate([centre, axes.reshape(-1)])]


def _glb(buildings) -> bytes:
    """One glb of ``(lot id, mesh)`` buildings, a node per building named by its id."""
    import trimesh

    scene = trimesh.Scene()
    for lot_id, mesh in buildings:
        scene.add_geometry(mesh, node_name=lot_id, geom_name=lot_id)
    return trimesh.exchange.gltf.export_glb(scene)
