"""Seconds to derive a 10 000-block model from a grammar (the optimizer rebuilds at every step).

Run: ``.venv/bin/python benchmarks/bench_derivation.py``. Prints the best of several runs for a
masonry wall of 100 courses x 100 stones with running bond, labels, a stochastic rule and
per-course attributes: the kind of per-shape work real rule files do.
"""

from __future__ import annotations

import time

import shapegen

WALL = """
attr courses = 100
attr stones = 100
attr height = 50
@StartRule @Lot(50, 0.6)
Lot --> extrude(height) split(y) { ~height / courses : Course(split.index) }*
Course(k) --> label("course") set(density, 2000 + 10 * (k % 5)) Bond(k)
Bond(k) --> case k % 2 == 0 : split(x) { ~scope.sx / stones : Stone }*
            else : split(x) { 0.25 : Stone | { ~scope.sx / stones : Stone }* | 0.25 : Stone }
Stone --> 20% : label("dark") i("box")
          else : Block.
"""


def main() -> None:
    grammar = shapegen.parse_grammar(WALL)
    timings = []
    for seed in range(5):
        start = time.perf_counter()
        model = grammar.build(seed=seed)
        timings.append(time.perf_counter() - start)
    print(f"blocks: {len(model.blocks)}")
    print(
        f"derivation: best {min(timings):.3f} s, median {sorted(timings)[2]:.3f} s "
        f"(5 runs, {len(model.blocks) / min(timings):,.0f} blocks/s)"
    )


if __name__ == "__main__":
    main()
