"""``shapegen analyze MODEL``: judge a model file with the structure it records (block statics
by default)."""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
from contextlib import contextmanager
from pathlib import Path

from shapegen.cli.common_options import (
    CommandLineError,
    add_plugin_option,
    add_statics_options,
    block_statics_flags,
    judges_blocks,
    statics_options,
)
from shapegen.cli.display import print_analysis
from shapegen.cli.lateral_options import add_lateral_options, capacity_request
from shapegen.cli.outputs import check_outputs, print_written, write_all
from shapegen.limits import DEFAULT_LIMITS, current_limits, raised_with, work_limits

EXIT_OK = 0
BYTES_PER_BLOCK = 4096
"""File size allowed per block with --max-blocks: a brick as shapegen writes it (8 vertices,
6 faces, indented) takes about 900 bytes."""


HELP = "check whether a model file stands"
DESCRIPTION = (
    "Check whether a block model stands under its own weight and its loads, with"
    " compression-only frictional joints (the tension-penalty QP); a model written by"
    " `shapegen build` is judged by the structure it records (a bridge by its cables)."
    " --tilt judges it on a tilting table, --capacity reports how far it can tilt."
    " Exits 0 whether or not it stands; exits 2 for bad input."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    parser.add_argument(
        "model",
        metavar="MODEL",
        help="block model: shapegen-blocks .json, or a mesh (.obj .gltf .glb .ply .stl)",
    )
    add_statics_options(parser)
    add_lateral_options(parser)
    add_plugin_option(parser)  # a model judged by a structure of one's own
    parser.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        help="write the model coloured by tension with resultant arrows (.glb .gltf; or any"
        " model format: .json .obj .ply .stl)",
    )
    parser.add_argument("--report", metavar="R.json", help="write a JSON report")
    parser.add_argument(
        "--max-blocks",
        type=_block_count,
        metavar="N",
        help=f"read a model of up to N blocks (default {DEFAULT_LIMITS.max_blocks}) and a file"
        f" of up to {BYTES_PER_BLOCK} bytes a block",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing")


def run(args: argparse.Namespace) -> int:
    from shapegen.engine.project.rules_path import find_bundled_rule
    from shapegen.pipeline import encode_outputs
    from shapegen.readers.models import read_model
    from shapegen.structures import Design, make_structure

    name = str(args.model)
    if name.endswith((".grammar", ".cga", ".rpk")) or (
        not Path(name).exists() and find_bundled_rule(name) is not None
    ):
        raise CommandLineError(
            f"{name} is a rule file, not a model: use `shapegen build {name} --analyze`"
        )
    check_outputs({"-o": args.output, "--report": args.report}, models=("-o",))
    with _reading_limits(args.max_blocks):
        model = read_model(name)
    design = Design.of_model(model)
    recorded = (model.metadata.get("structure") or {}).get("name")
    options = statics_options(args)
    given = block_statics_flags(args)
    if given and not judges_blocks(recorded):
        verb = "applies" if len(given) == 1 else "apply"
        raise CommandLineError(
            f"{', '.join(given)} {verb} to block statics; {name} is judged by the"
            f" {recorded!r} structure it records"
        )
    structure = make_structure(recorded, options)
    assessment = structure.assess(design)
    report = {"model": name, **assessment.to_report()}
    azimuths = capacity_request(args)
    if azimuths is not None:
        report["capacity"] = structure.lateral_capacity(design, azimuths).to_report()
    outputs = encode_outputs(model, assessment, report, model_path=args.output,
                             report_path=args.report)  # fmt: skip
    write_all(outputs)
    if not args.quiet:
        print_analysis(name, report)
        print_written(outputs)
    return EXIT_OK


def _block_count(text: str) -> int:
    """--max-blocks: a whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, got {text!r}")
    return value


@contextmanager
def _reading_limits(max_blocks: int | None):
    """The work limits for reading the model: ``max_blocks`` blocks (default: the limit in
    force), and a file of up to :data:`BYTES_PER_BLOCK` bytes a block (never less than the size
    limit in force), so that any file of as many blocks as allowed can be read; a message about
    either limit names ``--max-blocks``."""
    limits = current_limits()
    blocks = limits.max_blocks if max_blocks is None else max_blocks
    file_bytes = max(limits.max_file_bytes, BYTES_PER_BLOCK * blocks)
    option = "--max-blocks N"
    per_block = f"{option} ({BYTES_PER_BLOCK} bytes a block)"
    with (
        work_limits(limits, max_blocks=blocks, max_file_bytes=file_bytes),
        raised_with(max_blocks=option, max_file_bytes=per_block),
    ):
        yield
