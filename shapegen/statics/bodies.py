"""Rigid bodies: which blocks the statics judge, and which of them move as one.

A body is one rigid body made of one or more convex blocks, its *parts*. Blocks that overlap
in volume are glued into one body (a real CityEngine model overlaps its leaves freely), and
so are the blocks that name the same ``body`` (the convex parts of one non-convex leaf).
A body has one set of six equilibrium rows, about its centroid; the contacts between parts of
one body are not joints. A ``.grammar`` rule's blocks are convex and disjoint: each is its own
body, and the statics are those of the blocks.

What is structure is the user's to say, by label or rule name (:func:`find_bodies`): the
blocks *ignored* are ornaments that ride as load. Each adds its weight (and its point loads)
to the body it rests on: the one it overlaps most, else the one it touches over the largest
area, else (through ornaments it rests on) the body under those, else the body right below
it. An ornament over nothing but the ground or a support loads them, not the structure.

>>> from shapegen.model import Block, Model
>>> ell = Model([Block.box((0, 0, 0), (2, 1, 1)), Block.box((1, 0, 0), (3, 1, 1))])
>>> bodies = find_bodies(ell, [])
>>> bodies.count, bodies.body.tolist()
(1, [0, 0])
"""

from __future__ import annotations

__all__ = ["Bodies", "contacts_and_bodies", "find_bodies", "from_cityengine", "matching_blocks"]

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from shapegen.errors import OptionError, StaticsError, did_you_mean
from shapegen.geometry.graphs import connected_components
from shapegen.model.model import Model
from shapegen.model.packed import pack_blocks
from shapegen.statics.interface import GROUND, Interface
from shapegen.statics.standins import from_cityengine, statics_model
from shapegen.tolerances import Tolerances

NO_HOST = -1
"""The host of an ornament whose weight goes to the ground or a support, not to a body."""


@dataclass
class Bodies:
    """The bodies of a model and the ornaments they carry.

    Attributes
    ----------
    body
        ``(nb,)`` body of each block of ``model.blocks``; -1 for a block outside the statics
        (not structural, or ignored: an ornament).
    count
        Number of bodies; body ``k`` is numbered in the order of its first part.
    fixed
        ``(count,)`` True for a support: a body with a fixed part.
    host
        ``(nb,)`` for an ornament the body that carries its weight (:data:`NO_HOST` when the
        ground or a support does); -1 for the other blocks.
    glued
        Bodies glued from overlapping blocks (at least one overlapping pair among its parts).
    ignored
        Number of ornaments (structural blocks the selection left out).
    selection
        The labels or rule names that selected the structure (``structural``, ``ignore``).
    overlaps
        The common volume of each pair of overlapping parts: counted once in its body's
        weight (a point of three parts is counted twice: overlaps of three are rare and
        small), as a negative mass at its centroid.
    unsupported
        What a body with no chain of contacts to a support is: ``"error"`` (a modelling error,
        :func:`~shapegen.statics.checks.check_support` names it) or ``"ride"`` (an ornament
        fixed to something the statics leave out, an open surface: it rides as load).
    stranded
        Blocks that ride as load because they touch no support (with ``"ride"``).
    """

    body: np.ndarray
    count: int
    fixed: np.ndarray
    host: np.ndarray
    glued: int = 0
    ignored: int = 0
    selection: dict = field(default_factory=dict)
    overlaps: _Overlaps | None = None
    unsupported: str = "error"
    stranded: int = 0

    @property
    def riders(self) -> np.ndarray:
        """Positions of the ornaments whose weight a body carries."""
        return np.flatnonzero(self.host >= 0)

    @property
    def trivial(self) -> bool:
        """True when every block in the statics is its own body and nothing rides: the
        statics are those of the blocks (each its own six rows)."""
        inside = self.body >= 0
        return self.count == int(inside.sum()) and self.ignored == 0

    def parts(self) -> np.ndarray:
        """``(count,)`` number of blocks of each body."""
        inside = self.body >= 0
        return np.bincount(self.body[inside], minlength=self.count)

    def to_report(self) -> dict:
        """Plain JSON values: how many bodies, parts, glued bodies and ornaments."""
        parts = self.parts()
        carried = self.host >= 0
        return {
            "bodies": int(self.count),
            "supports": int(self.fixed.sum()),
            "parts": int(parts.sum()),
            "several_parts": int((parts > 1).sum()),
            "glued": int(self.glued),
            "ignored": int(self.ignored),
            "riding": int(carried.sum()),
            "riding_on_supports": int(self.ignored - carried.sum()),
            "unsupported_riding": int(self.stranded),
            **self.selection,
        }


