"""CGA derivation against CityEngine's runtime: CPU seconds of shapegen and PyPRT side by side.

For every rule package of the shared corpus (``../shared/cga-corpus/packages/*.rpk``) on the
12 x 8 m lot, and parthenon on 30 x 70 m, it times a warm derivation on both sides: the package
loaded and derived once, then the least CPU time (``time.process_time``) of ``--repeat``
derivations with the default attrs and seed 0. shapegen derives in this process
(``load_grammar(rpk).build(lot=...)``); PyPRT runs in a separate virtual environment that the
script makes once (``~/.cache/shapegen/prt-venv``, ``pip install pyprt``; shapegen never imports
it), driven as ``tools/cga_reference.py`` drives it: one ``ModelGenerator`` per package,
``generate_model`` with the PyEncoder and geometry and reports emitted. Where PyPRT cannot be
installed its column says why and shapegen's figures are printed alone.

It also prints shapegen's first derivation (cold: assets read, nothing kept from earlier
builds), the CPU seconds of a whole ``shapegen build`` process for a one-line rule (user +
system of the child, the least of ``--repeat``), and a slider on parthenon's ``Diameter``
(12 x 8 m): each value a new one, so the columns' geometry is new each time.

The machine has other work running: CPU seconds, not wall seconds, are what it measures::

    .venv/bin/python benchmarks/bench_cga.py
    .venv/bin/python benchmarks/bench_cga.py --only parthenon --repeat 5
    .venv/bin/python benchmarks/bench_cga.py --no-prt
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.processes import user_environment  # noqa: E402

# ../shared/cga-corpus of the checkout (a worktree's checkout lies one folder further down)
PACKAGES = next(
    (p / "shared" / "cga-corpus" / "packages" for p in ROOT.parents[:2]
     if (p / "shared" / "cga-corpus").is_dir()),
    ROOT.parent / "shared" / "cga-corpus" / "packages",
)  # fmt: skip
PRT_VENV = Path.home() / ".cache" / "shapegen" / "prt-venv"
ONE_LINE_RULE = "Lot --> extrude(10) Mass.\n"

_PRT_DRIVER = r"""
import json, sys, time
import pyprt

jobs = json.loads(sys.stdin.read())
out = []
for job in jobs:
    w, d = job["lot"]
    lot = [0.0, 0.0, d, w, 0.0, d, w, 0.0, 0.0, 0.0, 0.0, 0.0]
    generator = pyprt.ModelGenerator([pyprt.InitialShape(lot)])
    options = {"emitReport": True, "emitGeometry": True}
    times = []
    vertices = 0
    for _ in range(job["repeat"] + 1):  # the first run reads the package
        start = time.process_time()
        models = generator.generate_model([{}], job["package"], "com.esri.pyprt.PyEncoder", options)
        times.append(time.process_time() - start)
        vertices = len(models[0].get_vertices()) // 3 if models else 0
    out.append({"first": times[0], "warm": min(times[1:]), "vertices": vertices})
print(json.dumps(out))
"""


def prt_python() -> tuple[Path | None, str]:
    """The PyPRT environment's python, made on first use; or None and the reason."""
    python = PRT_VENV / "bin" / "python"
    check = [str(python), "-c", "import pyprt"]
    if python.exists() and subprocess.run(check, capture_output=True).returncode == 0:
        return python, ""
    try:
        subprocess.run([sys.executable, "-m", "venv", str(PRT_VENV)], check=True)
        subprocess.run(
            [str(python), "-m", "pip", "install", "-q", "pyprt"], check=True, capture_output=True
        )
    except (OSError, subprocess.CalledProcessError) as exc:
        return None, f"PyPRT could not be installed ({exc})"
    if subprocess.run(check, capture_output=True).returncode != 0:
        return None, "PyPRT installed but does not import on this machine"
    return python, ""


def prt_times(python: Path, jobs: list[dict]) -> list[dict] | str:
    """PyPRT's first and warm CPU seconds per job, or the reason it could not run."""
    result = subprocess.run(
        [str(python), "-W", "ignore", "-c", _PRT_DRIVER],
        input=json.dumps(jobs),
        capture_output=True,
        text=True,
    )
    if result.returncode != 0:
        return f"PyPRT failed: {result.stderr.strip().splitlines()[-1:]}"
    return json.loads(result.stdout.strip().splitlines()[-1])


