"""Cost of one evaluation of the bridge search against one build of the bridge model.

During ``shapegen build suspension_bridge.grammar --optimize`` the search evaluates the cable model
only; the bridge (deck, towers, cables, suspenders) is built once, at the end. This script prints
the time of one cable-model evaluation, of one whole search, and of one build.

Run: ``.venv/bin/python benchmarks/bridge_evaluation.py``
"""

from __future__ import annotations

import timeit

import shapegen
from shapegen.engine.bridge_rules import BridgeDesign, optimize_bridge


def main() -> None:
    grammar = shapegen.load_grammar("suspension_bridge.grammar")
    design = BridgeDesign.from_attrs(grammar.attrs)
    calls = 2000
    evaluation = min(timeit.repeat(design.sizing, number=calls, repeat=3)) / calls
    build = min(timeit.repeat(grammar.build, number=1, repeat=3))
    result = optimize_bridge(grammar)
    print(f"cable-model evaluation (size_cables):  {evaluation * 1e6:9.1f} us")
    print(
        f"search: {result.evaluations} evaluations in {result.search_seconds * 1e3:.2f} ms "
        f"({result.seconds_per_evaluation * 1e6:.1f} us per evaluation, Powell included)"
    )
    blocks = len(grammar.build().blocks)
    print(f"full build ({blocks} blocks):          {build * 1e3:9.1f} ms")
    print(f"build / evaluation:                     {build / evaluation:9.0f} x")


if __name__ == "__main__":
    main()
