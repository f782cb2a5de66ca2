"""The ``shapegen`` command: ``analyze``, ``build``, ``rules``.

A user's mistake (a bad file, a bad option value, a grammar error) ends with exit status 2 and one
line ``shapegen: error: <message>`` on stderr (grammar errors add their source excerpt); nothing
is written then. Whether a model stands is a result, not an error: ``analyze`` exits 0 either way.
Every command computes all of its outputs before writing any of them, and each file is written
atomically.
"""

from __future__ import annotations

__all__ = ["main", "build_parser", "CommandLineError"]

import argparse
import difflib
import json
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path

from shapegen import __version__
from shapegen.errors import InputFormatError, ShapegenError

EXIT_OK = 0
EXIT_USAGE = 2


class CommandLineError(ShapegenError):
    """A bad command line: unknown option, bad option value, missing argument."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors raised as exceptions instead of usage dumps and exits."""

    def error(self, message: str):  # argparse calls this for every usage error
        raise CommandLineError(message)


# ------------------------------------------------------------------------------ option values
def _finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def _nonnegative(text: str) -> float:
    value = _finite(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def _kern(text: str) -> float:
    value = _finite(text)
    if not 0 < value <= 1:
        raise argparse.ArgumentTypeError(f"must be in (0, 1], got {text}")
    return value


def _lot(text: str) -> tuple[float, float]:
    parts = text.split(",")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected WIDTH,DEPTH in metres, got {text!r}")
    width, depth = (_finite(p.strip()) for p in parts)
    if width <= 0 or depth <= 0:
        raise argparse.ArgumentTypeError(f"lot sides must be > 0 m, got {text!r}")
    return width, depth


def _assignment(text: str) -> tuple[str, object]:
    name, sep, raw = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name, _attr_value(raw.strip(), name)


def _attr_value(raw: str, name: str) -> object:
    """A ``--set`` value: a number, true/false, or else a string (quotes optional)."""
    lowered = raw.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        number = int(raw)
    except ValueError:
        try:
            number = float(raw)
        except ValueError:
            if len(raw) >= 2 and raw[0] == raw[-1] and raw[0] in "\"'":
                return raw[1:-1]
            return raw
    if not math.isfinite(number):
        raise argparse.ArgumentTypeError(f"{name}: expected a finite number, got {raw!r}")
    return number


# ------------------------------------------------------------------------------ parser
def build_parser() -> argparse.ArgumentParser:
    """The ``shapegen`` argument parser (subcommands ``analyze``, ``build``, ``rules``)."""
    parser = _Parser(
        prog="shapegen",
        description=(
            "Procedural modeling of structures that stand up: build block models from .grammar"
            " rules and check that they stand (compression-only, frictional rigid-block statics)."
        ),
    )
    parser.add_argument("--version", action="version", version=f"shapegen {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    commands.required = True

    analyze = commands.add_parser(
        "analyze",
        help="check whether a block model stands",
        description=(
            "Check whether a block model stands under its own weight and its loads, with"
            " compression-only frictional joints (the tension-penalty QP). Exits 0 whether or not"
            " it stands; exits 2 for bad input."
        ),
    )
    analyze.add_argument(
        "model",
        metavar="MODEL",
        help="block model: shapegen-blocks .json, or a mesh (.obj .gltf .glb .ply .stl)",
    )
    _add_statics_options(analyze)
    analyze.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write the model coloured by tension with resultant arrows (.glb .gltf; or any"
        " model format: .json .obj .ply .stl)",
    )
    analyze.add_argument("--report", metavar="R.json", help="write a JSON report")
    analyze.add_argument("-q", "--quiet", action="store_true", help="print nothing")
    analyze.set_defaults(handler=_run_analyze)

    build = commands.add_parser(
        "build",
        help="derive a block model from a .grammar file",
        description=(
            "Derive a block model from a .grammar file. A bare file name that is not in the"
            " working directory is looked up among the bundled rules (see `shapegen rules`)."
        ),
    )
    build.add_argument(
        "grammar", metavar="FILE.grammar", help="rule file, or the name of a bundled one"
    )
    _add_derivation_options(build)
    build.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write the model: .json (shapegen-blocks), .glb/.gltf, .obj, .ply, .stl",
    )
    build.add_argument("--report", metavar="R.json", help="write a JSON report")
    build.add_argument(
        "--analyze",
        action="store_true",
        help='also check whether the model stands (the report gets an "analysis" object)',
    )
    _add_statics_options(build, prefix="with --analyze or --optimize: ")
    _add_search_options(build)
    build.add_argument(
        "--osm",
        metavar="FILE.osm",
        help="place a bridge on an OpenStreetMap way (OSM XML), with --way: its straight length"
        " sets the attr length, its first and last nodes the position and direction",
    )
    build.add_argument("--way", type=int, metavar="ID", help="with --osm: the way's id")
    build.add_argument("-q", "--quiet", action="store_true", help="print nothing")
    build.set_defaults(handler=_run_build)

    landscape = commands.add_parser(
        "landscape",
        help="plot the infeasibility over two free parameters",
        description=(
            "Evaluate the infeasibility y/W^2 on a grid over the @Range of two attrs, mark the"
            " region where the model stands, draw the optimizer's path, and write a PNG."
        ),
    )
    landscape.add_argument(
        "grammar", metavar="FILE.grammar", help="rule file, or the name of a bundled one"
    )
    landscape.add_argument("first", metavar="P1", help="attr on the horizontal axis")
    landscape.add_argument("second", metavar="P2", help="attr on the vertical axis")
    landscape.add_argument(
        "--grid", type=int, default=15, metavar="N", help="points per axis (default 15)"
    )
    _add_derivation_options(landscape)
    landscape.add_argument(
        "--no-path", action="store_true", help="do not run and draw the optimizer"
    )
    landscape.add_argument(
        "-o", "--output", metavar="OUT.png", required=True, help="the picture to write (.png)"
    )
    _add_statics_options(landscape)
    landscape.add_argument("-q", "--quiet", action="store_true", help="print nothing")
    landscape.set_defaults(handler=_run_landscape)

    rules = commands.add_parser(
        "rules",
        help="list the bundled rule files",
        description="List the bundled .grammar files with the first comment line of each.",
    )
    rules.set_defaults(handler=_run_rules)
    _add_simulate_command(commands)
    return parser


def _add_statics_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    parser.add_argument(
        "--friction",
        type=_nonnegative,
        metavar="MU",
        help=prefix + "friction coefficient of every joint (default: the model's, 0.7)",
    )
    parser.add_argument(
        "--pyramid",
        choices=["4", "4r", "8"],
        default="4",
        help=prefix + "friction pyramid: 4 sides, 4 rotated 45 degrees, or 8 sides (default 4)",
    )
    parser.add_argument(
        "--kern",
        type=_kern,
        default=1.0,
        metavar="K",
        help=prefix + "scale every joint about its centroid by K, a geometric factor of safety"
        " (1 = none, 1/3 = middle third; default 1)",
    )
    parser.add_argument(
        "--solver",
        choices=["auto", "reduced", "clarabel", "cvxpy"],
        default="auto",
        help=prefix + "QP back-end (default auto)",
    )


def _add_derivation_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """--set, --lot and --seed: how a .grammar is derived."""
    parser.add_argument(
        "--set",
        dest="assignments",
        metavar="NAME=VALUE",
        action="append",
        type=_assignment,
        default=[],
        help=prefix + "override an attr (a number, true/false, or a string); repeatable",
    )
    parser.add_argument(
        "--lot",
        type=_lot,
        metavar="W,D",
        help=prefix + "lot width (x) and depth (z) in metres, instead of the grammar's @Lot",
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=0,
        metavar="N",
        help=prefix + "seed of rand() and stochastic rules (default 0)",
    )


def _add_search_options(parser: argparse.ArgumentParser, margin: float = 0.0) -> None:
    """The --optimize options; ``margin`` is the default --margin (simulate keeps a reserve)."""
    parser.add_argument(
        "--optimize",
        action="store_true",
        help="tune the free parameters (@Free attrs, or --free) until the model stands",
    )
    parser.add_argument(
        "--free",
        type=_names,
        metavar="A,B",
        help="with --optimize: the attrs to tune (each needs a @Range) instead of the @Free ones",
    )
    parser.add_argument(
        "--fix",
        dest="fixed",
        metavar="NAME=VALUE",
        action="append",
        type=_assignment,
        default=[],
        help="with --optimize: hold a @Free attr at a value; repeatable",
    )
    parser.add_argument(
        "--objective",
        choices=["energy", "closest"],
        default="energy",
        help="with --optimize: 'energy' minimises the tension and stops at the first design that"
        " stands (the paper); 'closest' finds the standing design nearest to the given values"
        " (default energy)",
    )
    parser.add_argument(
        "--gradient",
        choices=["adjoint", "forward"],
        default="adjoint",
        help="with --optimize: 'adjoint' (one QP per gradient) or 'forward' finite differences"
        " (n + 1 QPs; default adjoint)",
    )
    parser.add_argument(
        "--max-iter",
        type=int,
        default=50,
        metavar="N",
        help="with --optimize: SQP iterations per start (default 50)",
    )
    parser.add_argument(
        "--margin",
        type=float,
        default=margin,
        metavar="M",
        help="with --optimize: geometric safety margin, 0 to 1: search for a design that still"
        " stands with every joint shrunk to 1 - M of its size"
        + (
            f" (default {margin:g}: a design on the statics boundary has no reserve for the"
            " simulator's contact compliance; 0 stops on the boundary, as the paper does)"
            if margin
            else " (default 0: stop on the boundary, as the paper does; 0.1 leaves a reserve a"
            " real structure or a simulation needs)"
        ),
    )
    parser.add_argument(
        "--multistart",
        type=int,
        default=0,
        metavar="N",
        help="with --optimize: extra random starts within the bounds, seeded by --seed (default 0)",
    )


def _names(text: str) -> list[str]:
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"expected attr names separated by commas, got {text!r}")
    return names


