"""The option definitions and value checks shared by the commands, and what they turn into.

A bad command line raises :class:`CommandLineError`, which ``main`` prints as one line. An option
is honoured or refused: an option given where it means nothing (``--fix`` without
``--optimize``, ``--friction`` for a design judged by its cables) is an error, never dropped.
"""

from __future__ import annotations

__all__ = [
    "CommandLineError",
    "Parser",
    "add_derivation_options",
    "add_plugin_option",
    "add_rules_argument",
    "add_search_options",
    "add_statics_options",
    "block_statics_flags",
    "checked_attrs",
    "finite",
    "loaded_rules",
    "nonnegative",
    "positive",
    "search_settings",
    "statics_options",
]

import argparse
import math
from dataclasses import MISSING

from shapegen.errors import ShapegenError

# The flags of StaticsOptions' fields (add_statics_options); --tilt and --capacity are the
# lateral ones (lateral_options.py).
STATICS_FLAGS = {name: "--" + name for name in ("friction", "pyramid", "kern", "solver")}
LATERAL_FLAGS = {"tilt": "--tilt", "capacity": "--capacity"}
SELECTION_FLAGS = {"structural": "--structural", "ignore": "--ignore"}


class CommandLineError(ShapegenError):
    """A bad command line: unknown option, bad option value, missing argument."""


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors raised as exceptions instead of usage dumps and exits."""

    def error(self, message: str):  # argparse calls this for every usage error
        raise CommandLineError(message)


# ------------------------------------------------------------------------------ option values
def finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def nonnegative(text: str) -> float:
    value = finite(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text}")
    return value


def positive(text: str) -> float:
    value = finite(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _number(text: str) -> float:
    """A number as written (its range is the option's to check)."""
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _whole(minimum: int):
    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}, got {value}")
        return value

    return convert


def _lot(text: str):
    """``--lot``: WIDTH,DEPTH, a polygon ``"x,z x,z ..."``, a GeoJSON or OBJ file
    (:func:`shapegen.readers.lot_sources.read_lot`)."""
    from shapegen.errors import InputFormatError
    from shapegen.readers.lot_sources import read_lot

    try:
        return read_lot(text)
    except InputFormatError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("--lot ")) from None


def _assignment(text: str) -> tuple[str, object]:
    name, sep, raw = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    return name, _attr_value(raw.strip(), name)


def _attr_value(raw: str, name: str) -> object:
    """A ``--set`` value: a number, true/false, or else a string (quotes optional)."""
    lowered = raw.lower()
    if lowered in ("true", "false"):
        return lowered == "true"
    try:
        number = int(raw)
    except ValueError:
        try:
            number = float(raw)
        except ValueError:
            if len(raw) >= 2 and raw[0] == raw[-1] and raw[0] in "\"'":
                return raw[1:-1]
            return raw
    # an int beyond float range (1 and 400 zeros) would overflow math.isfinite
    if (isinstance(number, int) and number.bit_length() > 1023) or not math.isfinite(number):
        shown = raw if len(raw) <= 40 else raw[:37] + "..."
        raise argparse.ArgumentTypeError(f"{name}: expected a finite number, got {shown!r}")
    return number


def _labels(text: str) -> tuple[str, ...]:
    """``--structural`` / ``--ignore``: labels or rule names separated by commas."""
    names = tuple(dict.fromkeys(name.strip() for name in text.split(",") if name.strip()))
    if not names:
        raise argparse.ArgumentTypeError(
            f"expected labels or rule names separated by commas, got {text!r}"
        )
    return names


def _names(text: str) -> list[str]:
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"expected attr names separated by commas, got {text!r}")
    return names


# ------------------------------------------------------------------------------ option groups
def add_statics_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """A flag for each :class:`~shapegen.statics.statics_options.StaticsOptions` field but the tilt
    (``--friction``, ``--pyramid``, ``--kern``, ``--solver``, ``--structural``, ``--ignore``),
    with its help, choices and metavar from there; the values are checked by the options type
    when :func:`statics_options` makes it, and its refusal names the flag."""
    from shapegen.statics.statics_options import statics_fields

    for option in statics_fields():
        meta = option.metadata
        settings = {
            "number": {"type": _number, "metavar": meta.get("metavar")},
            "choice": {"choices": meta.get("choices")},
            "labels": {"type": _labels, "metavar": meta.get("metavar")},
        }.get(meta["kind"])
        if settings is not None:  # the tilt and its azimuth are --tilt (lateral_options.py)
            parser.add_argument(_flag(option.name), help=prefix + meta["help"], **settings)


