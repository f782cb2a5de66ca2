"""The city as 3D Tiles 1.1: the tileset's structure (required members, every content there,
bounding volumes holding their content and their children), and the root transform putting a
lot's corner back at its longitude/latitude."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pyproj = pytest.importorskip("pyproj")

import shapely  # noqa: E402
import trimesh  # noqa: E402

from shapegen.city import city_from_polygons, read_lots  # noqa: E402
from shapegen.city.tiles import enu_to_ecef, write_tiles  # noqa: E402
from shapegen.errors import InputFormatError  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "docs" / "data"


def district_scene(city) -> trimesh.Scene:
    """Each buildable lot as a prism (6 to 12 m) in the city's y-up frame, named by its id."""
    scene = trimesh.Scene()
    for k, lot in enumerate(city.lots):
        if lot.problem is not None:
            continue
        prism = trimesh.creation.extrude_polygon(shapely.Polygon(lot.ring), 6.0 + 3 * (k % 3))
        east, north, up = prism.vertices.T
        prism.vertices = np.column_stack([east, up, -north])  # y up, north -z
        prism.visual.face_colors = [200, 180, 150, 255]
        scene.add_geometry(prism, node_name=lot.id, geom_name=lot.id)
    return scene


def _tiles(tile, ancestors=()):
    yield tile, ancestors
    for child in tile.get("children", []):
        yield from _tiles(child, (*ancestors, tile))


def _box_holds(box, points, tol=1e-6) -> bool:
    centre, axes = np.array(box[:3]), np.array(box[3:]).reshape(3, 3)
    # coordinates along each half-axis, in units of that half-axis
    local = np.linalg.solve(axes.T, (points - centre).T).T
    return bool(np.all(np.abs(local) <= 1 + tol))


def _enu(vertices: np.ndarray) -> np.ndarray:
    """glTF y-up content as 3D Tiles sees it, z up: (x, y, z) -> (x, -z, y)."""
    return np.column_stack([vertices[:, 0], -vertices[:, 2], vertices[:, 1]])


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("city")
    city = read_lots(DATA / "district_3857.geojson")
    tileset = write_tiles(folder, city, scene=district_scene(city), lots_per_tile=4)
    return folder, city, tileset


def test_the_tileset_is_whole_and_its_volumes_hold_their_content(written):
    folder, city, tileset = written
    document = json.loads(tileset.path.read_text())
    assert document["asset"]["version"] == "1.1"
    root = document["root"]
    assert root["refine"] == "ADD" and len(root["transform"]) == 16
    assert document["geometricError"] >= root["geometricError"] > 0
    built = [lot.id for lot in city.lots if lot.problem is None]
    seen = []
    leaves = 0
    for tile, ancestors in _tiles(root):
        assert len(tile["boundingVolume"]["box"]) == 12 and tile["geometricError"] >= 0
        for parent in ancestors:
            assert tile["geometricError"] <= parent["geometricError"]
        if "content" not in tile:
            assert tile["children"], "a tile with neither content nor children"
            continue
        leaves += 1
        assert tile["geometricError"] == 0
        path = tileset.path.parent / tile["content"]["uri"]
        assert path.is_file(), path
        scene = trimesh.load(path, file_type="glb", force="scene")
        for node in scene.graph.nodes_geometry:
            transform, name = scene.graph[node]
            points = _enu(trimesh.transform_points(scene.geometry[name].vertices, transform))
            for holder in (tile, *ancestors):
                assert _box_holds(holder["boundingVolume"]["box"], points), node
            seen.append(node)
    assert sorted(seen) == sorted(built)  # every building once
    assert leaves == tileset.tiles > 1 and tileset.buildings == len(built)
    assert tileset.depth >= 1