# ------------------------------------------------------------------------------ entry point
def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``shapegen`` command with ``argv`` (default: the process arguments).

    Returns the exit status: 0 on success, 2 for a user's mistake.
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        return args.handler(args)
    except SystemExit as exc:  # --help and --version
        return exc.code if isinstance(exc.code, int) else EXIT_OK
    except ShapegenError as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        return _fail(f"{where}{exc.strerror or exc}")
    except KeyboardInterrupt:
        return 130


def _fail(message: str) -> int:
    sys.stderr.write(f"shapegen: error: {message}\n")
    sys.stderr.flush()
    return EXIT_USAGE


# ------------------------------------------------------------------------------ analyze
def _run_analyze(args: argparse.Namespace) -> int:
    from shapegen.export.model_io import check_output_path, read_model

    _check_outputs(args, check_output_path)
    model = read_model(args.model)
    analysis = _analyze(model, args)
    report = {"model": str(args.model), **_analysis_report(analysis)}
    _write_all(_encoded_outputs(args, model, analysis, report))
    if not args.quiet:
        _print_summary(str(args.model), report)
    return EXIT_OK


def _analyze(model, args: argparse.Namespace):
    from shapegen.statics import analyze

    return analyze(
        model, friction=args.friction, pyramid=args.pyramid, kern=args.kern, solver=args.solver
    )