def add_rules_argument(parser: argparse.ArgumentParser, metavar: str = "RULES") -> None:
    """The rule file a command derives (``args.grammar``): a path, or a bundled rule's name."""
    parser.add_argument(
        "grammar",
        metavar=metavar,
        help="rule file (.grammar, .cga or a CityEngine .rpk package) or a bundled rule's name",
    )


def add_derivation_options(parser: argparse.ArgumentParser, prefix: str = "") -> None:
    """--set, --lot and --seed: how a .grammar is derived."""
    parser.add_argument(
        "--set",
        dest="assignments",
        metavar="NAME=VALUE",
        action="append",
        type=_assignment,
        default=[],
        help=prefix + "override an attr (a number, true/false, or a string); repeatable",
    )
    parser.add_argument(
        "--lot",
        type=_lot,
        metavar="LOT",
        help=prefix + "the lot instead of the grammar's @Lot: WIDTH,DEPTH in metres (x, z), a"
        ' polygon "x,z x,z x,z ..." in metres (its holes after a "|": "... | x,z x,z x,z"),'
        " FILE.geojson[#ID] (a polygon's inner rings its holes) or FILE.obj (its first face)",
    )
    parser.add_argument(
        "--seed",
        type=int,
        default=0,
        metavar="N",
        help=prefix + "seed of rand() and stochastic rules (default 0)",
    )
    add_rules_path_option(parser)
    add_plugin_option(parser)


def add_plugin_option(parser: argparse.ArgumentParser) -> None:
    """--plugin: a module of one's own primitives or structures, loaded for this command."""
    parser.add_argument(
        "--plugin",
        action="append",
        metavar="MODULE_OR_FILE.py",
        help="import a module (a name on the Python path, or a .py file) before the work, so"
        " that the primitives and structures it registers can be used without installing it;"
        " repeatable; SHAPEGEN_PLUGINS lists more",
    )


def add_rules_path_option(parser: argparse.ArgumentParser) -> None:
    """--rules-path: where a .cga file's imports are looked up beyond its own project."""
    parser.add_argument(
        "--rules-path",
        action="append",
        metavar="DIR",
        help="a folder (or rule package .rpk) where imports are looked up after the rule "
        "file's own project, e.g. one holding ESRI.lib; repeatable; SHAPEGEN_RULES_PATH lists "
        "more",
    )


def add_search_options(parser: argparse.ArgumentParser) -> None:
    """``--optimize`` and a flag for each :class:`~shapegen.search.search_options.SearchOptions`
    field (``max_iter`` is ``--max-iter``), with its help, choices and default from there."""
    from shapegen.search.search_options import search_fields

    parser.add_argument(
        "--optimize",
        action="store_true",
        help="tune the free parameters (@Free attrs, or --free) until the design stands",
    )
    for option in search_fields():
        meta = option.metadata
        kind = meta["kind"]
        flag = "--" + option.name.replace("_", "-")
        default = "" if option.default in (None, MISSING) else f" (default {option.default})"
        settings = {
            "names": {"type": _names, "metavar": "A,B"},
            "assignments": {"type": _assignment, "action": "append", "metavar": "NAME=VALUE"},
            "choice": {"choices": meta.get("choices")},
            "count": {"type": _whole(meta.get("minimum", 0)), "metavar": "N"},
            "fraction": {"type": finite, "metavar": "M"},
        }[kind]
        parser.add_argument(
            flag, dest=option.name, help=f"with --optimize: {meta['help']}{default}", **settings
        )


# ------------------------------------------------------------------------------ what they mean
def _given(args, flags: dict[str, str]) -> list[str]:
    return [flag for dest, flag in flags.items() if getattr(args, dest, None) not in (None, [])]