def test_the_root_transform_puts_a_corner_back_at_its_lonlat(written):
    folder, city, tileset = written
    document = json.loads(tileset.path.read_text())
    root = document["root"]
    transform = np.array(root["transform"]).reshape(4, 4).T  # column-major
    to_lonlat = pyproj.Transformer.from_crs("EPSG:4978", "EPSG:4979", always_xy=True)
    truth = {f["id"]: f for f in json.loads((DATA / "district.geojson").read_text())["features"]}
    checked = 0
    for tile, _ in _tiles(root):
        if "content" not in tile:
            continue
        scene = trimesh.load(tileset.path.parent / tile["content"]["uri"], force="scene")
        for node in scene.graph.nodes_geometry:
            mesh = scene.geometry[scene.graph[node][1]]
            enu = _enu(mesh.vertices)
            ground = enu[np.abs(enu[:, 2]) < 1e-6]
            ecef = np.column_stack([ground, np.ones(len(ground))]) @ transform.T
            lon, lat, h = to_lonlat.transform(ecef[:, 0], ecef[:, 1], ecef[:, 2])
            corners = np.array(truth[node]["geometry"]["coordinates"][0][:-1])
            metres = np.array([111_320.0 * np.cos(np.radians(46.434)), 111_140.0])
            for point in np.column_stack([lon, lat]):
                gap = np.min(np.hypot(*((corners - point) * metres).T))
                assert gap < 0.02, (node, gap)  # a few cm: here well under a millimetre
            assert np.all(np.abs(h) < 0.05)  # the tangent plane, 200 m across: mm above
            checked += 1
    assert checked == len([lot for lot in city.lots if lot.problem is None])


def test_enu_to_ecef_at_the_equator_and_the_pole():
    at_equator = enu_to_ecef(0.0, 0.0)
    assert np.allclose(at_equator[:3, 3], [6_378_137.0, 0, 0])
    assert np.allclose(at_equator[:3, :3], [[0, 0, 1], [1, 0, 0], [0, 1, 0]])  # e, n, up
    at_pole = enu_to_ecef(0.0, 90.0, height_m=10.0)
    assert np.allclose(at_pole[:3, 3], [0, 0, 6_356_752.314 + 10.0], atol=1e-3)


def test_a_city_in_local_metres_has_no_place_for_tiles(tmp_path):
    city = city_from_polygons([[(0, 0), (10, 0), (10, 8), (0, 8)]], crs="metres")
    with pytest.raises(InputFormatError, match="3D Tiles need the lots' place on the earth"):
        write_tiles(tmp_path, city, scene=district_scene(city))


def test_no_city_glb_is_one_line(tmp_path):
    city = read_lots(DATA / "district.geojson")
    with pytest.raises(InputFormatError, match="no city to tile"):
        write_tiles(tmp_path, city)


def test_buildings_of_a_wide_city_stand_on_their_own_ground(tmp_path):
    """Lots 7-8 km from the city's origin: the origin's tangent plane is some 4 m above the
    ellipsoid there and leans 0.07 degrees; each building is set on its own ground, upright."""
    centres = [(4.60, 46.40), (4.70, 46.40), (4.60, 46.47), (4.70, 46.47), (4.65, 46.435)]
    step = 0.0001  # about 8 by 11 m
    polygons = [
        [(lon, lat), (lon + step, lat), (lon + step, lat + step), (lon, lat + step)]
        for lon, lat in centres
    ]
    city = city_from_polygons(polygons, ids=list("abcde"), crs="lonlat")
    tileset = write_tiles(tmp_path, city, scene=district_scene(city), lots_per_tile=1)
    document = json.loads(tileset.path.read_text())
    transform = np.array(document["root"]["transform"]).reshape(4, 4).T
    to_lonlat = pyproj.Transformer.from_crs("EPSG:4978", "EPSG:4979", always_xy=True)
    geod = pyproj.Geod(ellps="WGS84")
    for tile, _ in _tiles(document["root"]):
        if "content" not in tile:
            continue
        scene = trimesh.load(tileset.path.parent / tile["content"]["uri"], force="scene")
        for node in scene.graph.nodes_geometry:
            enu = _enu(scene.geometry[scene.graph[node][1]].vertices)
            ecef = np.column_stack([enu, np.ones(len(enu))]) @ transform.T
            lon, lat, h = (np.asarray(v) for v in to_lonlat.transform(*ecef[:, :3].T))
            ground = h < 1.0
            assert np.all(np.abs(h[ground]) < 1e-3), (node, h[ground])  # on the ellipsoid
            roof = h[~ground]
            assert np.allclose(roof, roof[0], atol=1e-3) and roof[0] > 5.0  # level, upright
            corners = np.array(polygons["abcde".index(node)])
            for point in np.column_stack([lon[ground], lat[ground]]):
                _, _, gaps = geod.inv(
                    corners[:, 0], corners[:, 1], np.full(4, point[0]), np.full(4, point[1])
                )
                assert np.min(gaps) < 0.01, (node, np.min(gaps))  # cm, the lot's own corner