def _analysis_report(analysis) -> dict:
    report = analysis.to_report()
    # Keys the documented report always has, even if an Analysis leaves one out.
    report.setdefault("seconds", float(sum((analysis.timings or {}).values())))
    return report


# ------------------------------------------------------------------------------ build
def _run_build(args: argparse.Namespace) -> int:
    from shapegen.engine import bridge_rules
    from shapegen.export import osm
    from shapegen.export.model_io import check_output_path

    _check_outputs(args, check_output_path)
    started = time.perf_counter()
    grammar = _load_grammar(args.grammar)
    attrs = _checked_attrs(grammar, args.assignments)
    way = _osm_way(args, grammar, attrs)
    if way is not None:
        attrs["length"] = osm.require_straight_length(way)
    analysis = optimization = None
    if args.optimize:
        optimization = _optimize(grammar, attrs, args)
        attrs = {**attrs, **optimization.values}
    elif args.free or args.fixed:
        raise CommandLineError("--free and --fix only apply with --optimize")
    model = grammar.build(attrs=attrs, seed=args.seed, lot=args.lot)
    if way is not None:
        model = osm.place_on_way(model, way)
    report = _build_report(model)
    if way is not None:
        report["osm"] = model.metadata["osm"]
    if bridge_rules.is_cable_structure(grammar):  # a @Structure("cable") grammar: cable sizing
        report["bridge"] = bridge_rules.bridge_report(bridge_rules.model_design(model))
    if optimization is not None:
        report["optimization"] = optimization.to_report()
        # Placed on a way, the model has moved: analyse it where it stands (arrows, colours).
        analysis = optimization.analysis if way is None else None
    if args.analyze or optimization is not None:
        if analysis is None:
            analysis = _analyze(model, args)
        report["analysis"] = _analysis_report(analysis)
    report["seconds"] = time.perf_counter() - started
    _write_all(_encoded_outputs(args, model, analysis, report))
    if not args.quiet:
        _print_build_summary(str(args.grammar), report)
    return EXIT_OK


