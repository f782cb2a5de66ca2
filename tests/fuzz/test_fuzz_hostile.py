"""Fuzzing the doors of untrusted files: rule packages (.rpk) and lot files, 2 000 inputs per
door per run, each in a forked child capped at 10 s of CPU and 2 GiB (tests/fuzz/fuzz_sandbox.py).
Every input must end in a result or one of the project's own errors (a ShapegenError), never in
another exception, past the caps, hung, or with a file written outside where the door may write.

Inputs (tests/fuzz/hostile_files.py): byte corruptions and truncations of the corpus packages,
headers that lie about sizes, counts and names (their checksums made right), path escapes,
absolute paths, symbolic links, folders thousands deep, tens of thousands of members, a bomb of
640 MiB packed in 100 kB; lots with NaN or infinite corners, self-crossing rings, rings of
200 000 corners, JSON a million levels deep, a gzip bomb, truncated gzip, wrong or absurd
coordinate systems, mutated JSON, OSM XML with bad positions and entity expansion.

The seed is printed (and named in a failure); ``SHAPEGEN_FUZZ_SEED=N`` replays a run. One input
replays with ``python tests/fuzz/test_fuzz_hostile.py package SEED NUMBER`` (or ``lots``); a
campaign of any size prints its figures: ``python tests/fuzz/test_fuzz_hostile.py 2000 SEED``
(``... 500 SEED lots 1500``: one door from a given number, to run parts in parallel).
"""

from __future__ import annotations

import sys

import pytest
from fuzz_sandbox import CPU_SECONDS, MEMORY_BYTES, fuzz_seed, print_figures, run_campaign
from hostile_files import (
    bomb_package,
    corpus_packages,
    gzip_bomb,
    hostile_lots,
    hostile_package,
    run_lots,
    run_package,
)

DOORS = {"package": (hostile_package, run_package), "lots": (hostile_lots, run_lots)}
INPUTS_PER_DOOR = 2000


def _warm_up() -> None:
    """Make the shared inputs and import the readers once, before the children fork."""
    import importlib

    for name in ("shapegen.city.outputs", "shapegen.city.parquet", "shapegen.engine.grammar_api",
                 "shapegen.readers.lot_sources", "shapegen.readers.osm", "shapely", "pyproj",
                 "py7zr", "pyarrow", "pyarrow.parquet"):  # fmt: skip
        try:
            importlib.import_module(name)
        except ImportError:
            pass
    import shapegen

    shapegen.parse_grammar("@StartRule\nLot --> extrude(1)\n")  # the parser's tables

    corpus_packages()
    bomb_package()
    gzip_bomb()


def campaign(door: str, seed: int, count: int, *, start: int = 0, progress: bool = False) -> dict:
    """Run ``count`` inputs of one door; return the figures and the failures."""
    _warm_up()
    make, target = DOORS[door]

    def inputs():
        for number in range(start, start + count):
            kind, data = make(seed, number)
            yield f"{door} {seed} {number} ({kind})", target, data

    return run_campaign(inputs(), progress=progress, every=250)


@pytest.mark.slow
@pytest.mark.parametrize("door", sorted(DOORS))
def test_hostile_files_fuzz(door):
    seed = fuzz_seed()
    print(f"fuzz seed {seed}: replay with SHAPEGEN_FUZZ_SEED={seed}", flush=True)
    figures = campaign(door, seed, INPUTS_PER_DOOR)
    shown = "\n".join(figures["failures"][:10])
    assert not figures["failures"], (
        f"seed {seed}: {len(figures['failures'])} of {figures['inputs']} inputs failed:\n{shown}"
    )
    assert figures["slowest_cpu_s"][0] <= CPU_SECONDS, f"seed {seed}"
    assert figures["peak_mib"][0] * 2**20 <= MEMORY_BYTES, f"seed {seed}"


def _main(argv: list[str]) -> None:
    if len(argv) == 3 and argv[0] in DOORS:  # replay one input
        make, target = DOORS[argv[0]]
        kind, data = make(int(argv[1]), int(argv[2]))
        print(f"{kind}: {len(data)} bytes")
        target(data)
        return
    count = int(argv[0]) if argv else INPUTS_PER_DOOR
    seed = int(argv[1]) if len(argv) > 1 else fuzz_seed()
    doors = [argv[2]] if len(argv) > 2 else sorted(DOORS)
    start = int(argv[3]) if len(argv) > 3 else 0
    print(f"fuzz seed {seed}", flush=True)
    for door in doors:
        figures = campaign(door, seed, count, start=start, progress=True)
        print(f"[{door}]")
        print_figures(figures)


if __name__ == "__main__":
    _main(sys.argv[1:])
