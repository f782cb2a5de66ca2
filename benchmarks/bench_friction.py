"""Friction models compared: the cost of one analysis with the 4-sided pyramid and the exact cone.

For each model (a running-bond wall of about 1 000 blocks, the bundled Cluny nave and, with
``--rules``, any other bundled block rule) it prints, per friction model and back-end, the wall
and process CPU seconds of one ``analyze`` (interfaces found once, outside the timing), split
into phase one and QP, the verdict and ``y/W^2``. Each configuration runs ``--repeat`` times and
the median is printed, since the machine may be shared. Verdicts that differ between the
friction models are the point of the option, not an error.

Run: ``.venv/bin/python benchmarks/bench_friction.py [--repeat 3] [--rules cluny wall_windows]``
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import shapegen  # noqa: E402
from benchmarks.walls import running_bond_wall  # noqa: E402
from shapegen.statics import analyze, find_interfaces  # noqa: E402

CONFIGURATIONS = [
    ("4", "auto"),  # the default: the reduced interior point method
    ("4", "clarabel"),
    ("8", "auto"),
    ("cone", "auto"),  # Clarabel with one second-order cone per vertex
]


def models(rules: list[str]):
    yield "wall 1000", running_bond_wall(1000)
    for name in rules:
        yield name, shapegen.load_grammar(f"{name}.grammar").build()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--rules", nargs="*", default=["cluny"])
    args = parser.parse_args()
    print(f"# load average before: {os.getloadavg()[0]:.1f}; median of {args.repeat}")
    for label, model in models(args.rules):
        interfaces = find_interfaces(model)
        vertices = sum(len(i.vertices) for i in interfaces)
        print(
            f"{label}: {len(model.blocks)} blocks, {len(interfaces)} interfaces, "
            f"{vertices} vertices"
        )
        for pyramid, solver in CONFIGURATIONS:
            walls, cpus, solves = [], [], []
            for _ in range(args.repeat):
                wall, cpu = time.perf_counter(), time.process_time()
                result = analyze(
                    model, interfaces=interfaces, check=False, pyramid=pyramid, solver=solver
                )
                walls.append(time.perf_counter() - wall)
                cpus.append(time.process_time() - cpu)
                solves.append(result.timings["solve"])
            print(
                f"  pyramid {pyramid:4s} solver {solver:8s} -> {result.solver:8s} "
                f"total {statistics.median(walls):6.2f} s (cpu {statistics.median(cpus):6.2f} s, "
                f"solves {statistics.median(solves):6.2f} s)  feasible={result.feasible} "
                f"y/W^2={result.infeasibility_normalized:.3e}",
                flush=True,
            )


if __name__ == "__main__":
    main()
