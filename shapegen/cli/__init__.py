"""The ``shapegen`` command: ``build``, ``analyze``, ``simulate``, ``landscape``, ``rules``.

A user's mistake (a bad file, a bad option value, a grammar error) ends with exit status 2 and one
line ``shapegen: error: <message>`` on stderr (grammar errors add their source excerpt); nothing
is written then. Whether a design stands is a result, not an error: ``analyze`` exits 0 either
way. Every command checks its outputs before any work, computes all of them before writing any,
and writes each file atomically. Each command is one module of this package; all of them run
the library's pipeline (:mod:`shapegen.pipeline`).
"""

from __future__ import annotations

__all__ = ["main", "build_parser", "CommandLineError"]

import sys
from collections.abc import Sequence

from shapegen import __version__
from shapegen.cli.options import CommandLineError, Parser
from shapegen.errors import ShapegenError

EXIT_OK = 0
EXIT_USAGE = 2


def build_parser() -> Parser:
    """The ``shapegen`` argument parser with every command."""
    from shapegen.cli import analyze, build, edit, landscape, rules, simulate

    parser = Parser(
        prog="shapegen",
        description=(
            "Procedural modeling of structures that stand up: build models from .grammar rules,"
            " check that they stand (rigid-block statics, or a bridge's cable model) and tune"
            " their free parameters until they do."
        ),
    )
    parser.add_argument("--version", action="version", version=f"shapegen {__version__}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    commands.required = True
    for command in (analyze, build, edit, landscape, rules, simulate):
        command.add_command(commands)
    return parser


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
