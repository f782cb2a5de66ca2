"""How long a model's glTF takes to write: ``encode_glb`` of bundled rule files' models (what
``shapegen build -o model.glb`` and the design page's every edit write), with and without an
analysis (tension colours and resultant arrows).

    .venv/bin/python benchmarks/bench_gltf.py
    .venv/bin/python benchmarks/bench_gltf.py --rules cluny,tower --runs 9
"""

from __future__ import annotations

import argparse
import os
import time

import shapegen
from shapegen.export.gltf import encode_glb
from shapegen.statics import analyze


def least_cpu(call, runs: int) -> float:
    """The least CPU seconds of ``call()`` over ``runs`` runs."""
    best = float("inf")
    for _ in range(runs):
        start = time.process_time()
        call()
        best = min(best, time.process_time() - start)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rules", default="cluny,suspension_bridge")
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.1f}; least CPU of {args.runs} runs")
    for name in args.rules.split(","):
        model = shapegen.load_grammar(f"{name}.grammar").build()
        plain = least_cpu(lambda m=model: encode_glb(m), args.runs)
        analysis = analyze(model) if model.blocks else None
        judged = least_cpu(lambda m=model, a=analysis: encode_glb(m, a), args.runs)
        size = len(encode_glb(model)) / 1e6
        print(
            f"{name}: {len(model.blocks)} blocks, {len(model.surfaces)} surfaces, {size:.2f} MB;"
            f" encode_glb {plain:.4f} s, with the analysis {judged:.4f} s CPU"
        )


if __name__ == "__main__":
    main()
