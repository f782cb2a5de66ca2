"""The state of one derivation: the shapes being derived, the run's limits and its reports.

:class:`ShapeState` is one shape with everything the grammar can read or change on it;
:class:`Derivation` creates the shapes below it and stops a grammar that runs away.
"""

from __future__ import annotations

__all__ = [
    "DEFAULT_MAX_DEPTH",
    "DEFAULT_MAX_SHAPES",
    "TOO_DEEP",
    "Derivation",
    "Operation",
    "ShapeState",
    "format_chain",
    "root_state",
]

from collections.abc import Callable
from typing import Protocol

from shapegen.engine.derivation import random_streams
from shapegen.engine.derivation.finite import checked_child, with_carried_tags
from shapegen.engine.shapes.shape import Shape
from shapegen.errors import GrammarError, WorkLimitError
from shapegen.limits import (
    DEFAULT_LIMITS,
    WorkLimits,
    check_clock,
    current_limits,
    limit_hint,
    remaining_seconds,
)

DEFAULT_MAX_DEPTH = DEFAULT_LIMITS.max_depth
"""Longest chain of rules from the start rule to a shape (:class:`~shapegen.limits.WorkLimits`)."""

DEFAULT_MAX_SHAPES = DEFAULT_LIMITS.max_shapes
"""Most shapes one derivation may create (:class:`~shapegen.limits.WorkLimits`)."""

TOO_DEEP = (
    "user functions call each other too deeply for Python's stack (endless recursion?) "
    + limit_hint("max_call_depth", DEFAULT_LIMITS)
)

# How many user-function calls pass between two looks at the clock.
_CLOCK_EVERY = 1024


class _ErrorSource(Protocol):
    """What a derivation needs of its program: errors that point at a node of the grammar."""

    def error(self, node, message: str) -> GrammarError: ...


class ShapeState:
    """One shape being derived, with everything the grammar can read or change on it."""

    __slots__ = (
        "run",
        "shape",
        "attrs",
        "labels",
        "split_index",
        "split_total",
        "comp_index",
        "comp_total",
        "comp_sel",
        "path",
        "children",
        "rng",
        "rule_path",
        "depth",
        "initial_scope",
        "appearance",
        "trim_planes",
        "deleted",
        "piece",
        "pivot",
        "tree",
    )

    def is_leaf(self) -> bool:
        """No successor was made of this shape and no ``NIL`` deleted it: it is a leaf."""
        return self.children[0] == 0 and not self.deleted

    def random(self) -> float:
        """A uniform draw in [0, 1] from this shape's own stream, as CityEngine draws it
        (:mod:`~shapegen.engine.derivation.random_streams`)."""
        stream = self.rng
        stream[0], u = random_streams.draw(stream[0])
        return u

    def copy(self) -> ShapeState:
        """A copy for ``[ ... ]``: same place in the tree (children and draws are shared)."""
        other = ShapeState.__new__(ShapeState)
        for name in ShapeState.__slots__:
            setattr(other, name, getattr(self, name))
        other.initial_scope = self.shape.scope
        return other


