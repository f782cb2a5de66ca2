"""Cost of one cable-model assessment of the bridge against one search and one build.

The bridge is judged by the "cable" structure, which reads the start rule's
``@Structure("cable", ...)`` arguments and needs no geometry: during
``shapegen build suspension_bridge.grammar --optimize`` each design the search evaluates is the
arguments (``grammar.structure_arguments``) and one cable assessment; the bridge (deck, towers,
cables, suspenders) is built once, at the end. This script prints the time of one assessment, of
one search evaluation (arguments and assessment), of one whole ``optimize`` (with its final
build) and of one build.

Run: ``.venv/bin/python benchmarks/bridge_evaluation.py``
"""

from __future__ import annotations

import time
import timeit

import shapegen
from shapegen.search import optimize
from shapegen.structures import Design, make_structure

# A start whose cables are too thick (the file's own values already stand, so the search stops
# at its first evaluation): the search then has to move main_span and sag.
FAILING_START = {"sag": 100.0}


def main() -> None:
    grammar = shapegen.load_grammar("suspension_bridge.grammar")
    structure = make_structure(grammar.structure)
    arguments = grammar.structure_arguments()
    design = Design(arguments, build=grammar.build)
    calls = 2000
    assessment = structure.assess(design)
    assess = min(timeit.repeat(lambda: structure.assess(design), number=calls, repeat=3)) / calls

    def evaluate():
        return structure.assess(Design(grammar.structure_arguments(), build=grammar.build))

    evaluation = min(timeit.repeat(evaluate, number=calls // 10, repeat=3)) / (calls // 10)
    assert not design.built, "the cable assessment must not build the model"

    started = time.perf_counter()
    result = optimize(grammar)
    full = time.perf_counter() - started
    searched = optimize(grammar, start=FAILING_START, build=False)
    build = min(timeit.repeat(grammar.build, number=1, repeat=3))
    blocks = len(grammar.build().blocks)

    per_evaluation = searched.seconds / searched.evaluations
    print(f"structure {structure.name!r}, measure {structure.measure_name}")
    row("cable assessment (structure.assess)", f"{assess * 1e6:9.1f} us")
    print(
        f"{'':42}d = {assessment.section['cable_diameter']:.4f} m, allowed"
        f" {assessment.section['allowed_diameter']:.4f} m, stands: {assessment.stands}"
    )
    row("search evaluation (arguments + assess)", f"{evaluation * 1e6:9.1f} us")
    row(
        "optimize (the file's values, with build)",
        f"{full * 1e3:9.1f} ms  {result.evaluations} evaluations, {result.iterations}"
        f" iterations ({result.method}): {result.message}",
    )
    row(
        f"optimize from sag {FAILING_START['sag']:g} m (no build)",
        f"{searched.seconds * 1e3:9.1f} ms  {searched.evaluations} evaluations,"
        f" {searched.iterations} iterations ({searched.method}): {searched.message};"
        f" {per_evaluation * 1e6:.1f} us per evaluation, {searched.method} included",
    )
    row(f"full build ({blocks} blocks)", f"{build * 1e3:9.1f} ms")
    row("build / assessment", f"{build / assess:9.0f} x")


def row(label: str, value: str) -> None:
    print(f"{label + ':':42}{value}")


if __name__ == "__main__":
    main()