def _names(value: object, what: str) -> tuple[str, ...]:
    """Labels or rule names from ``"A,B"`` or a sequence of strings."""
    if value is None:
        return ()
    if isinstance(value, str):
        items = value.split(",")
    elif isinstance(value, Sequence) and all(isinstance(v, str) for v in value):
        items = list(value)
    else:
        raise OptionError(f"{what} takes labels or rule names separated by commas; got {value!r}")
    return tuple(dict.fromkeys(item.strip() for item in items if item.strip()))


def matching_blocks(model: Model, names: Sequence[str], what: str) -> np.ndarray:
    """``(nb,)`` True for the blocks with one of ``names`` among their labels or the rules of
    their chain; a name no block has is an error naming the option ``what``."""
    blocks = model.blocks
    match = np.zeros(len(blocks), dtype=bool)
    if not names:
        return match
    wanted = set(names)
    found: set[str] = set()
    for k, block in enumerate(blocks):
        hits = wanted.intersection(block.tags) | wanted.intersection(block.rule_path)
        if hits:
            match[k] = True
            found |= hits
    missing = [name for name in names if name not in found]
    if missing:
        known = sorted(
            {t for b in blocks for t in b.tags} | {r for b in blocks for r in b.rule_path}
        )
        hint = did_you_mean(missing[0], known, most=3, parenthesised=True)
        raise StaticsError(
            f"{what} {missing[0]}: no block has the label or rule {missing[0]!r}{hint}"
        )
    return match


def find_bodies(
    model: Model,
    interfaces: list[Interface],
    tol: Tolerances | None = None,
    *,
    structural: Sequence[str] | str | None = None,
    ignore: Sequence[str] | str | None = None,
    unsupported: str = "error",
    pack=None,
) -> Bodies:
    """The bodies of ``model`` and the ornaments they carry.

    Parameters
    ----------
    model
        The block model.
    interfaces
        Its contacts (``find_interfaces``): an ornament that overlaps no body rests on the one it
        touches over the largest area.
    tol
        Absolute tolerances (default ``model.tolerances()``): two blocks overlap when their
        intersection is above ``penetration_rel`` of the smaller one's volume.
    structural
        Labels or rule names (``"A,B"`` or a list): only the blocks with one of them are
        structure, the other structural blocks ride as load. None or empty: every structural
        block.
    ignore
        Labels or rule names of blocks that ride as load (ornaments), whatever ``structural``
        says.
    unsupported
        ``"error"``: a body with no chain of contacts to a support is left for the checks to
        name; ``"ride"``: its blocks ride as load like ornaments (a real model's ornament
        fixed to a surface the statics leave out).
    pack
        The structural blocks already packed (packed here when None).

    Raises
    ------
    StaticsError
        A name that no block has, or a selection that leaves no block to judge.
    """
    from shapegen.statics.checks import overlapping_pairs, stranded_blocks

    if unsupported not in ("error", "ride"):
        raise OptionError(f"unsupported must be 'error' or 'ride'; got {unsupported!r}")
    tol = model.tolerances() if tol is None else tol
    # overlaps among every structural block: glue between statics blocks, hosts for ornaments
    if pack is None:
        pack = pack_blocks(model.blocks, np.flatnonzero([b.structural for b in model.blocks]))
    pairs, volumes, centroids = overlapping_pairs(model, pack, tol)
    overlaps = (pack.index[pairs] if len(pairs) else pairs, volumes, centroids)
    bodies = _bodies(model, interfaces, structural, ignore, None, overlaps)
    if unsupported == "ride":
        stranded = stranded_blocks(model, interfaces, bodies)
        if len(stranded):
            bodies = _bodies(model, interfaces, structural, ignore, stranded, overlaps)
            bodies.stranded = len(stranded)
        bodies.unsupported = "ride"
    return bodies