class Derivation:
    """The mutable part of one derivation: seed, limits, the work counts and the reports.

    ``limits`` defaults to the current :class:`~shapegen.limits.WorkLimits`; ``max_depth`` and
    ``max_shapes``, when given, override its two fields of those names.
    """

    def __init__(
        self,
        program: _ErrorSource,
        seed: int,
        max_depth: int | None = None,
        max_shapes: int | None = None,
        limits: WorkLimits | None = None,
    ):
        self.program = program
        self.seed = int(seed)
        self.limits = limits = limits or current_limits()
        self.max_depth = limits.max_depth if max_depth is None else max_depth
        self.max_shapes = limits.max_shapes if max_shapes is None else max_shapes
        self.shape_count = 0
        self.calls = 0
        self.call_depth = 0
        self.string_chars = 0
        self.reports: dict[str, list] = {}
        self.warnings: list[str] = []  # what the model's metadata lists under "warnings"
        self.cga_errors = 0  # operations skipped past, as CityEngine's runtime does (.cga)
        # The start shape's axes: the frame of CGA's object.* selectors.
        self.object_rotation = None
        self.start_shape: Shape | None = None  # what resetGeometry() goes back to
        # whether a work clock runs (shapegen.limits.work_clock: Grammar.build starts one for
        # the derivation, inside any the build, the lot or the page's request runs): the
        # derivation's own checks look at it only then
        self.timed = remaining_seconds() is not None
        # inside()/overlaps()/touches(): set by the interpreter
        # (shapegen.engine.derivation.occlusion)
        self.occlusion = None
        # isTagged(): the component a comp() or modify() selector is looking at
        # (shapegen.engine.operations.cga.topology.TagSelection), None elsewhere
        self.tag_selection = None
        # whether component tags are kept (the program reads them: Program.reads_tags)
        self.tags = getattr(program, "reads_tags", True)
        self.tag_index = None  # (shape, its shapegen.engine.shapes.tags.TagIndex): the last

    def warn(self, message: str) -> None:
        """Record a warning of the derivation once (an asset not found, an operation ignored)."""
        if message not in self.warnings:
            self.warnings.append(message)

    def check_clock(self, node) -> None:
        """Stop the derivation, at ``node``'s place, when the work clock it runs
        (:func:`shapegen.limits.work_clock`, which the geometry kernels' loops look at too) has
        run out: the one clock of the build, the city lot or the page's request, or the
        derivation's own ``max_seconds`` when that ends first."""
        try:
            check_clock()
        except WorkLimitError as exc:
            raise self.program.error(node, str(exc)) from None

    def enter_call(self, node, name: str, nested: bool = True) -> None:
        """Count a user-function call; stop a runaway one (``max_calls``, ``max_call_depth``).
        A call in tail position (``nested=False``) takes its caller's place: it is counted,
        and the clock looked at, but it nests no deeper."""
        self.calls += 1
        self.call_depth += nested
        limits = self.limits
        if self.calls > limits.max_calls:
            raise self.program.error(
                node,
                f"more than {limits.max_calls} user-function calls (the last to {name!r}): an "
                f"endless recursion, or a function calling itself more than once per level "
                + limit_hint("max_calls", limits),
            )
        if self.call_depth > limits.max_call_depth:
            raise self.program.error(
                node,
                f"function {name!r} calls itself too deeply: more than "
                f"{limits.max_call_depth} nested user-function calls (endless recursion?) "
                + limit_hint("max_call_depth", limits),
            )
        if self.calls % _CLOCK_EVERY == 0:
            self.check_clock(node)

    def count_string(self, node, length: int) -> None:
        """Account for a string of ``length`` characters built by ``+``."""
        limits = self.limits
        if length > limits.max_string_length:
            raise self.program.error(
                node,
                f"a string of more than {limits.max_string_length} characters "
                + limit_hint("max_string_length", limits),
            )
        self.string_chars += length
        if self.string_chars > limits.max_string_chars:
            raise self.program.error(
                node,
                f"the derivation builds more than {limits.max_string_chars} characters of "
                f"strings " + limit_hint("max_string_chars", limits),
            )

    def child(
        self,
        parent: ShapeState,
        shape: Shape,
        node,
        name: str | None = None,
        within_bounds: bool = False,
    ) -> ShapeState:
        """A new shape below ``parent``; ``name`` is the successor's name for a successor.
        ``within_bounds``: the operation has checked the shape's numbers (for its batch)."""
        self.shape_count += 1
        if self.shape_count > self.max_shapes:
            chain = parent.rule_path + ((name,) if name else ())
            raise self.program.error(
                node,
                f"the derivation creates more than {self.max_shapes} shapes (max_shapes); "
                f"the grammar may be running away. Chain of rules: {format_chain(chain)} "
                + _argument_hint("max_shapes"),
            )
        if self.timed and self.shape_count % 64 == 0:
            self.check_clock(node)
        if shape is not parent.shape:
            if not within_bounds:  # made by a split, a comp...
                checked_child(self.program, node, parent, shape)
            if self.tags and parent.shape.tags is not None and shape.tags is None:
                shape = with_carried_tags(parent.shape, shape)
        if self.occlusion is not None and shape.kind != parent.shape.kind:
            self.occlusion.parent(
                parent
            )  # a comp of a mass: an occluder (engine/derivation/occlusion.py)
        state = ShapeState.__new__(ShapeState)
        state.run = self
        state.shape = shape
        state.attrs = parent.attrs
        state.labels = parent.labels
        state.split_index = parent.split_index
        state.split_total = parent.split_total
        state.comp_index = parent.comp_index
        state.comp_total = parent.comp_total
        state.comp_sel = parent.comp_sel
        state.path = parent.path + (parent.children[0],)
        parent.children[0] += 1
        state.children = [0]
        # a new shape takes one step of its parent's stream and begins its own from there
        # (random_streams: a successor, or a piece of a split, comp... one step further)
        stream = parent.rng
        x = stream[0]
        state.rng = [random_streams.child_stream(x, successor=name is not None)]
        stream[0] = random_streams.step(x)
        state.initial_scope = shape.scope
        state.appearance = parent.appearance
        state.trim_planes = parent.trim_planes
        state.deleted = False
        state.piece = name is None  # made by an operation (a split's, a comp's...), no rule
        state.pivot = parent.pivot
        if name is None:
            state.rule_path = parent.rule_path
            state.depth = parent.depth
            state.tree = parent.tree  # an operation's result: still the same node of the tree
        else:
            count = parent.tree[2]
            state.tree = (parent.tree, count[0], [0])  # a link up: no copy of the path
            count[0] += 1
            state.rule_path = parent.rule_path + (name,)
            state.depth = parent.depth + 1
            if state.depth > self.max_depth:
                raise self.program.error(
                    node,
                    f"the derivation is deeper than {self.max_depth} rules (max_depth); the "
                    f"grammar may recurse without end. Chain of rules: "
                    f"{format_chain(state.rule_path)} " + _argument_hint("max_depth"),
                )
        return state


