"""Seconds to write a city's 3D Tiles (``shapegen city --tiles``) and to read its lots in a
projected system, for the 30-lot district and for cities of 1 000 and more buildings.

Run: ``.venv/bin/python benchmarks/bench_city_tiles.py [BUILDINGS...]`` (default 1 000). The
district is built once with ``docs/data/house.grammar`` from its Lambert-93 copy (2 workers);
its tiles are then written from its ``city.glb``. The larger cities repeat the district's
buildings on a grid of districts 250 m apart (the same meshes, so the same triangles per
building) and write their tiles from that scene. Each figure is the CPU seconds of this process
(``time.process_time``) and the wall seconds, the best of 3, with the tiles, the buildings and
the bytes written. Then the seconds to read the district in EPSG:2154 and in EPSG:3857 (pyproj
to lon/lat, then the tangent plane) against the lon/lat file.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

import shapegen
from shapegen.city import read_lots, run_city
from shapegen.city.tiles import write_tiles

DATA = Path(__file__).resolve().parents[1] / "docs" / "data"


def _best(action, repeats=3):
    best = None
    for _ in range(repeats):
        cpu, wall = time.process_time(), time.perf_counter()
        result = action()
        spent = (time.process_time() - cpu, time.perf_counter() - wall)
        best = spent if best is None or spent[1] < best[1] else best
    return best, result


def _bytes(folder: Path) -> int:
    return sum(p.stat().st_size for p in (folder / "tiles").iterdir())


def _repeated(scene: trimesh.Scene, count: int) -> trimesh.Scene:
    """``count`` buildings: the scene's, repeated on a grid of districts 250 m apart."""
    buildings = [
        (node, scene.geometry[scene.graph[node][1]]) for node in scene.graph.nodes_geometry
    ]
    side = int(np.ceil(np.sqrt(count / len(buildings))))
    big = trimesh.Scene()
    for k in range(count):
        copy, which = divmod(k, len(buildings))
        node, mesh = buildings[which]
        moved = mesh.copy()
        moved.apply_translation([250.0 * (copy % side), 0.0, -250.0 * (copy // side)])
        big.add_geometry(moved, node_name=f"{node}/{copy}", geom_name=f"{node}/{copy}")
    return big


def main() -> None:
    sizes = [int(a) for a in sys.argv[1:]] or [1000]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "district"
        city = read_lots(DATA / "district_l93.geojson")
        grammar = shapegen.load_grammar(str(DATA / "house.grammar"))
        run = run_city(city, grammar, folder, workers=2)
        print(f"district: {run.built} of {len(city.lots)} lots built in {run.seconds:.1f} s")
        (cpu, wall), tileset = _best(lambda: write_tiles(folder, city))
        print(
            f"tiles of the district: {tileset.buildings} buildings, {tileset.tiles} tiles,"
            f" {_bytes(folder) / 1e3:.0f} kB: {cpu:.3f} s CPU, {wall:.3f} s wall"
        )
        scene = trimesh.load(folder / "city.glb", file_type="glb", force="scene")
        for count in sizes:
            big = _repeated(scene, count)
            out = Path(tmp) / f"city{count}"
            (cpu, wall), tileset = _best(lambda out=out, big=big: write_tiles(out, city, scene=big))
            print(
                f"tiles of {count} buildings: {tileset.tiles} tiles, depth {tileset.depth},"
                f" {_bytes(out) / 1e6:.1f} MB: {cpu:.2f} s CPU, {wall:.2f} s wall"
            )
    for name in ("district.geojson", "district_l93.geojson", "district_3857.geojson"):
        (cpu, wall), read = _best(lambda name=name: read_lots(DATA / name), repeats=5)
        print(f"read {name} ({read.crs}): {cpu * 1e3:.0f} ms CPU, {wall * 1e3:.0f} ms wall")


if __name__ == "__main__":
    main()
