"""Lots per second of ``shapegen city`` on 1 and 2 worker processes, and memory per worker.

Run: ``.venv/bin/python benchmarks/bench_city.py [LOTS]`` (default 1 000). Builds and analyzes
LOTS lots with the bundled ``wall_windows.grammar`` (a 90-block wall with four arched windows on
a 12 m lot; widths vary from 8 to 16 m, so the walls have 48 to 112 blocks) on 1 and then 2
local worker processes, and prints for each: the wall-clock seconds of the lots (workers' start
included), lots per second, the scaling against one worker, the median and 95th percentile of
one lot's seconds inside its worker, and the largest peak resident memory of a worker (MiB).
Then the seconds to write the tables and the city glTF of all the lots, which the parent does
once at the end. The figures are recorded in docs/performance.md.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import shapegen
from shapegen.city import city_from_polygons, run_city
from shapegen.city.outputs import write_tables


def _city(count: int):
    polygons, properties = [], []
    for k in range(count):
        width = 8.0 + (k % 9)  # 8..16 m
        x, z = (k % 40) * 20.0, (k // 40) * 6.0
        polygons.append([(x, z), (x + width, z), (x + width, z + 0.6), (x, z + 0.6)])
        properties.append({"windows": 2 + width // 4})
    return city_from_polygons(polygons, properties=properties, crs="metres")


def main() -> None:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    grammar = shapegen.load_grammar("wall_windows")
    city = _city(count)
    print(f"{count} lots of wall_windows.grammar; {os.cpu_count()} cores on this machine")
    rates = {}
    with tempfile.TemporaryDirectory() as folder:
        for workers in (1, 2):
            out = Path(folder) / f"w{workers}"
            started = time.perf_counter()
            run = run_city(city, grammar, out, workers=workers, scene=False)
            seconds = time.perf_counter() - started
            records = [r for r in run.records if r is not None]
            lot_seconds = sorted(r["seconds"] for r in records if r["seconds"] is not None)
            peak = max(r["peak_rss_mib"] or 0.0 for r in records)
            blocks = sum(r["blocks"] or 0 for r in records)
            rates[workers] = count / seconds
            print(
                f"{workers} worker(s): {seconds:.1f} s, {rates[workers]:.2f} lots/s"
                f" (scaling {rates[workers] / rates[1]:.2f}x), {blocks} blocks,"
                f" {run.failed} failed; one lot: median {statistics.median(lot_seconds):.3f} s,"
                f" 95th percentile {lot_seconds[int(0.95 * (len(lot_seconds) - 1))]:.3f} s;"
                f" peak memory per worker {peak:.0f} MiB"
            )
        started = time.perf_counter()
        write_tables(out, city, run.records, scene=True)
        size = (out / "city.glb").stat().st_size
        print(
            f"tables and city.glb of {count} lots: {time.perf_counter() - started:.1f} s"
            f" (city.glb {size / 2**20:.1f} MiB)"
        )


if __name__ == "__main__":
    main()
