"""``shapegen city LOTS RULE.grammar -o OUTDIR``: one rule over every lot of a city."""

from __future__ import annotations

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
import sys
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
from shapegen.cli.display import ProgressBar
from shapegen.cli.outputs import check_outputs

EXIT_OK = 0
EXIT_ALL_FAILED = 1  # the run went through and no lot was built


def _workers(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


HELP = "build and judge one rule on every lot of a city (GeoJSON or OSM buildings)"
DESCRIPTION = (
    "Derive RULE on every polygon of LOTS, judge (and with --optimize tune) each"
    " building, and write a results table (CSV, GeoJSON and GeoParquet) and the city"
    " as glTF to OUTDIR. A lot's properties set the rule's attrs of the same names."
    " Lots run on"
    " this machine's cores, or on a Dask cluster with --scheduler, in batches whose"
    " workers write their lots' results into OUTDIR (a folder or a URL); a rerun into"
    " the same OUTDIR skips the lots done."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    parser.add_argument(
        "lots",
        metavar="LOTS",
        help="a GeoJSON FeatureCollection of polygons, or an OSM XML file (its buildings)",
    )
    add_rules_argument(parser, metavar="RULE.grammar")
    parser.add_argument(
        "-o",
        "--output",
        metavar="OUTDIR",
        required=True,
        help="the output folder (created), or a URL fsspec understands (s3://bucket/city,"
        " memory://city)",
    )
    parser.add_argument(
        "--crs",
        metavar="CRS",
        help="the coordinates of LOTS: a system pyproj knows (EPSG:2154, EPSG:3857...), lonlat"
        " (WGS84) or metres (local, no place on the earth); default: the file's crs member,"
        " the .prj beside it, else detected from the coordinates' range",
    )
    add_derivation_options(parser, prefix="for every lot: ")
    for action in parser._actions:  # the lots are LOTS' polygons: --lot is refused, so not offered
        if "--lot" in action.option_strings:
            action.help = argparse.SUPPRESS
    add_statics_options(parser, prefix="for block statics: ")
    add_search_options(parser)
    parser.add_argument(
        "--timeout",
        type=positive,
        metavar="S",
        help="seconds one lot may take; a lot past it is a row with status 'timeout'",
    )
    parser.add_argument(
        "--workers",
        type=_workers,
        metavar="N",
        help="local worker processes (default: one per core)",
    )
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on an existing Dask cluster (tcp://host:8786) instead of local processes,"
        " or on a new Dask cluster of N processes of this machine (local:N); its workers need"
        " shapegen installed and must reach OUTDIR",
    )
    parser.add_argument(
        "--batch-size",
        type=_workers,
        metavar="N",
        help="lots per task (default: about half a second of a worker's time per task)",
    )
    parser.add_argument(
        "--no-analyze",
        action="store_true",
        help="derive the buildings without judging them (stands and measure left empty)",
    )
    parser.add_argument("--picture", metavar="OUT.png", help="also draw the built city")
    parser.add_argument(
        "--tiles",
        action="store_true",
        help="also write the city as OGC 3D Tiles 1.1 (OUTDIR/tiles/tileset.json and its .glb"
        " tiles, placed on the WGS84 ellipsoid); view them with python -m shapegen.city.viewer",
    )
    parser.add_argument(
        "--tiles-height",
        type=float,
        default=0.0,
        metavar="M",
        help="with --tiles: the ground's height above the WGS84 ellipsoid at the city (m)",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing")


def run(args: argparse.Namespace) -> int:
    from shapegen.city import read_lots, run_city

    if args.lot is not None:
        raise CommandLineError("--lot: a city's lots are the polygons of LOTS")
    if args.workers is not None and args.scheduler is not None:
        raise CommandLineError("--workers applies to local processes; a Dask cluster has its own")
    local = None if "://" in args.output and not args.output.startswith("file://") else args.output
    check_outputs(
        {"--picture": args.picture}, folders={"-o": local and local.removeprefix("file://")}
    )
    if args.picture and Path(args.picture).suffix.lower() != ".png":
        raise CommandLineError(f"--picture {args.picture}: a picture is written as .png")
    search = search_settings(args)
    statics = statics_options(args)
    grammar, attrs = loaded_rules(args, search)
    city = read_lots(args.lots, crs=args.crs)
    if args.tiles and city.origin_lonlat is None:
        raise CommandLineError(
            f"--tiles: {args.lots} is in local metres, with no place on the earth; name its"
            " coordinate system with --crs EPSG:NNNN"
        )
    if args.tiles and "://" in str(args.output) and not str(args.output).startswith("file://"):
        raise CommandLineError(f"--tiles: tiles are written into a local folder, not {args.output}")
    if args.tiles_height != 0.0 and not args.tiles:
        raise CommandLineError("--tiles-height applies to --tiles")
    if city.skipped and not args.quiet:
        sys.stderr.write(
            f"shapegen: warning: {args.lots}: {city.skipped} feature(s) that are not polygon"
            " footprints skipped\n"
        )
    with _ProgressBar(quiet=args.quiet) as progress:
        outcome = run_city(
            city,
            grammar,
            args.output,
            attrs=attrs,
            seed=args.seed,
            search=search,
            statics=statics,
            timeout=args.timeout,
            workers=args.workers,
            scheduler=args.scheduler,
            batch_size=args.batch_size,
            analyze=not args.no_analyze,
            progress=progress,
        )
    if args.picture and outcome.built == 0:
        sys.stderr.write(f"shapegen: warning: --picture {args.picture}: no lot was built\n")
    elif args.picture:
        from shapegen.city.outputs import encode_city_picture
        from shapegen.pipeline import write_outputs

        title = f"{Path(args.grammar).name} on {Path(args.lots).name}"
        picture = encode_city_picture(outcome.store, outcome.records, title=title)
        write_outputs([(Path(args.picture), picture)])
    tileset = None
    if args.tiles and outcome.built == 0:
        sys.stderr.write("shapegen: warning: --tiles: no lot was built, no tiles written\n")
    elif args.tiles:
        from shapegen.city.tiles import write_tiles

        folder = str(args.output).removeprefix("file://")
        tileset = write_tiles(folder, outcome.city, height=args.tiles_height)
    if not args.quiet:
        _summary(outcome, args)
        if tileset is not None:
            print(
                f"3D Tiles: {tileset.path} ({tileset.buildings} buildings in {tileset.tiles}"
                f" tiles); view: python -m shapegen.city.viewer {args.output}"
            )
    return _exit_status(outcome, quiet=args.quiet)


def _exit_status(outcome, quiet: bool) -> int:
    """0 when some lot was built (a failed one is a row of the results, and said on stderr);
    1 when every lot failed: the run made nothing, which a script must see. (2 stays a
    mistake found before any work.)"""
    records = [r for r in outcome.records if r is not None]
    failed = [r for r in records if r["status"] != "ok"]
    if not failed:
        return EXIT_OK
    if len(failed) == len(records):
        first = failed[0]
        sys.stderr.write(
            f"shapegen: error: every lot failed ({_failures(failed)}); first: {first['id']}:"
            f" {first['status']}: {first['error']}\n"
        )
        return EXIT_ALL_FAILED
    if not quiet:
        sys.stderr.write(
            f"shapegen: warning: {len(failed)} of {len(records)} lots failed"
            f" ({_failures(failed)}): their rows' error column says why\n"
        )
    return EXIT_OK


def _failures(failed: list[dict]) -> str:
    errors = sum(1 for r in failed if r["status"] == "error")
    timeouts = len(failed) - errors
    parts = [f"{errors} error{'s' * (errors != 1)}"] if errors else []
    return ", ".join(parts + ([f"{timeouts} timed out"] if timeouts else []))


def _summary(outcome, args) -> None:
    records = [r for r in outcome.records if r is not None]
    ok = [r for r in records if r["status"] == "ok"]
    stands = sum(1 for r in ok if r["stands"])
    unjudged = sum(1 for r in ok if r["stands"] is None)
    errors = sum(1 for r in records if r["status"] == "error")
    timeouts = sum(1 for r in records if r["status"] == "timeout")
    ran = len(records) - outcome.resumed
    rate = ran / outcome.seconds if outcome.seconds > 0 else 0.0
    mapped = sorted({name for r in records for name in r.get("from_properties") or []})
    print(
        f"{len(records)} lots: "
        + (
            f"{stands} stand, {len(ok) - stands - unjudged} do not stand, "
            if unjudged < len(ok)
            else ""
        )  # fmt: skip
        + (f"{unjudged} built (not judged), " if unjudged else "")
        + f"{errors} failed, {timeouts} timed out"
        + (f" ({outcome.resumed} done by an earlier run)" if outcome.resumed else "")
    )
    if ran:
        print(f"{ran} lots in {outcome.seconds:.1f} s ({rate:.2f} lots/s) on {outcome.executor}")
    how = outcome.derivation
    if how["batch"]:
        reasons = sorted(how["reasons"].items(), key=lambda item: -item[1])
        why = "; ".join(f"{reason}: {count}" for reason, count in reasons[:4])
        print(
            f"derived in batches: {how['batch']} lots; one shape at a time: {how['shape']}"
            + (f" ({why})" if why else "")
        )
    partial = [r["id"] for r in ok if r.get("left_out")]
    if partial:
        shown = ", ".join(partial[:5]) + (
            f" and {len(partial) - 5} more" if len(partial) > 5 else ""
        )
        print(f"judged without the leaves that are not convex blocks (left_out): {shown}")
    if mapped:
        print(f"attrs set by the lots' properties: {', '.join(mapped)}")
    for record in [r for r in records if r["status"] != "ok"][:5]:
        print(f"  {record['id']}: {record['status']}: {record['error']}")
    tables = [outcome.files[k] for k in ("csv", "geojson", "parquet") if k in outcome.files]
    print(f"results: {', '.join(map(str, tables))}")
    if "parquet" not in outcome.files:
        from shapegen.city.parquet import PARQUET_MISSING

        sys.stderr.write(f"shapegen: warning: {PARQUET_MISSING}\n")
    if "glb" in outcome.files:
        print(f"city: {outcome.files['glb']}")


class _ProgressBar(ProgressBar):
    """A rich progress bar on stderr: lots done of all, failures and the rate."""

    def columns(self) -> tuple:
        from rich.progress import BarColumn, MofNCompleteColumn, TextColumn

        return (
            TextColumn("lots"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("{task.fields[failed]} failed, {task.fields[rate]:.2f} lots/s"),
        )

    def __call__(self, event) -> None:
        if self.bar is None:
            return
        if self.task is None:
            self.task = self.bar.add_task("lots", total=event.total, failed=0, rate=0.0)
        self.bar.update(self.task, completed=event.done, failed=event.failed, rate=event.rate)