def _argument_hint(name: str) -> str:
    return f"(raise it with Grammar.build({name}=...) or shapegen.limits.work_limits({name}=...))"


def format_chain(chain: tuple[str, ...], keep: int = 12) -> str:
    """``A -> B -> C x 40 -> D``: a rule chain with repeats folded and the middle elided."""
    runs: list[list] = []
    for name in chain:
        if runs and runs[-1][0] == name:
            runs[-1][1] += 1
        else:
            runs.append([name, 1])
    parts = [name if count == 1 else f"{name} x {count}" for name, count in runs]
    if len(parts) > keep:
        half = keep // 2
        parts = parts[:half] + [f"... ({len(parts) - keep} more) ..."] + parts[-half:]
    return " -> ".join(parts)


# An operation: op(state, args, out) -> False when the shape was replaced by others (a split, a
# comp...), else True.
Operation = Callable[[ShapeState, tuple, list], bool]


def root_state(
    run: Derivation, shape: Shape, attrs, path: tuple, stream: int | None = None
) -> ShapeState:
    """A shape with no parent: the start shape of ``run`` (its stream begins at the seed's
    state), or the shape an attr's default is evaluated on (``stream``: the attr's own)."""
    state = ShapeState.__new__(ShapeState)
    state.run = run
    state.shape = shape
    state.attrs = attrs
    state.labels = ()
    state.split_index = 0
    state.split_total = 0
    state.comp_index = 0
    state.comp_total = 0
    state.comp_sel = ""  # comp.sel: the selector of the last comp, as written ("" before one)
    state.path = path
    state.children = [0]
    state.rng = [random_streams.start(run.seed) if stream is None else stream]
    state.rule_path = ()
    state.depth = 0
    state.initial_scope = shape.scope
    state.appearance = None
    state.trim_planes = ()  # geometry.trim.TrimPlane of the last comp(f), world coordinates
    state.deleted = False  # NIL; COMP_CAME_TO_NOTHING (engine/operations/cga/topology.py)
    state.piece = False
    # attr_pivot: (origin, axes as columns) in world coordinates, set by comp, setPivot and the
    # alignScopeTo* operations; None is the initial shape's pivot, the object frame
    state.pivot = None
    # getTreeKey(): the shape's node in the tree of rule applications (func_getTreeKey): the
    # parent's node, its index among the parent's successors, the successors made so far
    state.tree = (None, 0, [0])
    return state