def _bodies(model, interfaces, structural, ignore, stranded, overlaps) -> Bodies:
    """:func:`find_bodies` with the ``overlaps`` found (block pairs, volumes, centroids), the
    blocks ``stranded`` (positions) riding as load."""
    blocks = model.blocks
    nb = len(blocks)
    structural_names = _names(structural, "--structural")
    ignore_names = _names(ignore, "--ignore")
    flagged = np.array([b.structural for b in blocks], dtype=bool)
    fixed = np.array([b.fixed for b in blocks], dtype=bool)
    chosen = flagged.copy()
    if structural_names:
        chosen &= matching_blocks(model, structural_names, "--structural")
    if ignore_names:
        chosen &= ~matching_blocks(model, ignore_names, "--ignore")
    chosen |= fixed & flagged  # a support stays a support
    if stranded is not None:
        chosen[stranded] = False
    ornaments = flagged & ~chosen
    if (structural_names or ignore_names) and not (chosen & ~fixed).any():
        raise StaticsError(
            "the structure selected has no block to judge: every free block is ignored"
            + (f" (--structural {','.join(structural_names)})" if structural_names else "")
        )
    selection = {}
    if structural_names:
        selection["structural"] = list(structural_names)
    if ignore_names:
        selection["ignore"] = list(ignore_names)

    pairs, volumes, overlap_centroids = overlaps
    inside_pair = chosen[pairs[:, 0]] & chosen[pairs[:, 1]] if len(pairs) else np.zeros(0, bool)

    # parts of one body: overlapping statics blocks, and blocks naming the same body
    rows = [pairs[inside_pair, 0]]
    cols = [pairs[inside_pair, 1]]
    leaders: dict[str, int] = {}
    for k in np.flatnonzero(chosen).tolist():
        name = blocks[k].body
        if name:
            leader = leaders.setdefault(name, k)
            if leader != k:
                rows.append(np.array([leader]))
                cols.append(np.array([k]))
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    _, component = connected_components(nb, rows, cols)
    body = np.full(nb, -1, dtype=np.int64)
    members = np.flatnonzero(chosen)
    # bodies numbered in the order of their first part: one block each gives the block order
    _, first, inverse = np.unique(component[members], return_index=True, return_inverse=True)
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    body[members] = rank[inverse.ravel()]
    count = len(first)
    body_fixed = np.zeros(count, dtype=bool)
    np.logical_or.at(body_fixed, body[members], fixed[members])
    glued_bodies = np.unique(body[pairs[inside_pair, 0]]) if inside_pair.any() else []
    # the common volume of two parts is one solid: counted once in the body's weight
    inner = np.flatnonzero(inside_pair)
    densities = np.array([b.density for b in blocks]) if nb else np.zeros(0)
    overlaps = _Overlaps(
        body[pairs[inner, 0]],
        -0.5 * (densities[pairs[inner, 0]] + densities[pairs[inner, 1]]) * volumes[inner],
        overlap_centroids[inner],
    )

    host = np.full(nb, -1, dtype=np.int64)
    riders = np.flatnonzero(ornaments)
    if len(riders):
        host[riders] = _hosts(model, body, body_fixed, riders, pairs, volumes, interfaces)
    return Bodies(
        body=body,
        count=count,
        fixed=body_fixed,
        host=host,
        glued=len(glued_bodies),
        ignored=len(riders),
        selection=selection,
        overlaps=overlaps,
    )


@dataclass(frozen=True)
class _Overlaps:
    """The common volumes of overlapping parts, as negative masses: ``body`` (k,), ``mass``
    (k,) kg (negative), ``centroid`` (k, 3) m."""

    body: np.ndarray
    mass: np.ndarray
    centroid: np.ndarray


