"""``shapegen edit RULES [--port N] [--no-open]``: the design page in the browser.

Serves the page and its JSON API on 127.0.0.1 (docs/editor.md), opens it in the user's browser,
re-reads the grammar file when it changes on disk, and stops on Ctrl-C.
"""

from __future__ import annotations

__all__ = ["DEFAULT_PORT", "HELP", "DESCRIPTION", "add_arguments", "run"]

import argparse
import errno
import signal
import sys
from pathlib import Path

from shapegen.cli.common_options import CommandLineError, add_derivation_options, add_rules_argument

DEFAULT_PORT = 8765


def _port(text: str) -> int:
    try:
        port = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a port number: {text!r}") from None
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"a port is between 0 and 65535, got {port}")
    return port


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


HELP = "edit a design in the browser: sliders, verdict, stable ranges, optimize"
DESCRIPTION = (
    "Serve an interactive design page for a .grammar on 127.0.0.1: the model in 3D, an"
    " Inspector of its attrs (sliders for those with @Range; on each @Free slider the"
    " interval where the design stands), the verdict after every change, and the"
    " search. The page reloads when the file changes on disk. Ctrl-C stops."
)


def add_arguments(parser) -> None:
    """The command's arguments and options, on its ``parser``."""
    add_rules_argument(parser)
    parser.add_argument(
        "--port",
        type=_port,
        default=DEFAULT_PORT,
        metavar="N",
        help=f"port on 127.0.0.1 (default {DEFAULT_PORT}; 0 picks a free one)",
    )
    parser.add_argument(
        "--no-open", action="store_true", help="print the address without opening a browser"
    )
    add_derivation_options(parser, prefix="initial design: ")


def run(args: argparse.Namespace) -> int:
    from shapegen.cli.common_options import checked_attrs, load_grammar
    from shapegen.editor import EditorSession, make_server
    from shapegen.editor.watch import FileWatcher

    grammar = load_grammar(args.grammar)
    if grammar.path is None:
        raise CommandLineError(f"{args.grammar}: the editor needs a grammar file")
    # the build's rule: an unknown attr is refused, a value outside its @Range warned of
    checked_attrs(grammar, args.assignments)
    try:
        server = make_server(None, args.port)  # the port first: a taken one costs no build
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise CommandLineError(
                f"port {args.port} on 127.0.0.1 is in use; choose another with --port N"
                " (0 picks a free one)"
            ) from None
        raise
    try:
        # --set values are checked as the page's are: a known attr, of its kind (the page
        # shows the warning of one outside its @Range too)
        # a package is opened as such (its exported command names it), not as its start rule
        opened = args.grammar if Path(args.grammar).suffix.lower() == ".rpk" else grammar.path
        server.session = session = EditorSession(
            str(opened),
            attrs=dict(args.assignments),
            seed=args.seed,
            lot=args.lot,
            rules_path=args.rules_path or (),
            measure_follows=True,  # the page shows a proven verdict at once, its measure after
        )
    except BaseException:
        server.server_close()
        raise
    # a package is watched, not its start rule in the cache: CityEngine exports it anew
    watcher = FileWatcher(session.package or grammar.path, lambda: session.reload())
    shown = (
        grammar.path if session.package is None else f"{args.grammar}, start rule {grammar.path}"
    )
    print(f"shapegen edit: {server.url}  ({shown}; Ctrl-C stops)", flush=True)
    if not args.no_open:
        import webbrowser

        if not webbrowser.open(server.url):
            print("shapegen edit: no browser could be opened; open the address above", flush=True)
    previous = signal.signal(signal.SIGTERM, _interrupt)  # a `kill` stops as cleanly as Ctrl-C
    try:
        server.serve_forever(poll_interval=0.2)
    except KeyboardInterrupt:
        pass
    finally:
        watcher.stop()
        server.server_close()
        session.close()
        signal.signal(signal.SIGTERM, previous)
    sys.stderr.write("shapegen edit: stopped\n")
    return 0