def _osm_way(args: argparse.Namespace, grammar, attrs: dict):
    """The way of ``--osm FILE --way ID`` (None without them), checked against the grammar."""
    if args.osm is None and args.way is None:
        return None
    if args.osm is None or args.way is None:
        raise CommandLineError("--osm and --way go together: --osm FILE.osm --way ID")
    if "length" not in _attr_names(grammar):
        raise CommandLineError(
            f"--osm places a bridge along a way: {args.grammar} has no attr 'length' to set"
        )
    if "length" in attrs:
        raise CommandLineError("--set length conflicts with --osm: the way gives the length")
    from shapegen.export.osm import read_way

    return read_way(args.osm, args.way)


def _optimize(grammar, attrs: dict, args: argparse.Namespace):
    from shapegen.engine.search import optimize

    if args.max_iter < 1:
        raise CommandLineError(f"--max-iter must be at least 1, got {args.max_iter}")
    if args.multistart < 0:
        raise CommandLineError(f"--multistart must be 0 or more, got {args.multistart}")
    if not 0.0 <= args.margin < 1.0:
        raise CommandLineError(f"--margin must be at least 0 and below 1, got {args.margin}")
    fixed = dict(args.fixed)
    with _SearchProgress(quiet=args.quiet) as progress:
        return optimize(
            grammar,
            free=args.free,
            fix=fixed,
            attrs=attrs,
            seed=args.seed,
            lot=args.lot,
            objective=args.objective,
            gradient=args.gradient,
            max_iter=args.max_iter,
            multistart=args.multistart,
            analysis_options=_statics_options(args),
            progress=progress,
            margin=args.margin,
        )


def _statics_options(args: argparse.Namespace) -> dict:
    return {
        "friction": args.friction,
        "pyramid": args.pyramid,
        "kern": args.kern,
        "solver": args.solver,
    }


