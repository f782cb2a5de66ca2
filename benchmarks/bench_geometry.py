"""Seconds to derive models whose shapes carry polygon meshes (a polygon lot, not a box).

Run: ``.venv/bin/python benchmarks/bench_geometry.py``. Prints the best and median of five builds
of the same grammar on a rectangle lot (the box fast path: no meshes) and on an L-shaped and a
U-shaped lot of the same size (every floor, slice and stone a cut mesh), with the number of
blocks, surfaces and blocks per second.
"""

from __future__ import annotations

import time

import shapegen

BUILDING = """
@StartRule
Lot --> extrude(24) split(y) { ~3 : Floor }*
Floor --> split(x) { ~1 : Bay }*
Bay --> split(z) { ~1 : Stone }*
"""

LOTS = {
    "rectangle 16 x 12 m (fast path)": (16, 12),
    "L 16 x 12 m": [(0, 0), (16, 0), (16, -6), (8, -6), (8, -12), (0, -12)],
    "U 16 x 12 m": [(0, 0), (16, 0), (16, -12), (11, -12), (11, -4), (5, -4), (5, -12), (0, -12)],
}


def main() -> None:
    grammar = shapegen.parse_grammar(BUILDING)
    for name, lot in LOTS.items():
        timings = []
        for _ in range(5):
            start = time.perf_counter()
            model = grammar.build(lot=lot)
            timings.append(time.perf_counter() - start)
        best = min(timings)
        print(
            f"{name}: {len(model.blocks)} blocks, {len(model.surfaces)} surfaces; best "
            f"{best:.3f} s, median {sorted(timings)[2]:.3f} s ({len(model.blocks) / best:,.0f} "
            f"blocks/s)"
        )


if __name__ == "__main__":
    main()
