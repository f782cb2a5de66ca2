"""Fuzzing the boundary for numbers: random ``.cga`` rules whose operations take extreme numbers
(1e308, -1e308, NaN as 0/0, 1e-320, inf as 1e308 * 10, huge counts), each built through the
command line (``build -o x.json --report --analyze``, then ``-o x.glb``) in a forked child capped
at 20 s of CPU and 4 GiB; each build (deriving, judging and writing: the command's one clock)
under the work limit ``max_seconds = 6``, so that both builds fit in the child's CPU seconds.

Every input must end in exit status 0 with outputs whose numbers are all finite, or in exit
status 2 with no output file at all; never in a traceback, past the caps or hung. Every input
comes from its number and the campaign's seed, which is printed. The slow lane runs 300 inputs
(``SHAPEGEN_FUZZ_SEED=N`` replays a run); the campaigns run and what they found are in
docs/journal/performance.md ("Bounded work"), their reproducers in test_number_reproducers.py.
``python tests/fuzz/test_fuzz_numbers.py 2000 SEED [START]`` runs a campaign,
``python tests/fuzz/test_fuzz_numbers.py replay SEED NUMBER`` prints and runs one input.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import random
import sys
import tempfile
from pathlib import Path

import pytest
from fuzz_sandbox import fuzz_seed, print_figures, run_campaign
from json_numbers import json_numbers as _numbers

CPU_SECONDS = 20
BUILD_SECONDS = 6  # each of a child's two builds, whole: both within its CPU_SECONDS
MEMORY_BYTES = 4 * 2**30
SLOW_LANE_INPUTS = 300

NUMBERS = [
    "1e308", "-1e308", "(0/0)", "1e-320", "-1e-320", "(1e308 * 10)", "(-1e308 * 10)", "1e18",
    "1e9", "-1e9", "1e6", "0", "-0", "1", "10", "0.5", "89.9999999999", "90", "-90", "1e300",
    "5e-324", "4096", "2", "3",
]  # fmt: skip
COUNTS = ["3", "4", "16", "64", "300", "4096", "1e9", "0", "-1", "2.5", "1e308", "(0/0)"]

OPERATIONS = [
    "extrude({n})", "t({n}, {n}, {n})", "t('{n}, 0, 0)", "s({n}, {n}, {n})",
    "s('{n}, '{n}, '{n})", "r({n}, {n}, {n})", "center(xyz)", "translate(rel, world, {n}, 0, {n})",
    "rotate(rel, scope, {n}, 0, 0)", "rotateScope(0, {n}, 0)", "mirror(true, false, false)",
    "alignScopeToAxes(y)", "alignScopeToGeometryBBox()", "split(x) {{ {n} : A | ~{n} : B }}",
    "split(y) {{ ~{n} : A }}*", "split(z) {{ '{n} : B }}*", "comp(f) {{ side : A | top : B }}",
    "comp(f) {{ all : B }}", "roofHip({n})", "roofGable({n})", "roofPyramid({n})",
    "roofShed({n})", "setback({n}) {{ front : A | remainder : B }}", "offset({n})",
    "offset({n}, inside)", "taper({n})", "innerRectangle(scope) {{ shape : A | remainder : B }}",
    "primitiveCylinder({c})", "primitiveCylinder({c}, {n}, {n})", "primitiveSphere({c}, {c})",
    "primitiveSphere({c}, {c}, {n})", "primitiveDisk({c})", "primitiveCone({c}, {n}, {n})",
    "primitiveCube({n}, {n}, {n})", "primitiveQuad({n}, {n})", 'i("builtin:cube")',
    "set(scope.sx, {n})", "set(scope.ty, {n})", "trim()", "convexify()", "reverseNormals()",
    "splitArea(x) {{ {n} : A | ~{n} : B }}*", "shapeL({n}, {n}) {{ shape : A | remainder : B }}",
    "extrude(world.y, {n})", "cleanupGeometry(all, {n})",
]  # fmt: skip


def fuzz_rule(seed: int, number: int) -> str:
    """The ``.cga`` text of input ``number`` of the campaign ``seed``."""
    draw = random.Random(f"{seed}/{number}")

    def operation() -> str:
        template = draw.choice(OPERATIONS)
        return template.format_map(_Draws(draw))

    rules = []
    for name, successors in (("Lot", "A B"), ("A", "B"), ("B", "")):
        ops = " ".join(operation() for _ in range(draw.randint(1, 4)))
        tail = draw.choice(successors.split()) if successors and draw.random() < 0.7 else ""
        rules.append(f"{name} --> {ops} {tail}".rstrip())
    return "\n".join(rules) + "\n"


class _Draws(dict):
    """``{n}``: an extreme number, ``{c}``: a count, each drawn anew where it appears."""

    def __init__(self, draw: random.Random):
        super().__init__()
        self.draw = draw

    def __missing__(self, key: str) -> str:
        return self.draw.choice(NUMBERS if key == "n" else COUNTS)


def build_through_the_command_line(text: str) -> None:
    """What a child does with one input: the two builds, then the checks of their outputs."""
    from shapegen.cli import main
    from shapegen.limits import work_limits

    # a build stops itself past max_seconds (one line, exit status 2): below the CPU cap
    with tempfile.TemporaryDirectory() as folder, work_limits(max_seconds=BUILD_SECONDS):
        place = Path(folder)
        rule = place / "fuzz.cga"
        rule.write_text(text)
        runs = [
            ["-o", str(place / "x.json"), "--report", str(place / "r.json"), "--analyze"],
            ["-o", str(place / "x.glb")],
        ]
        for extra in runs:
            for old in place.iterdir():
                if old != rule:
                    old.unlink()
            errors = io.StringIO()
            with contextlib.redirect_stderr(errors), contextlib.redirect_stdout(io.StringIO()):
                status = main(["build", str(rule), *extra])
            printed = errors.getvalue()
            assert "Traceback" not in printed, printed
            left = sorted(p.name for p in place.iterdir() if p != rule)
            if status == 2:
                assert left == [], f"exit status 2 but {left} written: {printed}"
                assert printed.startswith("shapegen: error:"), printed
                continue
            assert status == 0, f"exit status {status}: {printed}"
            stray = [line for line in printed.splitlines() if "warning" in line]
            assert not stray, f"warnings on stderr: {stray}"
            for name in ("x.json", "r.json"):
                if name in left:
                    document = json.loads((place / name).read_text())
                    assert all(math.isfinite(x) for x in _numbers(document)), name


def campaign(seed: int, count: int, *, start: int = 0, progress: bool = False) -> dict:
    """Run ``count`` inputs of campaign ``seed`` from number ``start``; the figures and the
    failures."""
    from fuzz_inputs import warm_up

    warm_up()
    inputs = (
        (f"seed {seed} input {number}", build_through_the_command_line, fuzz_rule(seed, number))
        for number in range(start, start + count)
    )
    figures = run_campaign(
        inputs, cpu_seconds=CPU_SECONDS, memory_bytes=MEMORY_BYTES, progress=progress
    )
    return {"seed": seed, **figures}


@pytest.mark.slow
def test_extreme_numbers_end_cleanly():
    seed = fuzz_seed()
    print(f"numbers fuzz seed {seed}: replay with SHAPEGEN_FUZZ_SEED={seed}", flush=True)
    figures = campaign(seed, SLOW_LANE_INPUTS)
    print(figures)
    shown = "\n".join(figures["failures"][:10])
    assert not figures["failures"], (
        f"seed {seed}: {len(figures['failures'])} of {figures['inputs']} inputs failed:\n{shown}"
    )
    assert figures["slowest_cpu_s"][0] <= CPU_SECONDS, f"seed {seed}"
    assert figures["peak_mib"][0] * 2**20 <= MEMORY_BYTES, f"seed {seed}"


def test_the_generator_makes_extreme_rules():
    # the inputs are what the fuzz claims: extreme numbers in CityEngine operations
    texts = [fuzz_rule(7, n) for n in range(200)]
    assert texts == [fuzz_rule(7, n) for n in range(200)]  # replayable from the numbers
    joined = "".join(texts)
    for number in ("1e308", "(0/0)", "1e-320", "(1e308 * 10)"):
        assert number in joined
    assert all(text.startswith("Lot --> ") for text in texts)


def _main(argv: list[str]) -> None:
    if argv and argv[0] == "replay":
        text = fuzz_rule(int(argv[1]), int(argv[2]))
        print(text)
        build_through_the_command_line(text)
        return
    count = int(argv[0]) if argv else 2000
    seed = int(argv[1]) if len(argv) > 1 else fuzz_seed()
    start = int(argv[2]) if len(argv) > 2 else 0
    print(f"numbers fuzz seed {seed}", flush=True)
    print_figures(campaign(seed, count, start=start, progress=True))


if __name__ == "__main__":
    _main(sys.argv[1:])
