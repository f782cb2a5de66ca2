"""The tilting-table curve of the semicircular arch: critical tilt over t/R, by voussoir count.

A semicircular arch with radial joints (``shapegen.primitives.arch.semicircular_arch``, the
construction of the validation tests), centreline radius 1 m, depth 0.5 m, on the ground plane,
friction 5 so that no joint slides (hinges govern). For each thickness ratio t/R and each number
of voussoirs it prints the critical tilt in the plane of the arch (azimuth 0), from the lateral
capacity (the load-multiplier program, confirmed by the verdict to 0.05 degrees), and the
seconds it took. These are the figures of docs/statics.md, "Lateral capacity".

Run: ``.venv/bin/python benchmarks/bench_arch_tilt.py [--voussoirs 20 50 100 200]``
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from shapegen.model.model import Model  # noqa: E402
from shapegen.primitives.arch import semicircular_arch  # noqa: E402
from shapegen.statics.capacity import lateral_capacity  # noqa: E402

RATIOS = [0.11, 0.12, 0.13, 0.14, 0.15, 0.16, 0.17, 0.18, 0.19, 0.20, 0.22, 0.25, 0.28, 0.30]


def critical_tilt(ratio: float, voussoirs: int) -> tuple[float, bool, float]:
    model = Model(semicircular_arch(1.0, ratio, voussoirs, depth=0.5), ground=0.0, friction=5.0)
    start = time.perf_counter()
    capacity = lateral_capacity(model, azimuths=[0.0])
    return capacity.tilt, capacity.worst.checked, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--voussoirs", type=int, nargs="+", default=[20, 50, 100, 200])
    parser.add_argument("--ratios", type=float, nargs="+", default=RATIOS)
    args = parser.parse_args()
    header = "| t/R | " + " | ".join(f"{n} voussoirs" for n in args.voussoirs) + " |"
    print(header)
    print("|" + "---|" * (len(args.voussoirs) + 1))
    seconds = dict.fromkeys(args.voussoirs, 0.0)
    for ratio in args.ratios:
        cells = []
        for n in args.voussoirs:
            tilt, checked, spent = critical_tilt(ratio, n)
            seconds[n] += spent
            cells.append(f"{tilt:.2f}" + ("" if checked else " (unchecked)"))
        print(f"| {ratio:.2f} | " + " | ".join(cells) + " |", flush=True)
    print(
        "seconds per arch: "
        + ", ".join(f"{n}: {seconds[n] / len(args.ratios):.3f}" for n in args.voussoirs)
    )


if __name__ == "__main__":
    main()
