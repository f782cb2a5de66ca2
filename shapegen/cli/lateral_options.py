"""The lateral-load options of the commands that judge with block statics: ``--tilt
DEG[@AZIMUTH]`` (the tilting-table test) and ``--capacity [AZIMUTH,...]`` (the largest tilt at
which the design stands), their parsing and their one-line refusals."""

from __future__ import annotations

__all__ = ["add_lateral_options", "capacity_request"]

import argparse

from shapegen.cli.common_options import CommandLineError


def _tilt(text: str):
    """``--tilt DEG[@AZIMUTH]``: a :class:`~shapegen.statics.statics_options.Tilt`, parsed and
    checked by the type; its refusal is argparse's one line."""
    from shapegen.errors import OptionError
    from shapegen.statics.statics_options import Tilt

    try:
        return Tilt.parse(text)
    except OptionError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


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
    from shapegen.errors import OptionError
    from shapegen.statics.statics_options import checked_azimuth

    try:  # each as a tilt's azimuth is checked
        return tuple(checked_azimuth(v) for v in values)
    except OptionError as exc:
        raise argparse.ArgumentTypeError(f"{exc} (in {text!r})") from None


def add_lateral_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """--tilt and --capacity: the tilting-table test of block statics."""
    from shapegen.statics.statics_options import statics_field

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