class _SearchProgress:
    """One line per SQP iteration (iteration, y/W^2, parameters) under a spinner."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.console = None
        self.status = None

    def __enter__(self):
        if not self.quiet:
            from rich.console import Console

            self.console = Console(stderr=True, highlight=False)
            self.status = self.console.status("optimizing: first analysis...")
            self.status.__enter__()
        return self

    def __exit__(self, *exc) -> None:
        if self.status is not None:
            self.status.__exit__(*exc)

    def __call__(self, record) -> None:
        if self.console is None:
            return
        values = "  ".join(f"{k}={v:.4g}" for k, v in record.parameters.items())
        mark = "[green]stands[/green]" if record.feasible else ""
        self.console.print(
            f"iter {record.iteration:3d}  y/W^2 {record.infeasibility:10.3e}  {values}  {mark}"
        )
        self.status.update(f"optimizing: {record.qp_solves} analyses, {record.seconds:.1f} s")


# ------------------------------------------------------------------------------ landscape
def _run_landscape(args: argparse.Namespace) -> int:
    from shapegen.engine.landscape import energy_landscape
    from shapegen.engine.search import optimize
    from shapegen.export.landscape_plot import plot_landscape

    output = Path(args.output)
    if output.suffix.lower() != ".png":
        raise CommandLineError(f"{output}: the landscape is written as a .png picture")
    folder = output.parent if str(output.parent) else Path(".")
    if not folder.is_dir():
        raise InputFormatError(f"{output}: folder {folder} does not exist")
    if not 2 <= args.grid <= 200:
        raise CommandLineError(f"--grid must be between 2 and 200, got {args.grid}")
    grammar = _load_grammar(args.grammar)
    attrs = _checked_attrs(grammar, args.assignments)
    options = _statics_options(args)
    console = None
    if not args.quiet:
        from rich.console import Console

        console = Console(stderr=True, highlight=False)
    path = None
    if not args.no_path:
        result = optimize(
            grammar, free=[args.first, args.second], attrs=attrs, seed=args.seed, lot=args.lot,
            analysis_options=options,
        )  # fmt: skip
        path = result.path
    if console is not None:
        from rich.progress import Progress

        with Progress(console=console, transient=True) as bar:
            task = bar.add_task("landscape", total=args.grid**2)
            landscape = energy_landscape(
                grammar, args.first, args.second, grid=args.grid, attrs=attrs, seed=args.seed,
                lot=args.lot, analysis_options=options,
                progress=lambda done, total: bar.update(task, completed=done),
            )  # fmt: skip
    else:
        landscape = energy_landscape(
            grammar, args.first, args.second, grid=args.grid, attrs=attrs, seed=args.seed,
            lot=args.lot, analysis_options=options,
        )  # fmt: skip
    plot_landscape(landscape, output, path, title=f"{grammar.name}: infeasibility y/W²")
    if console is not None:
        share = landscape.feasible.mean() * 100
        console.print(
            f"wrote {output}: {args.grid}x{args.grid} grid, {share:.0f}% of it stands"
            + (f"; optimizer path of {len(path)} points" if path else "")
        )
    return EXIT_OK


def _load_grammar(name: str):
    from shapegen.engine.grammar_api import load_grammar

    return load_grammar(name)


def _attr_names(grammar) -> list[str]:
    attrs = grammar.attrs
    names = attrs.keys() if isinstance(attrs, dict) else attrs
    return [name if isinstance(name, str) else name.name for name in names]


def _checked_attrs(grammar, assignments: list[tuple[str, object]]) -> dict:
    """The ``--set`` values by name; an unknown name is an error with close suggestions."""
    known = _attr_names(grammar)
    attrs: dict = {}
    for name, value in assignments:
        if name not in known:
            close = difflib.get_close_matches(name, known, n=3)
            hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
            listing = f" (attrs: {', '.join(known)})" if known and not close else ""
            raise CommandLineError(f"--set {name}: the grammar has no attr {name!r}{hint}{listing}")
        attrs[name] = value
    return attrs


def _build_report(model) -> dict:
    metadata = model.metadata or {}
    lot = metadata.get("lot")
    return {
        "grammar": metadata.get("grammar"),
        "seed": metadata.get("seed"),
        "lot": list(lot) if lot is not None else None,
        "blocks": len(model.blocks),
        "volume": model.volume,
        "attrs": dict(metadata.get("attrs", {})),
        "free_parameters": _free_parameters(metadata.get("free_parameters", {})),
        "reports": dict(metadata.get("reports", {})),
    }


def _free_parameters(free) -> dict:
    """name -> {value, min, max}, whatever mapping or sequence form the grammar hands over."""
    out = {}
    items = free.items() if isinstance(free, dict) else ((p.name, p) for p in free)
    for name, parameter in items:
        if isinstance(parameter, dict):
            out[name] = {k: parameter.get(k) for k in ("value", "min", "max")}
        else:
            out[name] = {k: getattr(parameter, k, None) for k in ("value", "min", "max")}
    return out


# ------------------------------------------------------------------------------ simulate
def _add_simulate_command(commands) -> None:
    simulate = commands.add_parser(
        "simulate",
        help="run a model in a rigid-body simulator (pybullet) and see whether it stands",
        description=(
            "Drop a block model into a rigid-body simulator (pybullet, the optional extra"
            " shapegen[sim]): convex blocks with their exact mass and inertia, static supports"
            " and ground, restitution 0. After a settling window the model stands when no block"
            " moves more than the tolerance. MODEL is a .grammar file (built first; a bare name"
            " finds a bundled rule) or a block model (.json or a mesh). Exits 0 whether or not"
            " it stands; exits 2 for bad input."
        ),
    )
    simulate.add_argument(
        "model", metavar="MODEL", help=".grammar file or bundled rule name, or a block model"
    )
    simulate.add_argument(
        "--seconds", type=_positive, default=5.0, metavar="S", help="simulated seconds (default 5)"
    )
    simulate.add_argument(
        "--shake",
        type=_nonnegative,
        default=0.0,
        metavar="V",
        help="ground shake: a lateral velocity change of V m/s over 1/60 s along +x after"
        " settling (the seed paper: 4)",
    )
    simulate.add_argument(
        "--remove",
        metavar="ID|LABEL",
        action="append",
        default=[],
        help="delete the block with this id, or every block with this label, before the run;"
        " repeatable",
    )
    simulate.add_argument(
        "--time-step",
        type=_positive,
        default=None,
        metavar="DT",
        help="simulator step in seconds (default 0.001)",
    )
    simulate.add_argument(
        "--iterations",
        type=int,
        default=None,
        metavar="N",
        help="contact-solver iterations per step (default 100)",
    )
    simulate.add_argument(
        "--tolerance",
        type=_positive,
        default=None,
        metavar="M",
        help="a block moved when a vertex moved more than M metres after settling (default:"
        " 0.001, or 1/10000 of the model's height when that is larger)",
    )
    simulate.add_argument(
        "--fps",
        type=_positive,
        default=10.0,
        metavar="F",
        help="with --frames or -o .gif: frames per simulated second (default 10)",
    )
    pictures = simulate.add_mutually_exclusive_group()
    pictures.add_argument("--frames", metavar="DIR", help="write one PNG per frame into DIR")
    pictures.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write an animation (.gif) or a picture of the final state (.png)",
    )
    simulate.add_argument("--report", metavar="R.json", help="write a JSON report")
    _add_derivation_options(simulate, prefix="for a .grammar: ")
    _add_statics_options(simulate, prefix="with --optimize (and --friction for the run): ")
    # A design to simulate is searched with a safety margin by default.
    from shapegen.simulation.run import SIMULATION_MARGIN

    _add_search_options(simulate, margin=SIMULATION_MARGIN)
    simulate.add_argument("-q", "--quiet", action="store_true", help="print nothing")
    simulate.set_defaults(handler=_run_simulate)


def _positive(text: str) -> float:
    value = _finite(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _run_simulate(args: argparse.Namespace) -> int:
    from shapegen.simulation import SimulationSettings, simulate

    _check_simulate_outputs(args)
    model, build_report = _simulation_model(args)
    overrides = {
        "time_step": args.time_step,
        "solver_iterations": args.iterations,
        "tolerance": args.tolerance,
    }
    settings = SimulationSettings(
        seconds=args.seconds,
        shake=args.shake,
        friction=args.friction,
        frame_rate=args.fps if (args.frames or _is_gif(args.output)) else 0.0,
        **{k: v for k, v in overrides.items() if v is not None},
    )
    with _SimulationProgress(quiet=args.quiet) as progress:
        result = simulate(model, settings, remove=args.remove, progress=progress)
    report = {"model": str(args.model), **build_report, "simulation": result.to_report()}
    outputs = []
    if args.report:
        outputs.append((Path(args.report), _report_bytes(report)))
    if args.output:
        outputs.append((Path(args.output), _simulation_picture(result, args.output)))
    _write_all(outputs)
    if args.frames:
        from shapegen.simulation.frames import write_frames

        write_frames(result, args.frames)
    if not args.quiet:
        _print_simulation_summary(str(args.model), result, args, build_report.get("build", {}))
    return EXIT_OK


def _is_gif(output: str | None) -> bool:
    return bool(output) and Path(output).suffix.lower() == ".gif"


def _check_simulate_outputs(args: argparse.Namespace) -> None:
    from shapegen.simulation.world import load_pybullet

    load_pybullet()  # fail at once, before any building, when the extra is missing
    if args.output:
        output = Path(args.output)
        if output.suffix.lower() not in (".gif", ".png"):
            raise CommandLineError(
                f"{output}: the simulation is written as an animation (.gif) or a picture (.png)"
            )
    for path in (args.output, args.report):
        if path:
            folder = Path(path).parent if str(Path(path).parent) else Path(".")
            if not folder.is_dir():
                raise InputFormatError(f"{path}: folder {folder} does not exist")
    if args.iterations is not None and args.iterations < 1:
        raise CommandLineError(f"--iterations must be at least 1, got {args.iterations}")


def _simulation_model(args: argparse.Namespace):
    """The model to simulate and the build part of the report (empty for a block model)."""
    from shapegen.engine.rules_path import find_bundled_rule

    name = str(args.model)
    is_grammar = name.endswith(".grammar") or (
        not Path(name).exists() and find_bundled_rule(name) is not None
    )
    if not is_grammar:
        if args.assignments or args.optimize or args.lot or args.free or args.fixed:
            raise CommandLineError(
                "--set, --lot, --optimize, --free and --fix apply only to a .grammar MODEL"
            )
        from shapegen.export.model_io import read_model

        return read_model(name), {}
    grammar = _load_grammar(name)
    attrs = _checked_attrs(grammar, args.assignments)
    optimization = None
    if args.optimize:
        optimization = _optimize(grammar, attrs, args)
        attrs = {**attrs, **optimization.values}
    elif args.free or args.fixed:
        raise CommandLineError("--free and --fix only apply with --optimize")
    model = grammar.build(attrs=attrs, seed=args.seed, lot=args.lot)
    report = _build_report(model)
    if optimization is not None:
        report["optimization"] = optimization.to_report()
    return model, {"build": report}


def _simulation_picture(result, output: str) -> bytes:
    import tempfile

    from shapegen.simulation.frames import encode_gif, write_picture

    if _is_gif(output):
        return encode_gif(result)
    with tempfile.TemporaryDirectory(prefix="shapegen-picture-") as folder:
        path = Path(folder) / "final.png"
        write_picture(result, path, "final")
        return path.read_bytes()


class _SimulationProgress:
    """A progress bar over simulated seconds, on stderr."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.bar = None
        self.task = None

    def __enter__(self):
        if not self.quiet:
            from rich.console import Console
            from rich.progress import Progress

            self.bar = Progress(console=Console(stderr=True), transient=True)
            self.bar.__enter__()
            self.task = self.bar.add_task("simulating", total=1.0)
        return self

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.__exit__(*exc)

    def __call__(self, done: float, total: float) -> None:
        if self.bar is not None:
            self.bar.update(self.task, completed=done / total)


