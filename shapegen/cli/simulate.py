"""``shapegen simulate MODEL``: run a model in the rigid-body simulator; does it stand?"""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
from pathlib import Path

from shapegen.cli.common_options import (
    CommandLineError,
    add_derivation_options,
    add_search_options,
    add_statics_options,
    check_statics_apply,
    checked_attrs,
    judges_blocks,
    load_grammar,
    nonnegative,
    positive,
    search_settings,
    statics_options,
)
from shapegen.cli.display import SearchProgress, SimulationProgress, print_simulation
from shapegen.cli.outputs import check_outputs, require_suffix, write_all

HELP = "run a model in a rigid-body simulator (pybullet) and see whether it stands"
DESCRIPTION = (
    "Drop a block model into a rigid-body simulator (pybullet, the optional extra"
    " shapegen[sim]): convex blocks with their exact mass and inertia, static supports"
    " and ground, restitution 0. The model stands when no block moved more than 10% of"
    " its smallest width and none is still moving at the end. MODEL is a .grammar file"
    " (built first; a bare name finds a bundled rule) or a block model (.json or a"
    " mesh). Exits 0 whether or not"
    " it stands; exits 2 for bad input."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    parser.add_argument(
        "model", metavar="MODEL", help=".grammar file or bundled rule name, or a block model"
    )
    parser.add_argument(
        "--seconds", type=positive, default=5.0, metavar="S", help="simulated seconds (default 5)"
    )
    parser.add_argument(
        "--shake",
        type=nonnegative,
        default=0.0,
        metavar="V",
        help="ground shake: a lateral velocity change of V m/s over 1/60 s along +x after"
        " settling (the seed paper: 4)",
    )
    parser.add_argument(
        "--remove",
        metavar="ID|LABEL",
        action="append",
        default=[],
        help="delete the block with this id, or every block with this label, before the run;"
        " repeatable",
    )
    parser.add_argument(
        "--time-step",
        type=positive,
        default=None,
        metavar="DT",
        help="simulator step in seconds (default 0.0005)",
    )
    parser.add_argument(
        "--iterations",
        type=int,
        default=None,
        metavar="N",
        help="contact-solver iterations per step (default 50)",
    )
    parser.add_argument(
        "--tolerance",
        type=positive,
        default=None,
        metavar="M",
        help="judge by a fixed distance instead: a block fell when a vertex moved more than M"
        " metres after settling (default: relative to each block's smallest width)",
    )
    parser.add_argument(
        "--fps",
        type=positive,
        default=10.0,
        metavar="F",
        help="with --frames or -o .gif: frames per simulated second (default 10)",
    )
    pictures = parser.add_mutually_exclusive_group()
    pictures.add_argument("--frames", metavar="DIR", help="write one PNG per frame into DIR")
    pictures.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write an animation (.gif) or a picture of the final state (.png)",
    )
    parser.add_argument("--report", metavar="R.json", help="write a JSON report")
    add_derivation_options(parser, prefix="for a .grammar: ")
    add_statics_options(parser, prefix="with --optimize (and --friction for the run): ")
    # A design to simulate is searched with a safety margin by default (SIMULATION_MARGIN).
    add_search_options(parser)
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing")


def run(args: argparse.Namespace) -> int:
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
    with SimulationProgress(quiet=args.quiet) as progress:
        result = simulate(model, settings, remove=args.remove, progress=progress)
    report = {"model": str(args.model), **build_report, "simulation": result.to_report()}
    outputs = []
    if args.report:
        from shapegen.pipeline import report_bytes

        outputs.append((Path(args.report), report_bytes(report)))
    if args.output:
        outputs.append((Path(args.output), _simulation_picture(result, args.output)))
    write_all(outputs)
    if args.frames:
        from shapegen.simulation.pictures import write_frames

        write_frames(result, args.frames)
    if not args.quiet:
        print_simulation(str(args.model), result, args, build_report.get("build", {}))
    return 0


def _is_gif(output: str | None) -> bool:
    return bool(output) and Path(output).suffix.lower() == ".gif"


def _check_simulate_outputs(args: argparse.Namespace) -> None:
    from shapegen.simulation.world import load_pybullet

    load_pybullet()  # fail at once, before any building, when the extra is missing
    check_outputs({"-o": args.output, "--report": args.report}, folders={"--frames": args.frames})
    require_suffix(args.output, (".gif", ".png"), "the simulation (an animation or a picture)")
    if args.iterations is not None and args.iterations < 1:
        raise CommandLineError(f"--iterations must be at least 1, got {args.iterations}")


def _simulation_model(args: argparse.Namespace):
    """The model to simulate and the build part of the report (empty for a block model)."""
    from shapegen.engine.project.rules_path import find_bundled_rule

    name = str(args.model)
    is_grammar = name.endswith((".grammar", ".cga", ".rpk")) or (
        not Path(name).exists() and find_bundled_rule(name) is not None
    )
    if not is_grammar:
        if args.assignments or args.optimize or args.lot or args.free or args.fix:
            raise CommandLineError(
                "--set, --lot, --optimize, --free and --fix apply only to a rule file MODEL"
            )
        from shapegen.readers.models import read_model

        model = read_model(name)
        _refuse_other_structures((model.metadata.get("structure") or {}).get("name"), name)
        return model, {}
    from shapegen.pipeline import design
    from shapegen.structures import structure_class

    search = search_settings(args)
    grammar = load_grammar(name)
    _refuse_other_structures(grammar.structure, name)
    # --friction also sets the simulator's friction; the other statics options shape the search.
    statics = statics_options(args) if search is not None else None
    check_statics_apply(args, grammar, name)
    attrs = checked_attrs(grammar, args.assignments, search)
    measure = structure_class(grammar.structure).measure_name
    with SearchProgress(quiet=args.quiet or search is None, measure=measure) as progress:
        outcome = design(
            grammar,
            attrs=attrs,
            seed=args.seed,
            lot=args.lot,
            statics=statics,
            search=search,
            progress=progress,
        )
    report = dict(outcome.report)
    report.pop("seconds", None)
    return outcome.model, {"build": report}


def _refuse_other_structures(structure: str | None, source: str) -> None:
    """The simulator drops rigid blocks under gravity: a design judged otherwise (a bridge held by
    its cables) would fall and be called collapsed, which says nothing about it."""
    if not judges_blocks(structure):
        raise CommandLineError(
            f"{source} is judged by the {structure!r} structure, which the rigid-body simulator"
            " cannot represent (it simulates compression-only blocks); use `shapegen build"
            f" {source} --analyze`"
        )


def _simulation_picture(result, output: str) -> bytes:
    import tempfile

    from shapegen.simulation.pictures import encode_gif, write_picture

    if _is_gif(output):
        return encode_gif(result)
    with tempfile.TemporaryDirectory(prefix="shapegen-picture-") as folder:
        path = Path(folder) / "final.png"
        write_picture(result, path, "final")
        return path.read_bytes()
