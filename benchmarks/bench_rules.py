"""Every bundled rule file with free parameters, built, analysed and optimized end to end.

Prints a table like the seed paper's Table 1 (Whiting, Ochsendorf, Durand 2009): blocks, free
parameters, SQP iterations, evaluations (QP analyses), seconds per iteration, total seconds, and
whether the model stands before and after the search. Rule files are discovered at run time in
``rules/``; a grammar judged by another structure than block statics (the suspension bridge, a
cable model) is skipped.

Parameter sets. Each file is run with its ``@Free`` attrs, and also with every parameter set
documented in its header as a comment line

    # free10: wall_thickness, buttress_width, window_width, ...

(``# freeN:`` followed by comma-separated attr names; N is usually the number of names, so a
file may document ``# free4:`` and ``# free10:``). ``--free-set cluny=a,b,c`` replaces the sets
of ``cluny.grammar`` by that one (repeatable).

    .venv/bin/python benchmarks/bench_rules.py
    .venv/bin/python benchmarks/bench_rules.py --only tower,barrel_vault --pictures out/pictures
    .venv/bin/python benchmarks/bench_rules.py --free-set cluny=wall_thickness,window_width
    .venv/bin/python benchmarks/bench_rules.py --json out/rules.json

The searches stop on the feasibility boundary (``--margin 0``, the paper's setting) unless
``--margin`` says otherwise; ``--margin 0.1`` runs them as ``shapegen build --optimize`` does.

With ``--pictures DIR`` each run writes ``DIR/<file>[-<set>]-before.png`` and ``-after.png``,
blocks shaded by the tension they need (red) in the design's analysis.
"""

from __future__ import annotations

import argparse
import json
import re
import time
import traceback
from dataclasses import asdict, dataclass
from pathlib import Path

import shapegen
from shapegen.errors import ShapegenError
from shapegen.export.picture import render_model
from shapegen.search import optimize
from shapegen.statics import analyze

RULES = Path(__file__).resolve().parent.parent / "rules"
FREE_SET_LINE = re.compile(r"^\s*(?:#|//)\s*(free\d+)\s*:\s*(.+?)\s*$", re.MULTILINE)


@dataclass
class Row:
    """One optimization run: a rule file with one set of free parameters."""

    file: str
    parameter_set: str
    blocks: int = 0
    free: int = 0
    iterations: int = 0
    evaluations: int = 0  # designs analysed: one QP each
    seconds_per_iteration: float = 0.0
    seconds: float = 0.0
    cpu_seconds: float = 0.0  # the search's CPU seconds (the figure to compare on a shared machine)
    analysis_seconds: float = 0.0  # one build + analysis of the file's design
    feasible_before: bool | None = None
    feasible_after: bool | None = None
    message: str = ""


def header_sets(path: Path) -> dict[str, list[str]]:
    """The ``# freeN: a, b, c`` parameter sets documented in a rule file."""
    text = path.read_text(encoding="utf-8")
    return {
        name: [item.strip() for item in items.split(",") if item.strip()]
        for name, items in FREE_SET_LINE.findall(text)
    }


def parameter_sets(
    path: Path, grammar, overrides: dict[str, list[str]]
) -> dict[str, list[str] | None]:
    """The runs for one file: ``set name -> attr names`` (None: the ``@Free`` attrs)."""
    if path.stem in overrides:
        return {"cli": overrides[path.stem]}
    sets: dict[str, list[str] | None] = {}
    if grammar.free_parameters:
        sets["@Free"] = None
    sets.update(header_sets(path))
    return sets


