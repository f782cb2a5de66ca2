"""How long a picture takes: the depth-buffer rendering alone, and the whole PNG (legend, title).

Builds each bundled rule file named (Cluny and the bridge by default) and prints, for an
800 x 600 picture at 3 x 3 samples a pixel, the triangles drawn and the median over the runs of
the CPU and wall seconds of ``render_blocks`` and of ``encode_picture`` (tension colours and
legend when the structure is block statics).

    .venv/bin/python benchmarks/bench_picture.py
    .venv/bin/python benchmarks/bench_picture.py --rules cluny,tower --runs 7
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import shapegen
from shapegen.export.picture import _label_colors, encode_picture
from shapegen.export.render import render_blocks
from shapegen.statics import analyze


def timed(call, runs: int) -> tuple[float, float]:
    """Median CPU and wall seconds of ``call()`` over ``runs`` runs."""
    cpu, wall = [], []
    for _ in range(runs):
        c, w = time.process_time(), time.perf_counter()
        call()
        cpu.append(time.process_time() - c)
        wall.append(time.perf_counter() - w)
    return statistics.median(cpu), statistics.median(wall)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rules", default="cluny,suspension_bridge")
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    print(f"{'rules':<18} {'blocks':>6} {'triangles':>9} {'render cpu/wall s':>18} "
          f"{'PNG cpu/wall s':>15}")  # fmt: skip
    for name in args.rules.split(","):
        grammar = shapegen.load_grammar(f"{name.strip()}.grammar")
        model = grammar.build()
        analysis = analyze(model) if grammar.structure == "blocks" else None
        triangles = sum(len(face) - 2 for b in model.blocks for face in b.faces)
        colors = _label_colors(model)
        render = timed(lambda m=model, c=colors: render_blocks(m, c), args.runs)
        png = timed(lambda m=model, a=analysis: encode_picture(m, a), args.runs)
        print(f"{name:<18} {len(model.blocks):>6} {triangles:>9} "
              f"{render[0]:>8.2f} / {render[1]:<7.2f} {png[0]:>6.2f} / {png[1]:<6.2f}")  # fmt: skip
    print("load average " + ", ".join(f"{load:.1f}" for load in os.getloadavg()))


if __name__ == "__main__":
    main()
