"""The parameter search of every bundled block rule, as ``shapegen build RULE --optimize`` runs it.

Each rule file is run as the whole command, in a child process (``python -m shapegen build
rules/RULE --optimize``, its own ``@Free`` attrs and the default 10 % reserve), and the child's
CPU seconds (user + system, from the operating system's accounting of the finished process:
imports, reading, the search, the printout), wall seconds and peak memory are printed beside the
search's own figures read from its printout (iterations, evaluations). Each rule runs ``--runs``
times and the least CPU is printed (the machine is shared: the least is the one least disturbed).

    .venv/bin/python benchmarks/bench_search.py
    .venv/bin/python benchmarks/bench_search.py --only cluny --runs 5
    .venv/bin/python benchmarks/bench_search.py --pyramid 4      # the papers' friction pyramid

Rule files are found in ``rules/``; the suspension bridge (a cable model, no block search) is
left out. The goal for Cluny is under 3 CPU seconds for the whole command.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RULES = ROOT / "rules"
SKIP = {"suspension_bridge"}  # a cable model: no block search
SEARCH_LINE = re.compile(r"(\w+),\s+(\d+)\s+iterations?,\s+(\d+)\s+evaluations?")


def run_once(rule: Path, extra: list[str]) -> dict:
    """One whole command in a child: CPU, wall, peak memory and the search's figures."""
    command = [sys.executable, "-m", "shapegen", "build", str(rule), "--optimize", *extra]
    start = time.perf_counter()
    child = subprocess.Popen(
        command, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        env={**os.environ, "COLUMNS": "200"},
    )  # fmt: skip
    output = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - start
    output = " ".join(output.split())  # the printout wraps its lines
    found = SEARCH_LINE.search(output)
    return {
        "cpu": usage.ru_utime + usage.ru_stime,
        "wall": wall,
        "peak_mib": usage.ru_maxrss / 1024,
        "iterations": int(found.group(2)) if found else None,
        "evaluations": int(found.group(3)) if found else None,
        # the search found a design that stands with the reserve (or the start already did)
        "stands": "stands was found" in output or "already stands" in output,
        "ok": child.returncode == 0,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", help="rule names, separated by commas (default: every one)")
    parser.add_argument("--runs", type=int, default=3, help="runs per rule (the least is kept)")
    parser.add_argument("--pyramid", help="friction model passed to the command (--pyramid)")
    args = parser.parse_args()
    names = sorted(p.stem for p in RULES.glob("*.grammar") if p.stem not in SKIP)
    if args.only:
        names = [n for n in names if n in args.only.split(",")]
    extra = ["--pyramid", args.pyramid] if args.pyramid else []
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; {time.strftime('%F %T')}")
    print(f"{'rule':16s} {'iter':>4s} {'eval':>4s} {'CPU s':>7s} {'wall s':>7s} {'MiB':>6s} found")
    for name in names:
        runs = [run_once(RULES / f"{name}.grammar", extra) for _ in range(max(args.runs, 1))]
        best = min(runs, key=lambda r: r["cpu"])
        print(
            f"{name:16s} {best['iterations'] or '-':>4} {best['evaluations'] or '-':>4} "
            f"{best['cpu']:7.2f} {best['wall']:7.2f} {best['peak_mib']:6.0f} "
            f"{'yes' if best['stands'] else 'no'}{'' if best['ok'] else ' (failed)'}",
            flush=True,
        )


if __name__ == "__main__":
    main()