def shapegen_times(package: Path, lot: tuple[float, float], repeat: int) -> dict:
    """shapegen's first and warm CPU seconds for one package and lot."""
    from shapegen import load_grammar

    grammar = load_grammar(package)
    with open(os.devnull, "w") as quiet, contextlib.redirect_stdout(quiet):  # rules' print()
        start = time.process_time()
        model = grammar.build(lot=lot)
        first = time.process_time() - start
        warm = []
        for _ in range(repeat):
            start = time.process_time()
            model = grammar.build(lot=lot)
            warm.append(time.process_time() - start)
    return {
        "first": first,
        "warm": min(warm),
        "leaves": model.metadata.get("leaves"),
        "blocks": len(model.blocks),
    }


def slider_times(package: Path, values: list[float]) -> list[float]:
    """CPU seconds of a rebuild of parthenon (12 x 8 m) for each new ``Diameter`` value."""
    from shapegen import load_grammar

    grammar = load_grammar(package)
    grammar.build(lot=(12.0, 8.0))
    out = []
    for value in values:
        start = time.process_time()
        grammar.build({"Diameter": value}, lot=(12.0, 8.0))
        out.append(time.process_time() - start)
    return out


def one_line_process(repeat: int, output: str | None = None) -> float:
    """The least CPU seconds (user + system) of a ``shapegen build`` process for a one-line
    rule on a 12 x 8 m lot, writing the model to a file named ``output`` if given."""
    shapegen = Path(sys.executable).with_name("shapegen")
    with tempfile.TemporaryDirectory() as folder:
        rule = Path(folder) / "one.cga"
        rule.write_text(ONE_LINE_RULE)
        written = ["-o", str(Path(folder) / output)] if output else []
        best = float("inf")
        for _ in range(repeat + 1):  # the first may fill lark's table cache and write bytecode
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run(
                [str(shapegen), "build", str(rule), "--lot", "12,8", *written],
                check=True,
                capture_output=True,
                env=user_environment(),
            )
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            best = min(best, cpu)
    return best


def machine() -> str:
    model = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    return (
        f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"load average {load}, {datetime.datetime.now():%Y-%m-%d %H:%M}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm runs per package (min)")
    parser.add_argument("--only", default="", help="a substring of the package names to run")
    parser.add_argument("--no-prt", action="store_true", help="shapegen's figures alone")
    args = parser.parse_args(argv)

    packages = sorted(p for p in PACKAGES.glob("*.rpk") if args.only in p.name)
    cases = [(p, (12.0, 8.0)) for p in packages]
    cases += [(p, (30.0, 70.0)) for p in packages if "parthenon" in p.name]
    print(machine())
    if not cases:
        print(f"no packages in {PACKAGES}")
        return 1

    python, why = (None, "--no-prt") if args.no_prt else prt_python()
    prt: list[dict] | str = why
    if python is not None:
        jobs = [{"package": str(p), "lot": lot, "repeat": args.repeat} for p, lot in cases]
        prt = prt_times(python, jobs)
    if isinstance(prt, str):
        print(f"PyPRT: {prt}")

    header = f"{'package':52} {'lot':>7} {'PyPRT':>8} {'shapegen':>9} {'ratio':>6} "
    print(header + f"{'first':>7} {'leaves':>6}")
    worst = 0.0
    for k, (package, lot) in enumerate(cases):
        ours = shapegen_times(package, lot, args.repeat)
        name = package.name.removeprefix("Esri+pyprt__").removesuffix(".rpk")
        size = f"{lot[0]:g}x{lot[1]:g}"
        if isinstance(prt, list):
            theirs = prt[k]["warm"]
            ratio = ours["warm"] / max(theirs, 1e-4)  # PyPRT's tiny packages: 0.1 ms floor
            worst = max(worst, ratio)
            cells = f"{theirs:8.4f} {ours['warm']:9.4f} {ratio:6.1f}"
        else:
            cells = f"{'-':>8} {ours['warm']:9.4f} {'-':>6}"
        print(f"{name:52} {size:>7} {cells} {ours['first']:7.3f} {ours['leaves']!s:>6}")
    if isinstance(prt, list):
        print(f"largest ratio shapegen / PyPRT (warm CPU): {worst:.1f}")

    parthenon = [p for p in packages if "parthenon" in p.name]
    if parthenon:
        values = [1.5, 1.6, 1.7, 1.8, 2.0, 2.1, 2.2]
        times = slider_times(parthenon[0], values)
        shown = ", ".join(f"{t:.3f}" for t in times)
        print(f"parthenon 12x8, Diameter slider ({len(values)} new values): CPU s {shown}")
        print(f"  median {sorted(times)[len(times) // 2]:.3f} s, max {max(times):.3f} s")
    for output in (None, "model.glb"):
        cpu = one_line_process(args.repeat, output)
        written = f" -o {output}" if output else ""
        print(f"one-line rule, whole 'shapegen build{written}' process: {cpu:.3f} s CPU (least)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
