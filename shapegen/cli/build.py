"""``shapegen build RULES``: derive a model, optionally optimize and judge it, write it."""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
import contextlib
from pathlib import Path

from shapegen.cli.common_options import (
    CommandLineError,
    add_derivation_options,
    add_rules_argument,
    add_search_options,
    add_statics_options,
    loaded_rules,
    positive,
    search_settings,
    statics_options,
)
from shapegen.cli.display import SearchProgress, print_build
from shapegen.cli.lateral_options import add_lateral_options, capacity_request
from shapegen.cli.outputs import check_outputs, print_written, write_all
from shapegen.limits import DEFAULT_LIMITS, raised_with, work_clock, work_limits

HELP = "derive a model from a rule file"
DESCRIPTION = (
    "Derive a model from a rule file (.grammar, .cga or .rpk). A bare file name that is"
    " not in the working directory is looked up among the bundled rules (see"
    " `shapegen rules`)."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    add_rules_argument(parser)
    add_derivation_options(parser)
    parser.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write the model: .json (shapegen-blocks), .glb/.gltf, .obj, .ply, .stl",
    )
    parser.add_argument("--report", metavar="R.json", help="write a JSON report")
    parser.add_argument(
        "--picture",
        metavar="OUT.png",
        help="write a picture of the model: blocks in their label colours, or, with --analyze or"
        " --optimize of block statics, in the tension they need, with a legend",
    )
    parser.add_argument(
        "--analyze",
        action="store_true",
        help="also judge whether the design stands, with the grammar's structure (block statics,"
        ' or the cable model of a @Structure("cable") bridge); the report gets an "analysis"',
    )
    add_statics_options(parser, prefix="with --analyze or --optimize, for block statics: ")
    add_lateral_options(parser, prefix="with --analyze or --optimize, for block statics: ")
    add_search_options(parser)
    parser.add_argument(
        "--osm",
        metavar="FILE.osm",
        help="place a bridge on an OpenStreetMap way (OSM XML), with --way: its straight length"
        " sets the attr length, its first and last nodes the position and direction",
    )
    parser.add_argument("--way", type=int, metavar="ID", help="with --osm: the way's id")
    parser.add_argument(
        "--max-seconds",
        type=positive,
        metavar="S",
        help="stop with an error once the build (deriving, judging and writing the model) has"
        f" run S seconds (default {DEFAULT_LIMITS.max_seconds:g}); with --optimize, each of the"
        " search's derivations and judgings",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing")


def run(args: argparse.Namespace) -> int:
    changes = {} if args.max_seconds is None else {"max_seconds": args.max_seconds}
    with work_limits(**changes), raised_with(max_seconds="--max-seconds S"):
        return _build(args)


def _build(args: argparse.Namespace) -> int:
    from shapegen.pipeline import design, encode_outputs
    from shapegen.structures import structure_class

    check_outputs(
        {"-o": args.output, "--report": args.report, "--picture": args.picture}, models=("-o",)
    )
    if args.picture and Path(args.picture).suffix.lower() != ".png":
        raise CommandLineError(f"--picture {args.picture}: a picture is written as .png")
    search = search_settings(args)
    judged = args.analyze or search is not None
    why = "they apply with --analyze or --optimize"
    statics = statics_options(args, applies=judged, why=why)
    capacity = capacity_request(args, applies=judged, why="it applies with --analyze or --optimize")
    grammar, attrs = loaded_rules(args, search)
    place = None
    way = _osm_way(args, grammar, attrs)
    if way is not None:
        from shapegen.export import osm

        attrs["length"] = osm.require_straight_length(way)

        def place(model):
            return osm.place_on_way(model, way)

    measure = structure_class(grammar.structure).measure_name
    # one clock over the whole build, from deriving to the files' bytes (a search runs many
    # builds, each under its own clocks)
    whole = work_clock("the build") if search is None else contextlib.nullcontext()
    with whole, SearchProgress(quiet=args.quiet or search is None, measure=measure) as progress:
        outcome = design(
            grammar,
            attrs=attrs,
            seed=args.seed,
            lot=args.lot,
            statics=statics,
            search=search,
            assess=args.analyze,
            place=place,
            progress=progress,
            capacity=capacity,
        )
        report = outcome.report
        if way is not None:
            report["osm"] = outcome.model.metadata["osm"]
        outputs = encode_outputs(
            outcome.model,
            outcome.assessment,
            report,
            model_path=args.output,
            report_path=args.report,
        )
        if args.picture:
            outputs.append((Path(args.picture), _picture(args.grammar, outcome)))
    write_all(outputs)
    if not args.quiet:
        print_build(str(args.grammar), report, lot_source=_lot_source(args, grammar))
        print_written(outputs)
    return 0


def _lot_source(args: argparse.Namespace, grammar) -> str:
    """Where the lot came from: ``--lot``, the start rule's ``@Lot``, or the default."""
    if args.lot is not None or args.osm is not None:
        return "--lot"
    return "@Lot" if grammar.program.start.annotation("Lot") is not None else "default"


def _picture(grammar_path: str, outcome) -> bytes:
    from shapegen.export.picture import encode_picture

    assessment = outcome.assessment
    analysis = assessment.block_analysis if assessment else None
    title = Path(grammar_path).name
    if assessment is not None:
        title += ": stands" if assessment.stands else ": does not stand"
    return encode_picture(outcome.model, analysis, title=title)


def _osm_way(args: argparse.Namespace, grammar, attrs: dict):
    """The way of ``--osm FILE --way ID`` (None without them), checked against the grammar."""
    if args.osm is None and args.way is None:
        return None
    if args.osm is None or args.way is None:
        raise CommandLineError("--osm and --way go together: --osm FILE.osm --way ID")
    if "length" not in grammar.attrs:
        raise CommandLineError(
            f"--osm places a bridge along a way: {args.grammar} has no attr 'length' to set"
        )
    if "length" in attrs:
        raise CommandLineError("--set length conflicts with --osm: the way gives the length")
    from shapegen.readers.osm import read_way

    return read_way(args.osm, args.way)
