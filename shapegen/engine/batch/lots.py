"""A city's lots derived together: footprints as packed arrays, one rule on all of them.

:func:`derive_lots` takes the footprints of many lots (their corners end to end with ring
offsets), one seed and one set of attr values per lot, and derives them with the grammar's
compiled rules at the width of the batch: each rule body's batch form (``rule.body.batch``,
compiled beside its one-shape form by :mod:`~shapegen.engine.operations.compiler`) calls the
batch forms the registry holds (:mod:`~shapegen.engine.operations.registry`: ``set``,
``extrude`` of the flat footprint, ``color``, ``report``, successors) on a
:class:`ShapeBatch`, ``case`` and stochastic bodies split it by masks, and every lot draws its
random numbers from its own stream (:mod:`~shapegen.engine.derivation.random_streams`, the
stochastic choice lot by lot with the one-shape :func:`~shapegen.engine.derivation.
random_streams.choice`), so each lot's heights, reports and attrs are the ones its own
derivation gives.

Each lot of the batch ends in one leaf: its footprint extruded, a prism given by its packed
corners and height. A lot (or a branch of lots) meeting anything without a batch form
(:class:`~shapegen.engine.operations.registry.Unsupported`: other operations, a footprint
whose convexity or shape is in doubt, a height that is not clearly positive) is marked
``fallback``, with the reason counted: its caller derives it one shape at a time.

The leaf of a lot is drawn as the one-at-a-time derivation draws it, up to round-off
(1e-9 m): a footprint that is a rectangle filling its scope gives a box block (its eight
corners in scope order), a convex one a block of the prism, any other a solid kept as derived.
"""

from __future__ import annotations

__all__ = ["LotBatch", "derive_lots"]

import warnings
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from shapegen.engine.batch.columns import ColumnExpressions
from shapegen.engine.batch.footprints import Footprints
from shapegen.engine.derivation import random_streams
from shapegen.engine.operations.registry import Unsupported, is_column
from shapegen.grammar import ast

BOX, CONVEX, SOLID = 0, 1, 2  # what a lot's leaf is drawn as


@dataclass
class LotBatch:
    """What :func:`derive_lots` made of ``n`` lots.

    Attributes
    ----------
    fallback
        ``(n,)`` bool: lots the batch did not derive (derive them one at a time).
    reasons
        Why, counted over the lots (``{"reason": lots}``).
    why
        ``(n,)`` each lot's reason (``""`` for a lot the batch derived).
    footprints
        The lots' start shapes (:class:`~shapegen.engine.batch.footprints.Footprints`).
    kind
        ``(n,)`` what each lot's leaf is drawn as: ``BOX``, ``CONVEX`` (a block) or ``SOLID``.
    height
        ``(n,)`` the extrusion of each lot's footprint (m).
    events
        The batch's reports in the order they were made: ``(lot indices, key, value or
        column)`` (:meth:`reports` gives each lot's).
    values
        Per lot, the attr values it started with (its group's dict, shared).
    warnings
        The warnings of every lot's derivation (the rule's own, from its load).
    """

    fallback: np.ndarray
    reasons: Counter
    why: np.ndarray
    footprints: Footprints
    kind: np.ndarray
    height: np.ndarray
    events: list
    values: list
    warnings: list = field(default_factory=list)

    @property
    def derived(self) -> int:
        """Lots the batch derived."""
        return int((~self.fallback).sum())

    def reports(self) -> list:
        """Per lot, its reports as its own derivation gives them (``{key: value}``, or a list
        of values for a key reported more than once); None for a lot that fell back."""
        found: list = [None if bad else {} for bad in self.fallback.tolist()]
        for index, key, value in self.events:
            column = is_column(value)
            for j, k in enumerate(index.tolist()):
                if found[k] is not None:
                    found[k].setdefault(key, []).append(value[j].item() if column else value)
        for lot in found:
            if lot is not None:
                for key, items in lot.items():
                    lot[key] = items[0] if len(items) == 1 else items
        return found


def derive_lots(grammar, rings, offsets, seeds, overrides, limits=None) -> LotBatch:
    """Derive lots with ``grammar`` (a loaded :class:`~shapegen.Grammar`) as one batch.

    ``rings`` are ``(P, 2)`` corners ``(x, z)`` in metres of every lot end to end (as
    :meth:`~shapegen.Grammar.build` takes a polygon: counter-clockwise seen from above),
    ``offsets`` ``(n + 1,)`` where each lot's corners start; ``seeds`` one derivation seed per
    lot; ``overrides`` one dict of attr values per lot (lots sharing a dict object are grouped
    without comparing). ``limits`` are the :class:`~shapegen.limits.WorkLimits` of each lot.
    Never raises for a lot's trouble: such a lot falls back (see module doc)."""
    from shapegen.limits import current_limits

    program = grammar.program
    count = len(offsets) - 1
    footprints = Footprints(np.asarray(rings, dtype=float), np.asarray(offsets, dtype=np.int64))
    run = _Run(program, count, footprints, [int(s) for s in seeds])
    for reason in set(footprints.doubt[footprints.doubtful].tolist()):
        run.give_up(footprints.doubtful & (footprints.doubt == reason), reason)
    limits = limits or current_limits()
    reason = _whole_rule_reason(program, limits)
    if reason is not None:
        run.give_up(np.ones(count, dtype=bool), reason)
    else:
        run.max_depth = limits.max_depth
        for index, values in _groups(program, overrides, run):
            batch = ShapeBatch(run, index, values, 0)
            batch.streams = random_streams.starts(run.seeds)
            _derive(batch, program.rules[(program.start.name, 0)])
    return run.finish()