def _hosts(model, body, body_fixed, riders, pairs, volumes, interfaces) -> np.ndarray:
    """The body carrying each ornament of ``riders`` (:data:`NO_HOST` for the ground or a
    support): the body it overlaps most, else the body it touches over the largest area, else
    the host of the ornament it touches most, else the body right below it."""
    nb = len(model.blocks)
    rider = np.zeros(nb, dtype=bool)
    rider[riders] = True
    overlapped = _largest(nb)  # the body part each ornament overlaps most
    for (a, b), volume in zip(pairs.tolist(), volumes.tolist(), strict=True):
        for mine, other in ((a, b), (b, a)):
            if rider[mine] and body[other] >= 0:
                overlapped.offer(mine, other, volume)
    touched, touched_ornament = _largest(nb), _largest(nb)
    grounded = np.zeros(nb, dtype=bool)  # touches the ground plane
    for interface in interfaces:
        pair = (interface.first, interface.second)
        for mine, other in (pair, pair[::-1]):
            if mine < 0 or not rider[mine]:
                continue
            if other == GROUND:
                grounded[mine] = True
            elif body[other] >= 0:
                touched.offer(mine, other, interface.area)
            elif rider[other]:
                touched_ornament.offer(mine, other, interface.area)
    host = np.full(nb, NO_HOST, dtype=np.int64)
    settled = np.zeros(nb, dtype=bool)
    for choice in (overlapped.best, touched.best):
        take = rider & ~settled & (choice >= 0)
        host[take] = body[choice[take]]
        settled |= take
    settled |= rider & grounded & ~settled  # on the ground: no body carries it
    # ornaments on ornaments: the host of the one they rest on, as far as the chain goes
    below = touched_ornament.best
    for _ in range(len(riders)):
        take = rider & ~settled & (below >= 0)
        take[take] = settled[below[take]]
        if not take.any():
            break
        host[take] = host[below[take]]
        settled |= take
    lone = np.flatnonzero(rider & ~settled)
    if len(lone):
        host[lone] = _below(model, body, lone)
    carried = host >= 0
    host[carried] = np.where(body_fixed[host[carried]], NO_HOST, host[carried])
    return host[riders]


class _largest:
    """Per block, the other block offered with the largest value so far."""

    def __init__(self, n: int):
        self.best = np.full(n, -1, dtype=np.int64)
        self.value = np.zeros(n)

    def offer(self, mine: int, other: int, value: float) -> None:
        if self.best[mine] < 0 or value > self.value[mine]:
            self.best[mine], self.value[mine] = other, value


def _below(model, body, lone) -> np.ndarray:
    """For each ornament of ``lone``, the body whose top lies highest under its base within its
    footprint (:data:`NO_HOST` when none does: it stands on the ground)."""
    parts = np.flatnonzero(body >= 0)
    if len(parts) == 0:
        return np.full(len(lone), NO_HOST, dtype=np.int64)
    pack = pack_blocks(model.blocks, np.concatenate([parts, lone]))
    lower, upper = pack.lower, pack.upper
    n = len(parts)
    out = np.full(len(lone), NO_HOST, dtype=np.int64)
    for k in range(len(lone)):
        low, high = lower[n + k], upper[n + k]
        centre = 0.5 * (low + high)
        under = (
            (lower[:n, 0] <= centre[0])
            & (upper[:n, 0] >= centre[0])
            & (lower[:n, 2] <= centre[2])
            & (upper[:n, 2] >= centre[2])
            & (lower[:n, 1] <= low[1])
        )
        if under.any():
            candidates = np.flatnonzero(under)
            top = np.minimum(upper[candidates, 1], low[1])
            out[k] = body[parts[candidates[np.argmax(top)]]]
    return out


def contacts_and_bodies(model, options, tol, *, interfaces=None, bodies=None,
                        check: bool = True):  # fmt: skip
    """The contacts of ``model`` and its bodies under the structure ``options`` select (each
    found when not given), checked with ``check_model`` when ``check``; ``options`` is a
    :class:`~shapegen.statics.statics_options.StaticsOptions`. Both are those of
    :func:`~shapegen.statics.standins.statics_model` ``(model)``, the model with its
    stand-ins."""
    model = statics_model(model)
    pack = None  # the structural blocks packed once for the contacts, bodies and checks
    if interfaces is None or bodies is None or check:
        pack = pack_blocks(model.blocks, np.flatnonzero([b.structural for b in model.blocks]))
    if interfaces is None:
        from shapegen.statics.contacts import find_interfaces

        interfaces = find_interfaces(model, tol, pack)
    if bodies is None:
        bodies = find_bodies(
            model, interfaces, tol, structural=options.structural, ignore=options.ignore,
            unsupported="ride" if from_cityengine(model) else "error", pack=pack,
        )  # fmt: skip
    if check:
        from shapegen.statics.checks import check_model

        check_model(model, interfaces, tol, bodies, pack)
    return interfaces, bodies
