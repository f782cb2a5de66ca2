"""``shapegen landscape RULES P1 P2 -o OUT.png``: the structure's measure over two attrs."""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
from pathlib import Path

from shapegen.cli.common_options import (
    CommandLineError,
    add_derivation_options,
    add_rules_argument,
    add_statics_options,
    check_statics_apply,
    checked_attrs,
    load_grammar,
    statics_options,
)
from shapegen.cli.outputs import check_outputs, require_suffix

HELP = "plot how far from standing the design is, over two free parameters"
DESCRIPTION = (
    "Evaluate the grammar's structure on a grid over the @Range of two attrs (block"
    " statics: the infeasibility y/W^2; a cable bridge: the squared relative excess of"
    " its cable diameter), mark the region where the design stands, draw the"
    " optimizer's path, and write a PNG."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    add_rules_argument(parser)
    parser.add_argument("first", metavar="P1", help="attr on the horizontal axis")
    parser.add_argument("second", metavar="P2", help="attr on the vertical axis")
    parser.add_argument(
        "--grid", type=int, default=15, metavar="N", help="points per axis (default 15)"
    )
    add_derivation_options(parser)
    parser.add_argument("--no-path", action="store_true", help="do not run and draw the optimizer")
    parser.add_argument(
        "-o", "--output", metavar="OUT.png", required=True, help="the picture to write (.png)"
    )
    add_statics_options(parser, prefix="for block statics: ")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing")


def run(args: argparse.Namespace) -> int:
    from shapegen.export.landscape_plot import plot_landscape
    from shapegen.search import energy_landscape, optimize
    from shapegen.structures import make_structure

    output = Path(args.output)
    check_outputs({"-o": args.output})
    require_suffix(args.output, (".png",), "the landscape")
    if not 2 <= args.grid <= 200:
        raise CommandLineError(f"--grid must be between 2 and 200, got {args.grid}")
    grammar = load_grammar(args.grammar)
    statics = statics_options(args)
    check_statics_apply(args, grammar, args.grammar)
    structure = make_structure(grammar.structure, statics)
    attrs = checked_attrs(grammar, args.assignments)
    console = None
    if not args.quiet:
        from shapegen.cli.display import console as make_console

        console = make_console(stderr=True)
    path = None
    if not args.no_path:
        result = optimize(
            grammar, structure=structure, free=[args.first, args.second], attrs=attrs,
            seed=args.seed, lot=args.lot, build=False,
        )  # fmt: skip
        path = result.path
    settings = dict(attrs=attrs, seed=args.seed, lot=args.lot, structure=structure)
    if console is not None:
        from rich.progress import Progress

        with Progress(console=console, transient=True) as bar:
            task = bar.add_task("landscape", total=args.grid**2)
            landscape = energy_landscape(
                grammar, args.first, args.second, grid=args.grid, **settings,
                progress=lambda done, total: bar.update(task, completed=done),
            )  # fmt: skip
    else:
        landscape = energy_landscape(grammar, args.first, args.second, grid=args.grid, **settings)
    # the rule's file name (a package's, when one was opened): a full path would be cut at the
    # plot's edge, leaving the reader a fragment of a folder
    opened = args.grammar if Path(args.grammar).suffix.lower() == ".rpk" else grammar.name
    title = f"{Path(opened).name}: {structure.measure_name}"
    plot_landscape(landscape, output, path, title=title)
    if console is not None:
        share = landscape.feasible.mean() * 100
        console.print(
            f"wrote {output}: {args.grid}x{args.grid} grid of {structure.measure_name},"
            f" {share:.0f}% of it stands"
            + (f"; optimizer path of {len(path)} points" if path else "")
        )
    return 0
