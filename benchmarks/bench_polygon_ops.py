"""CPU seconds of the straight skeleton's operations: hip roofs, inward offsets and setbacks.

Run: ``.venv/bin/python benchmarks/bench_polygon_ops.py``. Prints the best of several runs for
polygons of 4 to 128 vertices (a wavy star: about half its vertices reflex), and the cost of
a building with an offset court and a hip roof derived from rule text.
"""

from __future__ import annotations

import time

import numpy as np

import shapegen
from shapegen.geometry import polygon2d, roofs

RULE = """
@StartRule @Lot(12, 8)
Lot      --> shapeL(4, 3) { shape : extrude(3) Wing | remainder : Court }
Court    --> offset(-1) comp(f) { inside : Building | border : Yard }
Building --> roofHip(30) Roof
"""


def _star(n: int) -> np.ndarray:
    angle = np.linspace(0, 2 * np.pi, n, endpoint=False)
    radius = 10 + (2 * np.sin(5 * angle) if n > 8 else 0)
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])


def _best(call, repeats: int) -> float:
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        call()
        best = min(best, time.process_time() - start)
    return best


def main() -> None:
    for n in (4, 8, 16, 32, 64, 128):
        polygon = _star(n)
        repeats = max(3, 256 // n)
        hip = _best(lambda p=polygon: roofs.roof_hip(p, 30), repeats)
        offset = _best(lambda p=polygon: polygon2d.offset(p, -1.0), repeats)
        one_edge = np.zeros(n)
        one_edge[0] = 1.0
        setback = _best(lambda p=polygon, d=one_edge: polygon2d.setback(p, d), repeats)
        print(f"{n:4d} vertices: hip roof {hip * 1e3:8.2f} ms, offset(-1) {offset * 1e3:7.2f} ms, "
              f"setback of one edge {setback * 1e3:7.2f} ms")  # fmt: skip
    grammar = shapegen.parse_grammar(RULE)
    build = _best(grammar.build, 5)
    model = grammar.build()
    print(f"L wing, offset court and hip roof: {len(model.blocks)} blocks, "
          f"{len(model.surfaces)} surfaces, {build * 1e3:.1f} ms per build")  # fmt: skip


if __name__ == "__main__":
    main()
