"""The lateral-load options of the commands that judge with block statics: ``--tilt
DEG[@AZIMUTH]`` (the tilting-table test) and ``--capacity [AZIMUTH,...]`` (the largest tilt at
which the design stands), their parsing and their one-line refusals."""

from __future__ import annotations

__all__ = ["add_lateral_options", "capacity_request"]

import argparse
import math

from shapegen.cli.options import CommandLineError


def _tilt(text: str) -> tuple[float, float | None]:
    """``--tilt DEG[@AZIMUTH]``: the two numbers as written (None: no azimuth, the worst
    direction); :class:`~shapegen.statics.options.StaticsOptions` checks their ranges."""
    tilt_text, sep, azimuth_text = text.partition("@")
    try:
        tilt = float(tilt_text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected DEG or DEG@AZIMUTH (degrees), got {text!r}"
        ) from None
    if not sep:
        return tilt, None
    try:
        return tilt, float(azimuth_text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"the azimuth {azimuth_text.strip()!r} in {text!r} is not a number of degrees"
        ) from None


def _azimuths(text: str) -> tuple[float, ...]:
    """``--capacity [AZIMUTH,...]``: azimuths in degrees; empty for the sweep."""
    if not text.strip():
        return ()
    parts = [part.strip() for part in text.split(",")]
    try:
        values = tuple(float(part) for part in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected azimuths in degrees separated by commas (0,90), got {text!r}; write"
            " --capacity after the model, or --capacity= for a sweep of directions"
        ) from None
    if not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"azimuths must be finite numbers, got {text!r}")
    return values


def add_lateral_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """--tilt and --capacity: the tilting-table test of block statics."""
    from shapegen.statics.options import statics_field

    tilt = statics_field("tilt").metadata
    parser.add_argument("--tilt", type=_tilt, metavar=tilt["metavar"], help=prefix + tilt["help"])
    parser.add_argument(
        "--capacity",
        type=_azimuths,
        nargs="?",
        const=(),
        metavar="AZIMUTH,...",
        help=prefix + "report the lateral capacity: the largest tilt at which the design stands"
        " (and its tangent, the horizontal load multiplier), to 0.05 degrees, towards each"
        " azimuth given, or over a sweep of 16 directions and the worst when none is",
    )


def capacity_request(args, *, applies: bool = True, why: str = ""):
    """The azimuths of --capacity (an empty tuple for the sweep; None without it), or an
    error when it cannot apply."""
    azimuths = getattr(args, "capacity", None)
    if azimuths is not None and not applies:
        raise CommandLineError(f"--capacity: {why}")
    return azimuths
