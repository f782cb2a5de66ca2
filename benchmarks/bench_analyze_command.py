"""The whole ``shapegen analyze MODEL.json`` command on running-bond walls, as a user runs it.

Three walls of ``benchmarks/walls.py`` (about 1 980, 10 000 and 100 000 bricks) are written in
two ways: vertices only (each block a list of its 8 corners and no faces, as compas_cra or
another program writes a block model; shapegen finds each block's faces) and in shapegen's own
format (``write_blocks_json``: the faces are given). Each file is judged by ``shapegen analyze``
in a child process; the figures are that child's CPU seconds (user + system, from
``resource.getrusage(RUSAGE_CHILDREN)`` before and after), its wall-clock seconds and its peak
resident memory (``os.wait4``, this child alone). A second child splits one run into its phases:
the imports the command needs, reading the file, and the analysis (contacts, assembly, solve).

compas_cra's figure beside them is its CPU time on the same 2 001-brick wall (contacts + RBE
solve, ``benchmarks/bench_peer_cra.py``; 58.7 s measured on the quiet machine, 64.8 s in the
goal's measurement); give ``--peer-python`` (a Python with compas_cra installed, see
``bench_peer_cra.py``) to measure it again here.

Run: ``.venv/bin/python benchmarks/bench_analyze_command.py [--sizes 1980 10000 100000]
[--formats vertices shapegen] [--repeat 2] [--peer-python /tmp/cra/bin/python]``
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_peer_cra import peer_measure  # noqa: E402
from benchmarks.processes import user_environment  # noqa: E402
from benchmarks.walls import running_bond_wall  # noqa: E402

PEER_CPU_S = 64.8
"""compas_cra's CPU seconds for the ~2 000-block wall (contacts + RBE), the goal's figure."""
PEER_BLOCKS = 1980

_PHASES = """
import json, sys, time
start = time.process_time()
from shapegen.cli import analyze as _cli
from shapegen.readers.models import read_model
from shapegen.structures import Design, make_structure
import shapegen.statics.contacts, shapegen.statics.solvers.reduced  # noqa
from shapegen.limits import work_limits
from shapegen.statics.statics_options import StaticsOptions
imported = time.process_time()
with work_limits(max_blocks=10**7, max_file_bytes=2**34):
    model = read_model(sys.argv[1])
read = time.process_time()
options = StaticsOptions(pyramid=sys.argv[2]) if len(sys.argv) > 2 else None
structure = make_structure(None, options)
assessment = structure.assess(Design.of_model(model))
done = time.process_time()
print(json.dumps({"imports": imported - start, "reading": read - imported,
                  "analysis": done - read, "stands": bool(assessment.to_report()["feasible"])}))
"""


def write_walls(folder: Path, sizes: list[int], formats: list[str]) -> list[tuple]:
    """The wall files: ``(size, blocks, format, path)`` each."""
    from shapegen.export.blocks_json import model_to_dict

    files = []
    for size in sizes:
        model = running_bond_wall(size)
        document = model_to_dict(model)
        for name in formats:
            path = folder / f"wall{size}-{name}.json"
            if name == "vertices":
                entries = [{"id": b.id, "vertices": b.vertices.tolist()} for b in model.blocks]
                path.write_text(
                    json.dumps({"format": "shapegen-blocks", "version": 1, "blocks": entries})
                )
            else:
                path.write_text(json.dumps(document, indent=1))
            files.append((size, len(model.blocks), name, path))
    return files


def run_child(command: list[str]) -> dict:
    """Run ``command``; its CPU seconds, wall seconds, peak RSS (MiB), exit status, output."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        child = subprocess.Popen(command, stdout=out, stderr=err, cwd=ROOT, env=user_environment())
        _, status, usage = os.wait4(child.pid, 0)
        child.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        out.seek(0)
        err.seek(0)
        output, errors = out.read(), err.read()
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {
        "cpu": cpu,
        "wall": wall,
        "peak_mib": usage.ru_maxrss / 1024,
        "status": child.returncode,
        "stdout": output,
        "stderr": errors,
    }