def _print_simulation_summary(title: str, result, args: argparse.Namespace, build: dict) -> None:
    from rich.console import Console
    from rich.table import Table
    from rich.text import Text

    table = Table.grid(padding=(0, 2))
    table.add_column(style="bold")
    table.add_column()
    table.add_row("model", Text(title))
    table.add_row("blocks", str(len(result.model.blocks)))
    if "optimization" in build:
        optimization = build["optimization"]
        values = ", ".join(
            f"{name} {_fmt(spec['final'])}" for name, spec in optimization["parameters"].items()
        )
        table.add_row("optimized", Text(f"{optimization['message']}: {values}"))
    if result.removed:
        table.add_row("removed", Text(", ".join(result.removed)))
    stands = result.stands
    table.add_row("verdict", Text(result.verdict, style="green" if stands else "bold red"))
    table.add_row(
        "max displacement",
        f"{result.max_displacement * 1000:.4g} mm after settling"
        f" (tolerance {result.settings.tolerance * 1000:.3g} mm)",
    )
    table.add_row("moved blocks", str(result.moved_blocks))
    table.add_row("settlement", f"{result.settlement * 1000:.4g} mm")
    if result.settings.shake > 0:
        table.add_row("shake", f"{result.settings.shake:g} m/s over 1/60 s")
    table.add_row(
        "seconds",
        f"{result.seconds:.4g} simulated, {result.wall_seconds:.4g} wall"
        f" ({result.speed:.3g} simulated s per wall s)",
    )
    for label, path in (("report", args.report), ("output", args.output), ("frames", args.frames)):
        if path:
            table.add_row(label, Text(str(path)))
    Console(highlight=False).print(table)


