r"""Work limits: how much one grammar load, one build or one file read may do before it stops.

Every path that could otherwise run until memory or patience runs out (a user function calling
itself twice per level, a string doubled forty times, ``i("arch", segments = 1e16)``, a model
file of a million blocks, a FIFO named ``.json``) is bounded by one of the limits below, and
exceeding one raises a :class:`~shapegen.errors.ShapegenError` whose message names the limit and
how to raise it. The defaults let every bundled rule and documentation example run with a wide
margin (the largest bundled model has about 1 100 blocks and 700 shapes).

Limits are read from the current context, so they reach every layer (the grammar parser, the
interpreter, the primitives, the model readers, and the search that rebuilds a design many
times) without being passed through each call:

>>> import shapegen
>>> from shapegen.limits import work_limits
>>> grammar = shapegen.parse_grammar("@StartRule @Lot(4, 1)\n"
...     "Lot --> extrude(1) split(x) { ~0.1 : A }*")
>>> with work_limits(max_shapes=20):
...     grammar.build()
Traceback (most recent call last):
    ...
shapegen.errors.GrammarError: ...
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_LIMITS",
    "LOT_EXTENT_LIMIT_M",
    "WorkLimits",
    "check_clock",
    "clock_ran_out",
    "current_limits",
    "limit_hint",
    "raised_with",
    "remaining_seconds",
    "work_clock",
    "work_limits",
]

import contextvars
import math
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, fields, replace

from shapegen.errors import OptionError, WorkLimitError


@dataclass(frozen=True)
class WorkLimits:
    """The most work one load, build or read may do.

    Attributes
    ----------
    max_source_chars
        Characters of grammar source text (a rule file or a string).
    max_definition_tokens
        Tokens of one definition (an attr, const, function or rule with its annotations): what
        bounds the parse of runaway text (a 5 MB expression), while a long file of ordinary
        definitions loads.
    max_depth
        Longest chain of rules from the start rule to a shape.
    max_shapes
        Shapes one derivation may create.
    max_calls
        User-function calls in one derivation (or one evaluation of attrs, ``@Range``, ``@Lot``
        and ``@Structure`` arguments); without calls, an expression's work is bounded by its size.
    max_call_depth
        User functions calling each other (or themselves) at once; a call in tail position
        (the function's value, or a value of its ``case``) takes its caller's place and nests
        no deeper, so a tail recursion is bounded by ``max_calls`` and the clock only.
    max_string_length
        Characters of one string value.
    max_string_chars
        Characters of all strings built by ``+`` in one derivation.
    max_primitive_blocks
        Blocks one inserted primitive may make (and bound of every count parameter: segments,
        rings, meridians, courses, sides...); checked before any array is allocated.
    max_blocks
        Blocks of one model, derived or read from a file.
    max_mesh_faces
        Faces of one shape's mesh: a CityEngine primitive's resolution (sides x divisions,
        checked before its mesh is made), an asset, the result of an operation.
    max_face_vertex_pairs
        Faces times vertices of a mesh that a check compares with each other (is it convex,
        where to cut it into convex pieces): what bounds the one piece of work that grows as
        the square of a mesh's size.
    max_skeleton_corners
        Corners of a polygon whose straight skeleton is swept (CGA's roofs, ``offset``,
        ``setback``, ``shapeL``...): the sweep's work grows as their square.
    max_coordinate
        Largest coordinate or size of a shape, metres. Past it an operation's result counts
        as overflowed, as inf or NaN do (its volume, weight and moments would lose every
        digit, and a float32 writer could not hold it).
    max_file_bytes
        Size of a model file (JSON or mesh) or a lots file read, bytes (a gzipped file's once
        inflated); a rule package may unpack to 16 times as much.
    max_json_depth
        Arrays and objects nested in one JSON document read.
    max_archive_members
        Files and folders of one archive (a rule package).
    max_archive_depth
        Folders one archive member lies in.
    max_import_depth
        Rule files importing one another in a chain (``a`` imports ``b``, which imports ``c``...).
    max_definitions
        Rules, attrs, consts and functions of one rule file with its imports merged: each
        ``import p:"x.cga"`` copies ``x.cga``'s under its prefix, so files that import one
        another several times over multiply them.
    max_seconds
        Seconds of one derivation (wall clock), or None for no time limit; also of judging its
        model (the geometry and the solver) and of encoding it for a file. Each runs under a
        clock of its own (:func:`work_clock`) that every long loop looks at, within the clock
        of the whole when there is one (the command line's ``build`` runs all three under one).
    """

    max_source_chars: int = 10_000_000
    max_definition_tokens: int = 100_000
    max_depth: int = 500
    max_shapes: int = 200_000
    max_calls: int = 500_000
    max_call_depth: int = 200
    max_string_length: int = 100_000
    max_string_chars: int = 10_000_000
    max_primitive_blocks: int = 20_000
    max_blocks: int = 50_000
    max_mesh_faces: int = 50_000
    max_face_vertex_pairs: int = 50_000_000
    max_skeleton_corners: int = 1_000
    max_coordinate: int = 1_000_000_000
    max_file_bytes: int = 32 * 2**20
    max_json_depth: int = 256
    max_archive_members: int = 20_000
    max_archive_depth: int = 64
    max_import_depth: int = 64
    max_definitions: int = 50_000
    max_seconds: float | None = 60.0

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if field.name == "max_seconds":
                ok = value is None or (
                    isinstance(value, int | float)
                    and not isinstance(value, bool)
                    and math.isfinite(value)
                    and value > 0
                )
                wanted = "a positive number of seconds or None"
            else:
                ok = isinstance(value, int) and not isinstance(value, bool) and value >= 1
                wanted = "a whole number >= 1"
            if not ok:
                raise OptionError(f"work limit {field.name} must be {wanted}, got {value!r}")


DEFAULT_LIMITS = WorkLimits()
"""The limits in force unless :func:`work_limits` says otherwise."""

#: A lot's corners (and a rectangle lot's width and depth) lie within this many metres of the
#: origin: far beyond any site on Earth (its circumference is 4e7 m), and far enough below
#: float64's range that a lot's area, a building's volumes and their sums stay finite. It is
#: the bound of every shape the rules make (``max_coordinate``), so that a lot is one.
LOT_EXTENT_LIMIT_M = float(DEFAULT_LIMITS.max_coordinate)

_CURRENT: contextvars.ContextVar[WorkLimits] = contextvars.ContextVar(
    "shapegen_work_limits", default=DEFAULT_LIMITS
)


def current_limits() -> WorkLimits:
    """The limits in force in this context (thread, task)."""
    return _CURRENT.get()


@contextmanager
def work_limits(limits: WorkLimits | None = None, /, **changes) -> Iterator[WorkLimits]:
    """Run a block of code under other limits: ``limits`` (default: the current ones) with
    ``changes`` applied, e.g. ``work_limits(max_blocks=200_000)``.

    Raises
    ------
    OptionError
        An unknown limit name or a value that is not a positive whole number (seconds: a
        positive number or None).
    """
    base = current_limits() if limits is None else limits
    if not isinstance(base, WorkLimits):
        raise OptionError(f"work_limits takes a WorkLimits, got {type(base).__name__}")
    known = [field.name for field in fields(WorkLimits)]
    unknown = sorted(set(changes) - set(known))
    if unknown:
        raise OptionError(f"unknown work limit {unknown[0]!r}; the limits: {', '.join(known)}")
    token = _CURRENT.set(replace(base, **changes))
    try:
        yield _CURRENT.get()
    finally:
        _CURRENT.reset(token)


_RAISED_WITH: contextvars.ContextVar[tuple[tuple[str, str], ...]] = contextvars.ContextVar(
    "shapegen_limits_raised_with", default=()
)


@contextmanager
def raised_with(**options: str) -> Iterator[None]:
    """Within this block, a message about limit ``name`` tells how to raise it with
    ``options[name]`` (a command's option, e.g. ``max_blocks="--max-blocks N"``) instead of
    :func:`work_limits`, which a command-line user cannot call."""
    token = _RAISED_WITH.set(tuple({**dict(_RAISED_WITH.get()), **options}.items()))
    try:
        yield
    finally:
        _RAISED_WITH.reset(token)


def limit_hint(name: str, limits: WorkLimits | None = None) -> str:
    """``(limit max_blocks = 50000; raise it with shapegen.limits.work_limits(max_blocks=...))``:
    the end of every message about a limit reached (or the option :func:`raised_with` names)."""
    value = getattr(limits or current_limits(), name)
    how = dict(_RAISED_WITH.get()).get(name) or f"shapegen.limits.work_limits({name}=...)"
    return f"(limit {name} = {value}; raise it with {how})"


# The work clock running in this context: its deadline (time.monotonic()), its seconds and
# the work it times, for the message.
_CLOCK: contextvars.ContextVar[tuple[float, float, str] | None] = contextvars.ContextVar(
    "shapegen_work_clock", default=None
)


@contextmanager
def work_clock(what: str, seconds: float | None = None) -> Iterator[float | None]:
    """Within this block, :func:`check_clock` stops the work (``what``, for the message:
    "the derivation") ``seconds`` (default: the limit ``max_seconds``; None: no clock) from
    now, or at the deadline of a clock already running if that comes first (its message then
    names both: "the build (judging the model) ran for more than 60 s"). Yields the deadline
    (``time.monotonic()``) or None."""
    if seconds is None:
        seconds = current_limits().max_seconds
    running = _CLOCK.get()
    clock = running
    if seconds is not None:
        mine = (time.monotonic() + seconds, float(seconds), what)
        clock = mine if running is None or mine[0] < running[0] else running
    if clock is not None and clock is running and what not in running[2]:
        clock = (running[0], running[1], f"{running[2]} ({what})")
    token = _CLOCK.set(clock)
    try:
        yield None if clock is None else clock[0]
    finally:
        _CLOCK.reset(token)


def remaining_seconds() -> float | None:
    """Seconds left on the work clock of this context (at least 0), or None without one: the
    time limit of a step that cannot look at the clock itself (a solver's own loop)."""
    clock = _CLOCK.get()
    return None if clock is None else max(0.0, clock[0] - time.monotonic())


def check_clock() -> None:
    """Raise :class:`~shapegen.errors.WorkLimitError` when the work clock of this context
    (:func:`work_clock`) has run out. Cheap (about 0.1 µs): every loop whose count an input
    sets looks at it once a pass.

    >>> with work_limits(max_seconds=1e-9), work_clock("the derivation"):
    ...     check_clock()
    Traceback (most recent call last):
        ...
    shapegen.errors.WorkLimitError: the derivation ran for more than 1e-09 s ...
    """
    clock = _CLOCK.get()
    if clock is not None and time.monotonic() > clock[0]:
        clock_ran_out()


def clock_ran_out() -> None:
    """Raise the :class:`~shapegen.errors.WorkLimitError` of the running work clock: a step
    given :func:`remaining_seconds` as its time limit (a solver) said that it ran out."""
    clock = _CLOCK.get()
    seconds = 0.0 if clock is None else clock[1]
    what = "the work" if clock is None else clock[2]
    raise WorkLimitError(f"{what} ran for more than {seconds:g} s " + limit_hint("max_seconds"))
