"""Seconds to build the Cluny grammar (1 072 blocks), and the block validation inside it.

Run: ``.venv/bin/python benchmarks/bench_build.py``. Prints the median of 5 builds of
``cluny.grammar`` with its default attributes (the parameter search rebuilds at every step; the
goal is < 0.15 s): warm, with the primitive templates of earlier builds at hand, and cold, with
them forgotten before each build (wall and CPU seconds); then the validation of the built
model's blocks: one ``Block.validate`` per block against one ``validate_blocks`` call, each on
fresh copies of the blocks (validation fills per-block caches, so a second pass over the same
blocks would measure nothing). Last, a build
followed by what an analysis reads of the blocks first (``Model.validate``, every block's mass and
centroid): work that a build no longer does ahead is paid there; and how much of a build the
checks of the inserts' blocks take.
"""

from __future__ import annotations

import statistics
import time
from unittest import mock

import shapegen
from shapegen.model import Block
from shapegen.primitives import registry

RUNS = 5


def _median_seconds(work, clock=time.perf_counter) -> float:
    timings = []
    for _ in range(RUNS):
        start = clock()
        work()
        timings.append(clock() - start)
    return statistics.median(timings)


def _forget_templates() -> None:
    for made in registry.REGISTRY.values():
        made.templates.clear()


def _cold_build(grammar) -> None:
    _forget_templates()
    grammar.build()


def _fresh(blocks: list[Block]) -> list[Block]:
    return [Block(b.vertices, b.faces, density=b.density, id=b.id) for b in blocks]


def main() -> None:
    grammar = shapegen.load_grammar("cluny.grammar")
    model = grammar.build()  # warm: imports, the parsed grammar, the first hull
    print(f"blocks: {len(model.blocks)}")
    for what, work in (("warm", grammar.build), ("cold", lambda: _cold_build(grammar))):
        wall = _median_seconds(work)
        cpu = _median_seconds(work, time.process_time)
        print(f"cluny build, {what}: median {wall:.3f} s wall, {cpu:.3f} s CPU ({RUNS} runs)")

    def build_and_read() -> None:
        built = grammar.build()
        built.validate()
        sum(block.mass * block.centroid for block in built.blocks)

    seconds = _median_seconds(build_and_read)
    print(f"cluny build + validate + masses and centroids: median {seconds:.3f} s")

    # The share of a build spent checking the blocks each insert returns.
    check = getattr(registry, "first_invalid_block", None)
    if check is not None:
        spent, calls = [], []

        def timed_check(*args):
            start = time.perf_counter()
            try:
                return check(*args)
            finally:
                spent[-1] += time.perf_counter() - start
                calls[-1] += 1

        def counted_build() -> None:
            spent.append(0.0)
            calls.append(0)
            _cold_build(grammar)

        with mock.patch.object(registry, "first_invalid_block", timed_check):
            _median_seconds(counted_build)
        print(
            f"block checks in a cold build: median {statistics.median(spent):.3f} s "
            f"in {calls[-1]} calls (one per distinct primitive shape)"
        )

    tol = model.tolerances()
    copies = [_fresh(model.blocks) for _ in range(RUNS)]

    def one_by_one() -> None:
        for block in copies.pop():
            block.validate(tol)

    print(f"Block.validate, block by block: median {_median_seconds(one_by_one) * 1e3:.1f} ms")
    try:
        from shapegen.model.validation import validate_blocks
    except ImportError:  # before the vectorised check existed
        return
    copies = [_fresh(model.blocks) for _ in range(RUNS)]
    seconds = _median_seconds(lambda: validate_blocks(copies.pop(), tol))
    print(f"validate_blocks, all at once: median {seconds * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