def _whole_rule_reason(program, limits) -> str | None:
    """Why no lot of this rule can go in a batch, or None."""
    if not program.cga_dialect:
        return "a .grammar rule (only .cga rules go in batches)"
    for node in program.attr_nodes.values():
        if node.local_variables or not isinstance(
            node.value, ast.Number | ast.String | ast.Boolean
        ):
            return "an attr whose value is not a literal"
        if any(a.name == "Free" for a in node.annotations):
            return "an @Free attr"
    for node in program.const_nodes.values():
        if node.local_variables or not isinstance(
            node.value, ast.Number | ast.String | ast.Boolean
        ):
            return "a const whose value is not a literal"
    if program.start.annotations and any(a.name == "Structure" for a in program.start.annotations):
        return "an @Structure start rule"
    if limits.max_depth < 8 or limits.max_shapes < 8 or limits.max_blocks < 1:
        return "work limits below a batch's few shapes"
    return None


def _groups(program, overrides, run):
    """``(lot indices, initial values)`` per distinct overrides; a group whose values do not
    come out cleanly (a coercion warns or fails) falls back."""
    from shapegen.engine.shapes.shape import lot_scope

    by_object: dict[int, list] = {}
    first: dict[int, dict] = {}
    for k, given in enumerate(overrides):
        by_object.setdefault(id(given), []).append(k)
        first.setdefault(id(given), given)
    merged: dict[tuple, list] = {}
    for key, lots in by_object.items():
        given = first[key]
        try:
            signature = tuple(sorted((name, repr(v)) for name, v in given.items()))
        except TypeError:
            run.give_up(_mask(run.count, lots), "attr values that cannot be compared")
            continue
        merged.setdefault(signature, []).extend(lots)
    scope = lot_scope(10.0, 10.0)
    for lots in merged.values():
        given = first[id(overrides[lots[0]])]
        index = np.array(sorted(lots), dtype=np.int64)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                values = program.attributes.initial_values(given, 0, scope)
        except Exception:  # noqa: BLE001 - the one-at-a-time derivation says what it is
            run.give_up(_mask(run.count, index), "attr values that do not evaluate")
            continue
        if caught:
            run.give_up(_mask(run.count, index), "attr values that warn")
            continue
        index = index[~run.fallback[index]]
        if len(index):
            run.values_of[index] = len(run.groups)
            run.groups.append(values)
            yield index, values


def _mask(count: int, index) -> np.ndarray:
    mask = np.zeros(count, dtype=bool)
    mask[np.asarray(index, dtype=np.int64)] = True
    return mask


class _Run:
    """The batch's shared state: which lots fell back and why, the reports, the leaves."""

    def __init__(self, program, count: int, footprints: Footprints, seeds: list[int]):
        from shapegen.engine.derivation.state import Derivation, root_state
        from shapegen.engine.shapes.shape import FACE, Shape, lot_scope

        self.program = program
        self.count = count
        self.footprints = footprints
        self.seeds = seeds
        self.fallback = np.zeros(count, dtype=bool)
        self.reasons: Counter = Counter()
        self.why = np.full(count, "", dtype=object)
        self.events: list[tuple] = []  # (lot indices, key, value or column), in order
        self.kind = np.full(count, -1, dtype=np.int8)
        self.height = np.zeros(count)
        self.leaves = np.zeros(count, dtype=np.int64)
        self.groups: list[dict] = []
        self.values_of = np.full(count, -1, dtype=np.int64)
        self.max_depth = 0
        probe_run = Derivation(program, 0)
        self.probe = root_state(probe_run, Shape(lot_scope(10.0, 10.0), FACE, 1), {}, ("probe",))
        self.expressions = ColumnExpressions(program, self.probe)

    def give_up(self, mask: np.ndarray, reason: str) -> None:
        new = mask & ~self.fallback
        if new.any():
            self.fallback |= new
            self.reasons[reason] += int(new.sum())
            self.why[new] = reason

    def finish(self) -> LotBatch:
        self.give_up(self.leaves != 1, "not one leaf a lot")
        self.give_up(self.kind < 0, "a leaf that is not an extruded footprint")
        footprints = self.footprints
        self.give_up(footprints.not_convex_in_doubt(self.height), "convex or not, in doubt")
        kind = np.where(footprints.box, BOX, np.where(footprints.convex, CONVEX, SOLID))
        kind = np.where(self.fallback, -1, kind).astype(np.int8)
        values = [self.groups[g] if g >= 0 else None for g in self.values_of.tolist()]
        return LotBatch(
            self.fallback,
            self.reasons,
            self.why,
            footprints,
            kind,
            self.height,
            self.events,
            values,
            list(self.program.grammar.warnings),
        )


