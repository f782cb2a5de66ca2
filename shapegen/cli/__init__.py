"""The ``shapegen`` command: ``build``, ``analyze``, ``simulate``, ``landscape``, ``rules``,
``city``.

A user's mistake (a bad file, a bad option value, a grammar error) ends with exit status 2 and one
line ``shapegen: error: <message>`` on stderr (grammar errors add their source excerpt); nothing
is written then. Whether a design stands is a result, not an error: ``analyze`` exits 0 either
way. Every command checks its outputs before any work, computes all of them before writing any,
and writes each file atomically. Ctrl-C (or SIGTERM, SIGHUP) at any point, imports included,
prints ``shapegen: interrupted``, removes any temporary file and exits 130 (143, 129). Each
command is one module of this package; all of them run the library's pipeline
(:mod:`shapegen.pipeline`).
"""

from __future__ import annotations

__all__ = ["main", "build_parser", "CommandLineError"]

# Only the standard library's sys here: the console script imports this module before main()
# can catch a Ctrl-C, so everything else is imported inside main's guard.
import sys

EXIT_OK = 0
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130  # 128 + SIGINT, as a shell reports a process stopped by Ctrl-C


def __getattr__(name: str):
    if name == "CommandLineError":
        from shapegen.cli.common_options import CommandLineError

        return CommandLineError
    raise AttributeError(f"module 'shapegen.cli' has no attribute {name!r}")


def build_parser():
    """The ``shapegen`` argument parser with every command."""
    from shapegen import __version__
    from shapegen.cli import analyze, build, city, edit, landscape, rules, simulate
    from shapegen.cli.common_options import Parser

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
    # each command is a module: its name, HELP, DESCRIPTION, add_arguments(parser) and run(args)
    for command in (analyze, build, city, edit, landscape, rules, simulate):
        name = command.__name__.rpartition(".")[2]
        sub = commands.add_parser(name, help=command.HELP, description=command.DESCRIPTION)
        command.add_arguments(sub)
        sub.set_defaults(handler=command.run)
    return parser


def main(argv=None) -> int:
    """Run the ``shapegen`` command with ``argv`` (default: the process arguments).

    Returns the exit status: 0 on success, 2 for a user's mistake, 128 + the signal's number
    when interrupted (130 for Ctrl-C).
    """
    try:
        from shapegen.threads import one_thread_unless_chosen

        one_thread_unless_chosen()  # before numpy loads: see shapegen.threads
        from shapegen.export.atomic import stop_on_signals

        with stop_on_signals():
            return _run(argv)
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM/SIGHUP as atomic.Interrupted
        return _interrupted(exc)


def _run(argv) -> int:
    import warnings

    from shapegen.errors import ShapegenError

    parser = build_parser()
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _warning_line
            args = parser.parse_args(argv)
            _apply_rules_path(getattr(args, "rules_path", None))
            _apply_plugins(getattr(args, "plugin", None))
            return args.handler(args)
    except SystemExit as exc:  # --help and --version
        return exc.code if isinstance(exc.code, int) else EXIT_OK
    except ShapegenError as exc:
        return _fail(str(exc))
    except OSError as exc:
        where = f"{exc.filename}: " if exc.filename else ""
        return _fail(f"{where}{exc.strerror or exc}")


def _apply_rules_path(folders: list[str] | None) -> None:
    """``--rules-path`` folders go before SHAPEGEN_RULES_PATH's, for every rule file this run
    loads (the page's reloads and the city's workers included): they are made into one
    :class:`~shapegen.engine.project.rule_packages.RulesPath` here, each checked once (a
    missing folder is one line now, not at the first import), and the checked folders are what
    the variable then lists, for this process's loads and the processes it starts."""
    if not folders:
        return
    import os

    from shapegen.engine.project.rule_packages import RULES_PATH_VARIABLE, RulesPath

    os.environ[RULES_PATH_VARIABLE] = RulesPath.of(folders).exported()


def _apply_plugins(specs: list[str] | None) -> None:
    """``--plugin`` modules are imported before the work (a broken one is one line now) and
    listed in SHAPEGEN_PLUGINS, so that a city's workers load them too."""
    if not specs:
        return
    from shapegen.plugins import use_modules

    use_modules(specs)


def _interrupted(exc: KeyboardInterrupt) -> int:
    """Remove what an interrupted write left, say so in one line, and give the exit status."""
    import signal

    status = getattr(exc, "exit_status", EXIT_INTERRUPTED)
    held = {}
    try:
        for name in ("SIGINT", "SIGTERM", "SIGHUP"):  # a second Ctrl-C must not cut this short
            if hasattr(signal, name):
                signum = getattr(signal, name)
                held[signum] = signal.signal(signum, signal.SIG_IGN)
    except ValueError:  # not the main thread: handlers cannot be changed there
        pass
    try:
        atomic = sys.modules.get("shapegen.export.atomic")
        if atomic is not None:
            atomic.remove_temporaries()
        sys.stderr.write("shapegen: interrupted\n")
        sys.stderr.flush()
    finally:
        for signum, handler in held.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
    return status


def _warning_line(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning (a search start moved into its @Range...) as one line, like the errors."""
    sys.stderr.write(f"shapegen: warning: {message}\n")
    sys.stderr.flush()


def _fail(message: str) -> int:
    sys.stderr.write(f"shapegen: error: {message}\n")
    sys.stderr.flush()
    return EXIT_USAGE
