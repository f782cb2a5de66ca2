"""Statics benchmark: walls and arches of about 100, 1 000 and 10 000 blocks.

Kinds: ``wall`` (running-bond brick wall, benchmarks/walls.py), ``slide`` (the same wall with
gravity tilted by 12 degrees and friction 0.2: it slides, so phase one and the QP both run),
``arch`` (one semicircular arch of n voussoirs, t/R = 0.2) and ``arches`` (a row of independent
20-voussoir arches).

For each model it prints the seconds spent finding interfaces, assembling and solving (wall
clock and process CPU time, since the machine may be shared), the peak memory, the number of
interior point iterations of each solve with the CPU seconds of its factorisations, and the
verdict; the Clarabel and cvxpy paths are run on the same problem up to a size limit (they grow
much faster than the reduced path).

Run: ``.venv/bin/python benchmarks/bench_statics.py [--sizes 100 1000 10000] [--kinds wall arch]``
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.arches import arch_row, semicircular_arch  # noqa: E402
from benchmarks.walls import running_bond_wall  # noqa: E402
from shapegen.statics import analyze, find_interfaces  # noqa: E402
from shapegen.statics.solvers import reduced  # noqa: E402

SOLVES: list[str] = []  # one entry per reduced solve: iterations and factorisation CPU seconds


def _recording(solve):
    def recorded(self, problem):
        cpu = time.process_time()
        solution = solve(self, problem)
        cpu = time.process_time() - cpu
        info = solution.info
        count = max(info.get("factorizations", 0), 1)
        per_iteration = cpu / max(solution.iterations, 1)
        SOLVES.append(
            f"{solution.iterations} it {cpu:.2f} s (per iteration {per_iteration:.3f} s;"
            f" {info.get('factorization', '-')} {info.get('factor_cpu', 0.0) / count:.3f} s per"
            f" factorisation, M {info.get('normal_assembly_cpu', 0.0) / count:.3f} s"
            + (
                f", {info['factorization_fallbacks']} by SuperLU"
                if info.get("factorization_fallbacks")
                else ""
            )
            + ")"
        )
        return solution

    return recorded


reduced.ReducedBackend.solve = _recording(reduced.ReducedBackend.solve)

# largest model (blocks) each back-end is run on; beyond it the row says "skipped"
LIMITS = {"reduced": 10**9, "clarabel": 2_500, "cvxpy": 1_200}
KINDS = ["wall", "slide", "arch", "arches"]
SLIDE_TILT_DEGREES, SLIDE_FRICTION = 12.0, 0.2


def machine() -> str:
    try:
        text = subprocess.run(["lscpu"], capture_output=True, text=True, check=False).stdout
        model = next(
            (line.split(":", 1)[1].strip() for line in text.splitlines() if "Model name" in line),
            platform.processor(),
        )
    except OSError:
        model = platform.processor()
    return f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}"


def peak_rss_mib() -> float:
    """Peak resident memory of this process so far, MiB (ru_maxrss is in KiB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def build(kind: str, size: int):
    if kind in ("wall", "slide"):
        model = running_bond_wall(size)
        if kind == "slide":
            tilt = math.radians(SLIDE_TILT_DEGREES)
            model.gravity = 9.81 * np.array([math.sin(tilt), -math.cos(tilt), 0.0])
            model.friction = SLIDE_FRICTION
        return model
    if kind == "arch":
        return semicircular_arch(size, 0.2)
    return arch_row(size)


def run(kind: str, size: int, solvers: list[str]) -> None:
    model = build(kind, size)
    for block in model.blocks:  # mass properties belong to the model (computed once, cached)
        _ = block.mass, block.centroid
    start = time.perf_counter()
    interfaces = find_interfaces(model)
    seconds_interfaces = time.perf_counter() - start
    for solver in solvers:
        if len(model.blocks) > LIMITS[solver]:
            print(
                f"{kind:6s} {len(model.blocks):6d} {solver:9s} skipped (above {LIMITS[solver]} "
                "blocks: too slow to be useful)",
                flush=True,
            )
            continue
        wall, cpu = time.perf_counter(), time.process_time()
        SOLVES.clear()
        result = analyze(model, interfaces=interfaces, check=False, solver=solver)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        t = result.timings
        print(
            f"{kind:6s} {len(model.blocks):6d} {solver:9s} interfaces {seconds_interfaces:6.2f} s "
            f"assembly {t['assembly']:6.2f} s solve {t['solve']:7.2f} s "
            f"certify {t['certify']:6.2f} s total {wall:7.2f} s (cpu {cpu:7.2f} s) "
            f"peak {peak_rss_mib():7.0f} MiB  {result.status.value} feasible={result.feasible} "
            f"y/W^2={result.infeasibility_normalized:.2e}"
            + (f"  solves: {'; '.join(SOLVES)}" if SOLVES else ""),
            flush=True,
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[100, 1000, 10000])
    parser.add_argument("--kinds", nargs="+", default=KINDS, choices=KINDS)
    parser.add_argument(
        "--solvers", nargs="+", default=["reduced", "clarabel", "cvxpy"], choices=list(LIMITS)
    )
    parser.add_argument("--single", action="store_true", help="run in this process (internal)")
    args = parser.parse_args()
    if args.single:
        run(args.kinds[0], args.sizes[0], args.solvers)
        return
    print(f"# {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, {machine()}")
    print(f"# load average before: {os.getloadavg()[0]:.1f}")
    for kind in args.kinds:
        for size in args.sizes:
            # one process per model, so that the peak memory is that model's
            command = [
                sys.executable,
                __file__,
                "--single",
                "--kinds",
                kind,
                "--sizes",
                str(size),
                "--solvers",
                *args.solvers,
            ]
            subprocess.run(command, check=False)


if __name__ == "__main__":
    main()