class ShapeBatch:
    """The shapes of some lots standing at the same place of their trees, one per lot: their
    attrs (shared values or columns) and shape (the footprint, or its extrusion).

    A rule is derived on it by the batch form of the rule's compiled body (``rule.body.batch``,
    :mod:`~shapegen.engine.operations.compiler`), which calls the registered batch forms of its
    operations (:mod:`~shapegen.engine.operations.registry`) on it; this class holds only the
    state they change."""

    def __init__(self, run: _Run, index: np.ndarray, attrs: dict, depth: int):
        self.run = run
        self.index = index
        self.attrs = attrs
        self.depth = depth
        self.height = None  # None: the flat footprint; else the extrusion's column (m)
        self.children = 0
        # each lot's state of this shape's stream, indexed by lot (the parts of the batch share
        # the array: the same shapes, whose streams go on)
        self.streams = np.zeros(run.count, dtype=np.int64)

    @property
    def size(self) -> int:
        return len(self.index)

    @property
    def footprints(self) -> Footprints:
        return self.run.footprints

    def shared_attrs(self) -> dict:
        return {k: v for k, v in self.attrs.items() if not is_column(v)}

    def value(self, node):
        """The value of expression ``node`` on these shapes: one Python value or a column."""
        return self.run.expressions.value(node, self)

    def give_up(self, mask: np.ndarray, reason: str) -> None:
        """Lots of this batch (``mask`` over it) that fall back."""
        self.run.give_up(_mask(self.run.count, self.index[mask]), reason)

    def draws(self) -> np.ndarray:
        """One uniform draw in [0, 1] per shape, each from its lot's stream of this shape (as
        ShapeState.random draws it)."""
        self.streams[self.index], u = random_streams.draws(self.streams[self.index])
        return u

    def successor(self) -> ShapeBatch:
        """The successor of these shapes (one per lot): their attrs and shape as they are now,
        its streams begun from theirs, which step for it (as Derivation.child makes one)."""
        if self.children:
            raise Unsupported("two successors of one shape")
        if self.depth + 1 > self.run.max_depth:
            raise Unsupported("a chain of rules deeper than max_depth")
        self.children += 1
        child = ShapeBatch(self.run, self.index, dict(self.attrs), self.depth + 1)
        child.height = self.height
        x = self.streams[self.index]
        child.streams[self.index] = random_streams.child_stream(x)
        self.streams[self.index] = random_streams.step(x)
        return child

    def report(self, key: str, value) -> None:
        """``report(key, value)`` of every shape (``value`` shared or a column)."""
        self.run.events.append((self.index, key, value))

    def leaf(self) -> None:
        """These shapes are leaves: each lot's is the prism of its footprint."""
        run = self.run
        run.leaves[self.index] += 1
        if self.height is None:
            self.give_up(np.ones(self.size, dtype=bool), "a flat footprint as a leaf")
            return
        run.kind[self.index] = 0
        run.height[self.index] = self.height

    def geometry_value(self, node):
        if node.args or node.obj != "geometry":
            raise Unsupported(f"{node.obj}.{node.field}")
        footprints = self.run.footprints
        area = footprints.area[self.index]
        if node.field == "area":  # the faces' area: the footprint, or the prism's surface
            if self.height is None:
                return area.copy()
            return 2.0 * area + footprints.perimeter[self.index] * self.height
        if node.field == "volume":
            return area * self.height if self.height is not None else np.zeros(self.size)
        raise Unsupported(f"geometry.{node.field}()")

    def part(self, mask: np.ndarray) -> ShapeBatch:
        """The shapes of ``mask``, with their state (their random streams go on where they are)."""
        part = ShapeBatch(self.run, self.index[mask], {}, self.depth)
        part.attrs = {k: (v[mask] if is_column(v) else v) for k, v in self.attrs.items()}
        part.height = None if self.height is None else self.height[mask]
        part.children = self.children
        part.streams = self.streams  # the same shapes: their generators go on
        return part

    def branch(self, mask: np.ndarray, body, out: list) -> None:
        """The shapes of ``mask`` derived by ``body`` (a compiled body's batch form): a branch
        of ``case`` or of a stochastic choice; shapes it cannot derive fall back alone."""
        part = self.part(mask)
        try:
            body(part, out)
        except Unsupported as exc:
            part.give_up(np.ones(part.size, dtype=bool), str(exc))


def _derive(root: ShapeBatch, rule) -> None:
    """Derive ``root`` from ``rule`` and every successor below, depth first as
    :meth:`Program.derive <shapegen.engine.program.interpreter.Program.derive>` does, each rule
    by the batch form of its compiled body."""
    stack = [(root, rule)]
    while stack:
        batch, rule = stack.pop()
        if rule is None:
            batch.leaf()
            continue
        out: list = []
        try:
            if rule.arity or rule.node.local_variables:
                raise Unsupported("a rule with parameters or local variables")
            rule.body.batch(batch, out)
        except Unsupported as exc:
            batch.give_up(np.ones(batch.size, dtype=bool), str(exc))
            continue
        stack.extend(reversed(out))
