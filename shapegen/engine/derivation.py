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

import random
from collections.abc import Callable
from typing import Protocol

from shapegen.engine.shape import Shape
from shapegen.errors import GrammarError

DEFAULT_MAX_DEPTH = 500
"""Longest chain of rules from the start rule to a shape."""

DEFAULT_MAX_SHAPES = 1_000_000
"""Most shapes one derivation may create."""

TOO_DEEP = "a user function calls itself too deeply (endless recursion?)"


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
        "path",
        "children",
        "rng",
        "rule_path",
        "depth",
        "initial_scope",
    )

    def random(self) -> float:
        """A uniform draw in [0, 1) from this shape's own generator."""
        rng = self.rng[0]
        if rng is None:
            key = f"{self.run.seed}/" + "/".join(str(k) for k in self.path)
            rng = self.rng[0] = random.Random(key)
        return rng.random()

    def copy(self) -> ShapeState:
        """A copy for ``[ ... ]``: same place in the tree (children and draws are shared)."""
        other = ShapeState.__new__(ShapeState)
        for name in ShapeState.__slots__:
            setattr(other, name, getattr(self, name))
        other.initial_scope = self.shape.scope
        return other


class Derivation:
    """The mutable part of one derivation: seed, limits, the shape count and the reports."""

    def __init__(self, program: _ErrorSource, seed: int, max_depth: int, max_shapes: int):
        self.program = program
        self.seed = int(seed)
        self.max_depth = max_depth
        self.max_shapes = max_shapes
        self.shape_count = 0
        self.reports: dict[str, list] = {}

    def child(self, parent: ShapeState, shape: Shape, node, name: str | None = None) -> ShapeState:
        """A new shape below ``parent``; ``name`` is the successor's name for a successor."""
        self.shape_count += 1
        if self.shape_count > self.max_shapes:
            chain = parent.rule_path + ((name,) if name else ())
            raise self.program.error(
                node,
                f"the derivation creates more than {self.max_shapes} shapes (max_shapes); "
                f"the grammar may be running away. Chain of rules: {format_chain(chain)}",
            )
        state = ShapeState.__new__(ShapeState)
        state.run = self
        state.shape = shape
        state.attrs = parent.attrs
        state.labels = parent.labels
        state.split_index = parent.split_index
        state.split_total = parent.split_total
        state.comp_index = parent.comp_index
        state.comp_total = parent.comp_total
        state.path = parent.path + (parent.children[0],)
        parent.children[0] += 1
        state.children = [0]
        state.rng = [None]
        state.initial_scope = shape.scope
        if name is None:
            state.rule_path = parent.rule_path
            state.depth = parent.depth
        else:
            state.rule_path = parent.rule_path + (name,)
            state.depth = parent.depth + 1
            if state.depth > self.max_depth:
                raise self.program.error(
                    node,
                    f"the derivation is deeper than {self.max_depth} rules (max_depth); the "
                    f"grammar may recurse without end. Chain of rules: "
                    f"{format_chain(state.rule_path)}",
                )
        return state


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


# An operation: op(state, args, out) -> False when the shape was deleted (NIL), else True.
Operation = Callable[[ShapeState, tuple, list], bool]


def root_state(run: Derivation, shape: Shape, attrs, path: tuple) -> ShapeState:
    state = ShapeState.__new__(ShapeState)
    state.run = run
    state.shape = shape
    state.attrs = attrs
    state.labels = ()
    state.split_index = 0
    state.split_total = 0
    state.comp_index = 0
    state.comp_total = 0
    state.path = path
    state.children = [0]
    state.rng = [None]
    state.rule_path = ()
    state.depth = 0
    state.initial_scope = shape.scope
    return state
