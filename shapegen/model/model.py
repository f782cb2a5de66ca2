"""The mass model: blocks, point loads, gravity, ground and friction."""

from __future__ import annotations

__all__ = ["Model", "PointLoad", "GRAVITY", "STANDARD_GRAVITY"]

from dataclasses import dataclass, field

import numpy as np

from shapegen.errors import GeometryError, OptionError
from shapegen.model.appearance import Surface
from shapegen.model.block import Block, compute_mass_properties
from shapegen.model.friction import checked_friction
from shapegen.model.validation import validate_blocks
from shapegen.tolerances import DEFAULT, Tolerances

STANDARD_GRAVITY = 9.81
"""The acceleration of gravity, m/s^2: the project's one value."""

GRAVITY = (0.0, -STANDARD_GRAVITY, 0.0)  # m/s^2, y up


@dataclass
class PointLoad:
    """A live load: ``force`` (N) applied at ``point`` (m) on the block named ``block``."""

    block: str
    force: np.ndarray
    point: np.ndarray

    def __post_init__(self) -> None:
        self.force = np.asarray(self.force, dtype=float).reshape(3)
        self.point = np.asarray(self.point, dtype=float).reshape(3)


@dataclass
class Model:
    """A rigid-block assembly.

    Attributes
    ----------
    blocks
        The blocks; ids are unique.
    loads
        Point loads (live loads) in addition to self-weight.
    gravity
        Acceleration of gravity, m/s^2 (default 9.81 along -y).
    ground
        Height of the ground plane y = ground (m), or None for no ground (then only fixed
        blocks support).
    friction
        Coulomb friction coefficient mu (dimensionless) of every joint.
    metadata
        Free-form information carried to reports (attrs, reports from a grammar...).
    surfaces
        Leaves that are drawn and exported but are not blocks (faces, open or non-convex
        meshes), each with the reason the statics leave it out.
    """

    blocks: list[Block] = field(default_factory=list)
    loads: list[PointLoad] = field(default_factory=list)
    gravity: np.ndarray = field(default_factory=lambda: np.array(GRAVITY))
    ground: float | None = 0.0
    friction: float = 0.7
    metadata: dict = field(default_factory=dict)
    surfaces: list[Surface] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.gravity = np.asarray(self.gravity, dtype=float).reshape(3)
        for k, block in enumerate(self.blocks):
            if not block.id:
                block.id = f"b{k}"

    @property
    def size(self) -> float:
        """Bounding-box diagonal of all blocks, metres (1 for an empty model)."""
        if not self.blocks:
            return 1.0
        # One array of all vertices: a min and max a block would cost more than the arithmetic.
        vertices = np.concatenate([b.vertices for b in self.blocks])
        if not len(vertices):  # blocks without corners (cut to nothing): refused by validation
            return 1.0
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        return float(np.linalg.norm(hi - lo)) or 1.0

    def tolerances(self, base: Tolerances = DEFAULT) -> Tolerances:
        """Tolerances scaled to this model's size."""
        return base.for_size(self.size)

    @property
    def total_weight(self) -> float:
        """Weight of the structural, non-fixed blocks, N."""
        g = float(np.linalg.norm(self.gravity))
        compute_mass_properties(self.blocks)
        return g * sum(b.mass for b in self.blocks if b.structural and not b.fixed)

    @property
    def volume(self) -> float:
        """Total block volume, m^3."""
        compute_mass_properties(self.blocks)
        return float(sum(b.volume for b in self.blocks))

    def index_of(self, block_id: str) -> int:
        """Position of the block named ``block_id``."""
        for k, block in enumerate(self.blocks):
            if block.id == block_id:
                return k
        raise GeometryError(f"no block named {block_id!r}")

    def validate(self) -> None:
        """Raise a :class:`GeometryError` naming the first bad block, duplicate id or load.

        A model validated before and unchanged since (the same blocks with the same ids,
        vertices, faces and densities, the same loads, gravity, ground and friction) is not
        checked again: a model read from a file is validated when read and again before it is
        judged.
        """
        state = self._validation_state()
        if _same_state(self.__dict__.get("_validated"), state):
            return
        self._checks()
        self.__dict__["_validated"] = state

    def __getstate__(self) -> dict:
        # The record of the last validation is a copy of every vertex: not worth pickling.
        state = dict(self.__dict__)
        state.pop("_validated", None)
        return state

    def _validation_state(self) -> tuple:
        """What :meth:`validate` looks at, to tell whether it changed: the blocks, faces and
        loads by identity and value, all vertices as one array (an in-place edit shows)."""
        blocks = [(b, b.id, b.faces, b.density) for b in self.blocks]
        vertices = (
            np.concatenate([b.vertices for b in self.blocks]) if self.blocks else np.empty((0, 3))
        )
        loads = [(ld.block, ld.force.tobytes(), ld.point.tobytes()) for ld in self.loads]
        scalars = (self.gravity.tobytes(), self.ground, self.friction)
        return scalars, blocks, loads, vertices

    def _checks(self) -> None:
        tol = self.tolerances()
        if not np.all(np.isfinite(self.gravity)):
            raise GeometryError("gravity must be finite numbers")
        if self.ground is not None and not np.isfinite(self.ground):
            raise GeometryError("ground height must be a finite number or null")
        try:
            checked_friction(self.friction)
        except OptionError as exc:  # a model that cannot be: its geometry's error
            raise GeometryError(str(exc)) from None
        seen: set[str] = set()
        duplicate = None
        for k, block in enumerate(self.blocks):
            if block.id in seen:
                duplicate = k
                break
            seen.add(block.id)
        # The blocks before a duplicate id are checked first, as a loop over the blocks would.
        validate_blocks(self.blocks[:duplicate], tol)
        if duplicate is not None:
            name = self.blocks[duplicate].id
            raise GeometryError(f"two blocks are named {name!r}; block ids must be unique")
        for load in self.loads:
            if load.block not in seen:
                raise GeometryError(f"a load names block {load.block!r}, which does not exist")
            if not (np.all(np.isfinite(load.force)) and np.all(np.isfinite(load.point))):
                raise GeometryError(f"the load on block {load.block!r} must be finite numbers")


def _same_state(before: tuple | None, now: tuple) -> bool:
    """True when two :meth:`Model._validation_state` values are the same (NaN never is)."""
    if before is None:
        return False
    return before[:3] == now[:3] and np.array_equal(before[3], now[3])