def peer_cpu(python: str, blocks: int) -> float | None:
    """compas_cra's CPU seconds on the same wall, through bench_peer_cra's peer side."""
    model = running_bond_wall(blocks)
    boxes = [
        (b.vertices.min(axis=0).tolist(), b.vertices.max(axis=0).tolist()) for b in model.blocks
    ]
    peer, _ = peer_measure(python, {"boxes": boxes, "tilt": 0.0, "friction": 0.7})
    return None if peer is None else peer["cpu"]


def _shown(phases: dict, key: str) -> str:
    return f"{phases[key]:7.2f}" if key in phases else f"{'-':>7s}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1980, 10000, 100000])
    parser.add_argument(
        "--formats", nargs="+", default=["vertices", "shapegen"], choices=["vertices", "shapegen"]
    )
    parser.add_argument("--repeat", type=int, default=1, help="runs of each command (best kept)")
    parser.add_argument("--no-phases", action="store_true", help="skip the phase split")
    parser.add_argument("--pyramid", help="friction model given to analyze (default: its own)")
    parser.add_argument("--peer-python", help="a Python with compas_cra, to measure it here")
    parser.add_argument("--keep", help="write the wall files to this folder and keep them")
    args = parser.parse_args()

    python = sys.executable
    peer = PEER_CPU_S
    if args.peer_python:
        measured = peer_cpu(args.peer_python, PEER_BLOCKS)
        if measured is not None:
            peer = measured
    print(
        f"# {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC, load"
        f" {os.getloadavg()[0]:.1f}; compas_cra on the ~{PEER_BLOCKS}-block wall: {peer:.1f} s"
        f" CPU ({'measured now' if args.peer_python and peer != PEER_CPU_S else 'goal figure'});"
        f" friction model: {args.pyramid or 'the default'}"
    )
    print(
        f"{'blocks':>7s} {'format':9s} | {'CPU s':>7s} {'wall s':>7s} {'peak MiB':>8s}"
        f" {'verdict':7s}"
        f" | {'imports':>7s} {'reading':>7s} {'analysis':>8s} | vs compas_cra"
    )
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(args.keep) if args.keep else Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        for size, blocks, name, path in write_walls(folder, args.sizes, args.formats):
            command = [python, "-m", "shapegen", "analyze", str(path), "-q"]
            report = folder / f"report-{size}-{name}.json"
            command += ["--max-blocks", str(max(blocks, 50_000)), "--report", str(report)]
            friction = ["--pyramid", args.pyramid] if args.pyramid else []
            runs = [run_child(command + friction) for _ in range(args.repeat)]
            best = min(runs, key=lambda r: r["cpu"])
            if best["status"] != 0:
                print(f"{blocks:7d} {name:9s} | failed: {best['stderr'].strip()[-300:]}")
                continue
            stands = json.loads(report.read_text())["feasible"]
            phases = {}
            if not args.no_phases:
                split = run_child([python, "-c", _PHASES, str(path), *friction[1:]])
                lines = [x for x in split["stdout"].splitlines() if x.startswith("{")]
                phases = json.loads(lines[-1]) if lines else {}
            ratio = peer / best["cpu"] if blocks <= 2 * PEER_BLOCKS else None

            print(
                f"{blocks:7d} {name:9s} | {best['cpu']:7.2f} {best['wall']:7.2f}"
                f" {best['peak_mib']:8.0f} {'stands' if stands else 'fails':7s}"
                f" | {_shown(phases, 'imports')} {_shown(phases, 'reading')}"
                f" {_shown(phases, 'analysis'):>8s}" + (f" | {ratio:.0f}x" if ratio else " |"),
                flush=True,
            )


if __name__ == "__main__":
    main()