def statics_options(args, *, applies: bool = True, why: str = ""):
    """The block-statics options given, --tilt among them (None when none was), or an error
    when they cannot apply or a value means nothing (naming its flag).

    ``applies`` False refuses them with ``why`` (for example "they apply with --analyze or
    --optimize").
    """
    given = _given(args, {**STATICS_FLAGS, **SELECTION_FLAGS, "tilt": "--tilt"})
    if not given:
        return None
    if not applies:
        raise CommandLineError(f"{', '.join(given)}: {why}")
    from shapegen.errors import OptionError
    from shapegen.statics.statics_options import StaticsOptions

    values = {
        dest: getattr(args, dest)
        for dest in (*STATICS_FLAGS, *SELECTION_FLAGS)
        if getattr(args, dest, None) is not None
    }
    tilt = getattr(args, "tilt", None)  # a Tilt, checked when --tilt was read
    if tilt is not None:
        values["tilt"], values["azimuth"] = tilt.degrees, tilt.azimuth
    try:
        return StaticsOptions(**values)
    except OptionError as exc:
        flag = "--tilt" if exc.option in ("tilt", "azimuth") else _flag(exc.option or "")
        raise CommandLineError(f"{flag}: {exc}") from None


def block_statics_flags(args) -> list[str]:
    """The options given that only block statics honour."""
    return _given(args, {**STATICS_FLAGS, **SELECTION_FLAGS, **LATERAL_FLAGS})


def judges_blocks(structure: str | None) -> bool:
    """True when the structure named ``structure`` (None: the default) judges rigid blocks."""
    from shapegen.structures import structure_class

    return structure_class(structure).judges_blocks


def check_statics_apply(args, grammar, source: str) -> None:
    """Refuse block-statics options (--tilt and --capacity among them) for a grammar judged by
    another structure."""
    given = block_statics_flags(args)
    if given and not judges_blocks(grammar.structure):
        verb = "applies" if len(given) == 1 else "apply"
        raise CommandLineError(
            f"{', '.join(given)} {verb} to block statics; {source} is judged by the"
            f" {grammar.structure!r} structure (@Structure on its start rule)"
        )


def search_settings(args):
    """The :class:`~shapegen.search.search_options.SearchOptions` of ``--optimize``, None without
    it; search options given without ``--optimize`` are refused."""
    from shapegen.search.search_options import SearchOptions, search_fields

    given = {f.name: getattr(args, f.name) for f in search_fields()}
    given = {name: value for name, value in given.items() if value is not None}
    if not args.optimize:
        if given:
            flags = [f"--{name.replace('_', '-')}" for name in given]
            verb = "applies" if len(flags) == 1 else "apply"
            raise CommandLineError(f"{', '.join(flags)} only {verb} with --optimize")
        return None
    if "fix" in given:
        given["fix"] = dict(given["fix"])
    return SearchOptions(**given)


def load_grammar(name: str):
    from shapegen.pipeline import load

    return load(name)


def loaded_rules(args: argparse.Namespace, search=None) -> tuple[object, dict]:
    """The rule file ``args.grammar`` loaded, the block-statics options refused if it is judged
    by another structure, and its ``--set`` (with ``search``, ``--fix``) values checked: the
    grammar and the attrs by name."""
    grammar = load_grammar(args.grammar)
    check_statics_apply(args, grammar, args.grammar)
    return grammar, checked_attrs(grammar, args.assignments, search)


def checked_attrs(grammar, assignments: list[tuple[str, object]], search=None) -> dict:
    """The ``--set`` values by name, and, with ``search`` (the search's settings), its
    ``--fix`` values checked alike with the ``--set`` ones beside them; an unknown name is an
    error with close suggestions, and a number outside its attr's ``@Range`` (or off its
    stepsize) one warning line: CityEngine treats a range as a hint, so the value is used as
    given, never clamped (:meth:`~shapegen.engine.attr_catalogue.AttrCatalogue.range_warnings`,
    the design page's rule too)."""
    attrs = _checked(grammar, assignments, "--set", {})
    if search is not None:
        _checked(grammar, list(search.fix.items()), "--fix", attrs)
    return attrs


def _checked(grammar, assignments: list[tuple[str, object]], option: str, given: dict) -> dict:
    """The values of one option by name; ``given`` holds the other attrs the ranges may
    depend on."""
    import sys

    catalogue = grammar.catalogue
    attrs: dict = {}
    for name, value in assignments:
        if name not in catalogue:
            raise CommandLineError(f"{option} {name}: {catalogue.no_attr(name, most=3)}")
        attrs[name] = value
    for warning in catalogue.range_warnings(attrs, given).values():
        sys.stderr.write(f"shapegen: warning: {option} {warning}\n")
    return attrs