# ------------------------------------------------------------------------------ rules
def _run_rules(args: argparse.Namespace) -> int:
    from rich.console import Console
    from rich.table import Table
    from rich.text import Text

    table = Table(box=None, show_header=True, header_style="bold", pad_edge=False)
    table.add_column("rule file")
    table.add_column("description")
    paths = _bundled_rule_paths()
    for path in paths:
        table.add_row(Text(path.name), Text(_first_comment(path)))
    console = Console(highlight=False)
    if paths:
        console.print(table)
    else:
        console.print("no bundled rule files found")
    return EXIT_OK


def _bundled_rule_paths() -> list[Path]:
    from shapegen.engine.rules_path import bundled_rules, find_bundled_rule

    return [find_bundled_rule(name) for name in bundled_rules()]


def _first_comment(path: Path) -> str:
    """The text of the file's first comment line (``#`` or ``//``), or ``""``."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except OSError:
        return ""
    for line in lines:
        stripped = line.strip()
        for marker in ("#", "//", "/*"):
            if stripped.startswith(marker):
                return stripped[len(marker) :].strip(" */")
    return ""


# ------------------------------------------------------------------------------ outputs
def _check_outputs(args: argparse.Namespace, check_output_path) -> None:
    """Fail before any work if an output path cannot be written (bad extension or folder)."""
    if args.output:
        check_output_path(args.output)
    if args.report:
        report = Path(args.report)
        folder = report.parent if str(report.parent) else Path(".")
        if not folder.is_dir():
            raise InputFormatError(f"{report}: folder {folder} does not exist")


def _encoded_outputs(args, model, analysis, report: dict) -> list[tuple[Path, bytes]]:
    """Every requested output file's content, built in memory before anything is written."""
    from shapegen.export.model_io import encode_model

    outputs = []
    if args.output:
        outputs.append((Path(args.output), encode_model(model, args.output, analysis)))
    if args.report:
        outputs.append((Path(args.report), _report_bytes(report)))
    return outputs