def run(path: Path, set_name: str, free: list[str] | None, args, grammar) -> Row:
    row = Row(path.stem, set_name)
    started = time.perf_counter()
    model = grammar.build()
    before = analyze(model)
    row.analysis_seconds = time.perf_counter() - started
    row.blocks = len(model.blocks)
    row.feasible_before = bool(before.feasible)
    cpu = time.process_time()
    result = optimize(
        grammar, free=free, gradient=args.gradient, max_iter=args.max_iter, margin=args.margin
    )
    row.cpu_seconds = time.process_time() - cpu
    row.free = len(result.parameters)
    row.iterations = result.iterations
    row.evaluations = result.evaluations
    row.seconds = result.seconds
    row.seconds_per_iteration = result.seconds_per_iteration
    row.feasible_after = bool(result.feasible)
    row.message = result.message
    if args.pictures:
        directory = Path(args.pictures)
        directory.mkdir(parents=True, exist_ok=True)
        stem = path.stem if set_name == "@Free" else f"{path.stem}-{set_name}"
        render_model(model, directory / f"{stem}-before.png", before,
                     title=f"{path.stem}: the file's values")  # fmt: skip
        if result.model is not None:
            render_model(result.model, directory / f"{stem}-after.png", result.analysis,
                         title=f"{path.stem}: optimized ({set_name})")  # fmt: skip
    return row


def print_table(rows: list[Row]) -> None:
    header = (
        f"{'file':<18} {'set':<7} {'blocks':>6} {'free':>4} {'iter':>4} {'evals':>5} "
        f"{'s/iter':>7} {'total s':>8} {'cpu s':>7} {'stands before':>13} {'after':>5}"
    )
    print(header)
    print("-" * len(header))
    for r in rows:
        print(
            f"{r.file:<18} {r.parameter_set:<7} {r.blocks:>6} {r.free:>4} {r.iterations:>4} "
            f"{r.evaluations:>5} {r.seconds_per_iteration:>7.2f} {r.seconds:>8.2f} "
            f"{r.cpu_seconds:>7.2f} "
            f"{_yes_no(r.feasible_before):>13} {_yes_no(r.feasible_after):>5}"
        )
    failed = [r for r in rows if r.message and not r.feasible_after]
    for r in failed:
        print(f"  {r.file} ({r.parameter_set}): {r.message}")


def _yes_no(value: bool | None) -> str:
    return "-" if value is None else ("yes" if value else "no")


def parse_overrides(items: list[str]) -> dict[str, list[str]]:
    overrides = {}
    for item in items:
        name, sep, names = item.partition("=")
        if not sep or not names.strip():
            raise SystemExit(f"--free-set expects FILE=a,b,c; got {item!r}")
        overrides[name.strip().removesuffix(".grammar")] = [
            n.strip() for n in names.split(",") if n.strip()
        ]
    return overrides


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rules", default=str(RULES), help="directory of .grammar files")
    parser.add_argument("--only", default="", help="comma-separated file stems to run")
    parser.add_argument("--free-set", action="append", default=[], metavar="FILE=a,b,c")
    parser.add_argument("--pictures", metavar="DIR", help="write before/after PNGs here")
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON")
    parser.add_argument("--gradient", default="adjoint", choices=("adjoint", "forward"))
    parser.add_argument("--max-iter", type=int, default=50)
    parser.add_argument(
        "--margin",
        type=float,
        default=0.0,
        help="the search's reserve (default 0: the feasibility boundary, as the paper's Table 1;"
        " `shapegen build --optimize` uses 0.1 unless told otherwise)",
    )
    args = parser.parse_args(argv)
    overrides = parse_overrides(args.free_set)
    only = {s.strip().removesuffix(".grammar") for s in args.only.split(",") if s.strip()}

    rows: list[Row] = []
    for path in sorted(Path(args.rules).glob("*.grammar")):
        if only and path.stem not in only:
            continue
        try:
            grammar = shapegen.load_grammar(path)
            if grammar.structure != "blocks":  # a cable model: no block QP to count
                continue
            sets = parameter_sets(path, grammar, overrides)
        except ShapegenError as exc:
            rows.append(Row(path.stem, "-", message=f"cannot load: {str(exc).splitlines()[0]}"))
            continue
        for set_name, free in sets.items():
            print(f"{path.name} [{set_name}] ...", flush=True)
            try:
                rows.append(run(path, set_name, free, args, grammar))
            except ShapegenError as exc:
                rows.append(Row(path.stem, set_name, message=str(exc).splitlines()[0]))
            except Exception:  # a benchmark reports a crash and goes on with the next file
                rows.append(Row(path.stem, set_name, message=traceback.format_exc(limit=2)))
    print()
    print_table(rows)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps([asdict(r) for r in rows], indent=2) + "\n")


if __name__ == "__main__":
    main()
