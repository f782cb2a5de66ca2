"""A primitive's blocks made once per shape and placed by a rigid motion.

A built-in primitive makes its blocks from the scope's size and its parameters only; where the
scope sits and how it is turned enters through ``scope.to_world``. So the blocks of a scope are
those of the same-sized scope at the origin, moved by one rigid motion, and the motion keeps
everything the registry checks (convexity, volume, face orientation). Cluny inserts 169
primitives of 38 distinct shapes; a search step that moves one attr changes only some of them.

The blocks are made in a *canonical* scope: at the origin, with the identity frame, or the
frame that mirrors z when the scope's frame is a reflection (a primitive reverses its faces
there, as :func:`~shapegen.primitives.prism.prism_blocks` does). Placing multiplies the same
local coordinates by the same matrix entries as ``scope.to_world`` would, so a placed block is
the block the primitive would have made in that scope.
"""

from __future__ import annotations

__all__ = ["Template", "canonical_scope", "place", "TemplateCache"]

import threading
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np

from shapegen.model.block import Block, compute_mass_properties
from shapegen.model.scope import Scope

_MIRROR = np.diag([1.0, 1.0, -1.0])


def canonical_scope(scope: Scope) -> Scope:
    """The scope of ``scope``'s size at the origin, with the identity frame or, for a mirrored
    frame, the frame that mirrors z (the same handedness)."""
    frame = _MIRROR if np.linalg.det(scope.rotation) < 0 else np.eye(3)
    return Scope(np.zeros(3), frame, scope.size.copy())


@dataclass(frozen=True)
class Template:
    """The checked blocks of one primitive shape in its canonical scope.

    ``points`` stacks every block's vertices (m, canonical scope coordinates); block ``k`` owns
    rows ``starts[k]:starts[k + 1]``; ``blocks`` are the checked blocks themselves, whose other
    fields (faces, tags, extras...) every placed copy repeats.
    """

    points: np.ndarray
    starts: tuple[int, ...]
    blocks: tuple[Block, ...]
    frame: np.ndarray  # the canonical scope's frame
    volumes: tuple[float, ...]  # m^3: a rigid motion keeps them
    centroids: np.ndarray  # (n, 3) m, canonical scope coordinates: moved with the points

    @classmethod
    def of(cls, blocks: list[Block], canonical: Scope) -> Template:
        sizes = [len(b.vertices) for b in blocks]
        starts = (0, *np.cumsum(sizes).tolist())
        points = np.concatenate([b.vertices for b in blocks]) if blocks else np.zeros((0, 3))
        compute_mass_properties(blocks)
        volumes = tuple(b.volume for b in blocks)
        centroids = np.array([b.centroid for b in blocks]).reshape(-1, 3)
        return cls(points, starts, tuple(blocks), canonical.rotation, volumes, centroids)


def place(template: Template, scope: Scope) -> list[Block]:
    """New blocks: ``template``'s moved into ``scope`` (one matrix product for all of them)."""
    # canonical = local @ frame.T, world = origin + local @ R.T = origin + canonical @ (R frame^T)^T
    # since frame is its own inverse; frame's entries are +-1 and 0, so the products are exact.
    motion = scope.rotation @ template.frame.T
    world = scope.origin + template.points @ motion.T
    centroids = scope.origin + template.centroids @ motion.T
    placed = []
    for k, block in enumerate(template.blocks):
        copy = block.with_vertices(world[template.starts[k] : template.starts[k + 1]])
        # The analysis reads every block's volume and centroid: carry them over, moved.
        copy.__dict__["_mass_properties"] = (template.volumes[k], centroids[k])
        placed.append(copy)
    return placed


class TemplateCache:
    """The most recently used templates, at most ``capacity`` of them (least recent dropped)."""

    def __init__(self, capacity: int = 1024):
        self.capacity = capacity
        self._entries: OrderedDict[tuple, Template] = OrderedDict()
        self._lock = threading.Lock()  # the design page builds from more than one thread

    def get(self, key: tuple) -> Template | None:
        with self._lock:
            template = self._entries.get(key)
            if template is not None:
                self._entries.move_to_end(key)
            return template

    def put(self, key: tuple, template: Template) -> None:
        with self._lock:
            self._entries[key] = template
            self._entries.move_to_end(key)
            while len(self._entries) > self.capacity:
                self._entries.popitem(last=False)

    def clear(self) -> None:
        with self._lock:
            self._entries.clear()

    def __len__(self) -> int:
        return len(self._entries)