def _report_bytes(report: dict) -> bytes:
    text = json.dumps(_json_ready(report), indent=1, allow_nan=False)
    return (text + "\n").encode("utf-8")


def _json_ready(value):
    """Plain JSON values: numpy scalars and arrays unwrapped, non-finite numbers as null."""
    if isinstance(value, dict):
        return {str(k): _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        return _json_ready(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(getattr(value, "value", value))


def _write_all(outputs: list[tuple[Path, bytes]]) -> None:
    from shapegen.export.model_io import write_bytes_atomic

    for path, content in outputs:
        write_bytes_atomic(path, content)


# ------------------------------------------------------------------------------ summaries
def _print_summary(title: str, report: dict) -> None:
    from rich.console import Console

    console = Console(highlight=False)
    console.print(_analysis_table(title, report))


def _analysis_table(title: str, report: dict):
    from rich.table import Table
    from rich.text import Text

    table = Table.grid(padding=(0, 2))
    table.add_column(style="bold")
    table.add_column()
    table.add_row("model", Text(title))
    table.add_row("blocks", str(report.get("blocks")))
    table.add_row("interfaces", str(report.get("interfaces")))
    feasible = bool(report.get("feasible"))
    table.add_row(
        "stands", Text("yes" if feasible else "no", style="green" if feasible else "bold red")
    )
    table.add_row(
        "infeasibility",
        f"{_fmt(report.get('infeasibility'))} N^2"
        f" (normalised {_fmt(report.get('infeasibility_normalized'))})",
    )
    table.add_row("max tension", f"{_fmt(report.get('max_tension'))} N")
    table.add_row("total weight", f"{_fmt(report.get('total_weight'))} N")
    table.add_row("seconds", f"{_fmt(report.get('seconds'))}")
    return table


def _print_build_summary(title: str, report: dict) -> None:
    from rich.console import Console
    from rich.table import Table
    from rich.text import Text

    console = Console(highlight=False)
    table = Table.grid(padding=(0, 2))
    table.add_column(style="bold")
    table.add_column()
    table.add_row("grammar", Text(title))
    table.add_row("blocks", str(report["blocks"]))
    table.add_row("volume", f"{_fmt(report['volume'])} m^3")
    table.add_row("seconds", _fmt(report["seconds"]))
    for name, value in report.get("reports", {}).items():
        table.add_row(Text(f"report {name}"), Text(str(value)))
    console.print(table)
    if "optimization" in report:
        console.print(_optimization_table(report["optimization"]))
    if "analysis" in report:
        console.print(_analysis_table(title, report["analysis"]))


def _optimization_table(optimization: dict):
    from rich.table import Table

    table = Table(title="optimization", title_justify="left")
    for column in ("parameter", "initial", "final", "min", "max"):
        table.add_column(column, justify="left" if column == "parameter" else "right")
    for name, spec in optimization["parameters"].items():
        table.add_row(name, *(_fmt(spec[k]) for k in ("initial", "final", "min", "max")))
    table.caption = (
        f"{optimization['message']}; {optimization['iterations']} iterations,"
        f" {optimization['qp_solves']} analyses, {_fmt(optimization['seconds'])} s"
    )
    return table


def _fmt(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return f"{value:.4g}"
    try:
        return f"{float(value):.4g}"
    except (TypeError, ValueError):
        return str(value)
