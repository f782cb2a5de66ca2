"""Lots per second of ``shapegen city`` on 1 and 2 worker processes, and memory per worker.

Run: ``.venv/bin/python benchmarks/bench_city.py [LOTS]`` (default 1 000). Builds and analyzes
LOTS lots with the bundled ``wall_windows.grammar`` (a 90-block wall with four arched windows on
a 12 m lot; widths vary from 8 to 16 m, so the walls have 48 to 112 blocks) on 1 and then 2
local worker processes, and prints for each: the wall-clock seconds of the lots (workers' start
included), lots per second, the scaling against one worker, the median and 95th percentile of
one lot's seconds inside its worker, and the largest peak resident memory of a worker (MiB).
Then the CPU the one parent process spends per lot (scheduling the batches, merging the records
the workers wrote, the tables), the seconds to write the tables and the city glTF of all the
lots (once, at the end), and, with
dask.distributed installed, the rate on a two-worker ``LocalCluster`` over the first 300 lots
(the scheduler's cost per task against local processes). The figures are recorded in
docs/performance.md (the current figure) and docs/journal/performance.md (each run).
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
            started, parent = time.perf_counter(), time.process_time()
            run = run_city(city, grammar, out, workers=workers, scene=False)
            seconds, parent = time.perf_counter() - started, time.process_time() - parent
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
        _parent_cost(parent, count)
        started = time.perf_counter()
        write_tables(out, city, run.records, scene=True)
        size = (out / "city.glb").stat().st_size
        print(
            f"tables and city.glb of {count} lots: {time.perf_counter() - started:.1f} s"
            f" (city.glb {size / 2**20:.1f} MiB)"
        )
    _dask(city, grammar)


def _parent_cost(parent_cpu: float, count: int) -> None:
    """CPU seconds the parent process spends per lot: scheduling batches, merging the records
    the workers wrote, the tables (city.glb is left to the line below)."""
    print(f"the parent spends {1000 * parent_cpu / count:.3f} ms of CPU a lot (tables included)")


def _dask(city, grammar, count: int = 300) -> None:
    try:
        import distributed
    except ImportError:
        print("dask.distributed not installed: no cluster figure")
        return
    from shapegen.city.city_lots import City

    part = City(city.lots[:count], city.crs, city.origin)
    with tempfile.TemporaryDirectory() as folder:
        for label, kwargs in (("2 local processes", {"workers": 2}), ("dask", {})):
            if label == "dask":
                cluster = distributed.LocalCluster(
                    n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
                )
                client = distributed.Client(cluster)
                kwargs = {"scheduler": client}
            started = time.perf_counter()
            run_city(part, grammar, Path(folder) / label, scene=False, **kwargs)
            seconds = time.perf_counter() - started
            if label == "dask":
                client.close()
                cluster.close()
            print(f"{count} lots on {label}: {seconds:.1f} s, {count / seconds:.2f} lots/s")


if __name__ == "__main__":
    main()
