"""Run a block model in the rigid-body simulator and judge whether it stands.

Settling: Bullet's contacts carry load only after a small penetration and a few steps of the
iterative solver, so during the first instants every block sinks into its joints by hundredths
of a millimetre and a long chain of joints (an arch, a tall pier) settles by up to about a
millimetre, then stays still. The first ``settle`` seconds (default 0.5 s) are therefore a settling
window: displacements are measured from the pose at its end, and the motion within it is reported
separately as the *settlement*.

The verdict: a non-fixed block *moved* when, after settling, one of its vertices ended farther than
``tolerance`` from where it was, or when it settled by more than
``settle_tolerance`` (default 1 cm: a block that falls within the window counts too); the model
*stands* when no block moved, and *collapses* otherwise. The default tolerance is 1 mm, or 1/10 000
of the model's height when that is larger (:func:`default_tolerance`): Bullet's contact solver lets
models of 18 m and more drift by 1-2 mm over 5 s whatever their margin of safety
(docs/simulation.md, "Tolerance"), so a fixed millimetre would judge the solver's noise, not the
building, there.

Ground shake (``shake``, m/s): the ground receives a velocity change ``shake`` along
``shake_direction`` spread evenly over ``shake_duration`` (1/60 s, the seed paper's impulse), i.e.
an acceleration ``a = shake / shake_duration``. The run is carried out in the ground's frame: there
the ground and the fixed blocks stay put and every block feels the inertial force ``-m a`` during
the shake, which is the same as gravity changed to ``g - a`` for that interval. This is exact for
rigid bodies (d'Alembert's principle), needs no moving static body in Bullet, and reports
displacements relative to the ground, which is what a verdict about the building needs.
"""

from __future__ import annotations

__all__ = [
    "SimulationSettings",
    "BlockMotion",
    "SimulationFrame",
    "SimulationResult",
    "simulate",
    "remove_blocks",
    "moved_model",
    "default_tolerance",
    "TOLERANCE",
    "TOLERANCE_PER_HEIGHT",
]

import difflib
import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace

import numpy as np

from shapegen.errors import ShapegenError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation.world import World

# The geometric safety margin with which a design is optimized before it is simulated (``shapegen
# simulate --optimize``): the first design the search finds stands exactly on the statics
# boundary, and the simulator's contact compliance tips such a design over (docs/simulation.md,
# "Bundled rules after --optimize").
SIMULATION_MARGIN = 0.1

# The default tolerance of the verdict: 1 mm (the bar of the reference 1 m arch), or this fraction
# of the model's height when that is larger (the simulator's drift is largest on tall models).
TOLERANCE = 1e-3
TOLERANCE_PER_HEIGHT = 1e-4


@dataclass(frozen=True)
class SimulationSettings:
    """How a simulation runs and how its outcome is judged.

    Attributes
    ----------
    seconds
        Simulated time, s.
    time_step
        Bullet step, s (1/1000 s; see docs/simulation.md for the measured creep).
    solver_iterations
        Contact-solver iterations per step.
    settle
        Settling window at the start, s; displacements are measured from its end.
    friction
        Coulomb coefficient of every contact; None takes the model's (dimensionless).
    shake
        Velocity change of the ground, m/s (0 = no shake; the seed paper uses 4).
    shake_direction
        Horizontal direction of the shake (normalised; default +x).
    shake_duration
        Seconds over which the ground's velocity changes (the seed paper: 1/60 s).
    shake_start
        Simulated time at which the shake begins, s (None: at the end of the settling window).
    tolerance
        A block moved when, after settling, one of its vertices moved farther than this, metres
        (None: :func:`default_tolerance` of the model).
    settle_tolerance
        A block also moved when it settled by more than this during the window, metres.
    frame_rate
        Frames recorded per simulated second for pictures (0 = only the first and last).
    """

    seconds: float = 5.0
    time_step: float = 1.0 / 1000.0
    solver_iterations: int = 100
    settle: float = 0.5
    friction: float | None = None
    shake: float = 0.0
    shake_direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    shake_duration: float = 1.0 / 60.0
    shake_start: float | None = None
    tolerance: float | None = None
    settle_tolerance: float = 1e-2
    frame_rate: float = 0.0

    def check(self) -> None:
        """Raise a :class:`ShapegenError` naming the first bad setting."""
        positive = {
            "seconds": self.seconds,
            "time_step": self.time_step,
            "shake_duration": self.shake_duration,
            "tolerance": TOLERANCE if self.tolerance is None else self.tolerance,
            "settle_tolerance": self.settle_tolerance,
        }
        for name, value in positive.items():
            if not (math.isfinite(value) and value > 0):
                raise ShapegenError(f"simulation: {name} must be a positive number, got {value}")
        for name, value in {
            "shake": self.shake,
            "shake_start": 0.0 if self.shake_start is None else self.shake_start,
            "settle": self.settle,
            "frame_rate": self.frame_rate,
        }.items():
            if not (math.isfinite(value) and value >= 0):
                raise ShapegenError(f"simulation: {name} must be a number >= 0, got {value}")
        if self.friction is not None and not (math.isfinite(self.friction) and self.friction >= 0):
            raise ShapegenError(f"simulation: friction must be >= 0, got {self.friction}")
        if self.solver_iterations < 1:
            raise ShapegenError("simulation: solver_iterations must be at least 1")
        if self.time_step > self.seconds:
            raise ShapegenError("simulation: time_step must not exceed the simulated seconds")
        if self.settle >= self.seconds:
            raise ShapegenError(
                f"simulation: the settling window ({self.settle:g} s) must be shorter than the"
                f" run ({self.seconds:g} s)"
            )
        direction = np.asarray(self.shake_direction, float)
        if direction.shape != (3,) or not np.all(np.isfinite(direction)):
            raise ShapegenError("simulation: shake_direction must be three finite numbers")
        if self.shake > 0 and np.linalg.norm(direction) == 0:
            raise ShapegenError("simulation: shake_direction must not be zero")


@dataclass(frozen=True)
class BlockMotion:
    """Where one block ended, relative to where it started.

    Attributes
    ----------
    id
        The block's id.
    displacement
        Distance its centroid moved from the start to the end, metres.
    rotation
        Angle it turned through from the start to the end, radians.
    max_displacement
        Largest distance any of its vertices moved from the end of settling to the end, metres.
    settlement
        Largest distance any of its vertices moved during the settling window, metres.
    moved
        ``max_displacement`` exceeds the tolerance or ``settlement`` the settling tolerance
        (never true for a fixed block).
    """

    id: str
    displacement: float
    rotation: float
    max_displacement: float
    settlement: float
    moved: bool

    def to_report(self) -> dict:
        return {
            "id": self.id,
            "displacement": self.displacement,
            "rotation": self.rotation,
            "max_displacement": self.max_displacement,
            "settlement": self.settlement,
            "moved": self.moved,
        }


@dataclass(frozen=True)
class SimulationFrame:
    """Every block's rigid motion ``x -> R x + t`` since the start, at one time.

    Attributes
    ----------
    time
        Simulated seconds.
    rotations
        ``(n, 3, 3)``.
    translations
        ``(n, 3)``, metres.
    """

    time: float
    rotations: np.ndarray
    translations: np.ndarray


@dataclass
class SimulationResult:
    """The outcome of :func:`simulate`.

    Attributes
    ----------
    model
        The simulated model (after ``remove``), in its starting position.
    removed
        Ids of the blocks taken out before the run.
    motions
        One :class:`BlockMotion` per block of ``model``.
    frames
        Recorded frames, the first at t = 0 and the last at the end.
    settled
        The frame at the end of the settling window.
    settings
        The settings used (with the friction actually used filled in).
    seconds
        Simulated seconds.
    wall_seconds
        Wall-clock seconds of the run (set-up included).
    """

    model: Model
    removed: list[str]
    motions: list[BlockMotion]
    frames: list[SimulationFrame]
    settled: SimulationFrame
    settings: SimulationSettings
    seconds: float
    wall_seconds: float
    steps: int = 0

    @property
    def max_displacement(self) -> float:
        """Largest distance any vertex of any block moved, metres."""
        return max((m.max_displacement for m in self.motions), default=0.0)

    @property
    def settlement(self) -> float:
        """Largest distance any vertex moved during the settling window, metres."""
        return max((m.settlement for m in self.motions), default=0.0)

    @property
    def moved_blocks(self) -> int:
        """How many blocks moved more than the tolerance."""
        return sum(m.moved for m in self.motions)

    @property
    def verdict(self) -> str:
        """``"stands"`` when no block moved more than the tolerance, else ``"collapses"``."""
        return "collapses" if self.moved_blocks else "stands"

    @property
    def stands(self) -> bool:
        return self.verdict == "stands"

    @property
    def speed(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.seconds / self.wall_seconds if self.wall_seconds > 0 else math.inf

    def final_model(self) -> Model:
        """The model with every block in its final position."""
        return moved_model(self.model, self.frames[-1])

    def to_report(self) -> dict:
        """A JSON-ready summary (units: metres, radians, seconds)."""
        settings = self.settings
        return {
            "verdict": self.verdict,
            "max_displacement": self.max_displacement,
            "moved_blocks": self.moved_blocks,
            "settlement": self.settlement,
            "tolerance": settings.tolerance,
            "settle": settings.settle,
            "settle_tolerance": settings.settle_tolerance,
            "blocks": len(self.motions),
            "removed": list(self.removed),
            "simulated_seconds": self.seconds,
            "wall_seconds": self.wall_seconds,
            "time_step": settings.time_step,
            "solver_iterations": settings.solver_iterations,
            "friction": settings.friction,
            "shake": settings.shake,
            "shake_direction": list(settings.shake_direction),
            "shake_duration": settings.shake_duration,
            "shake_start": settings.shake_start,
            "engine": "pybullet",
            "per_block": [m.to_report() for m in self.motions],
        }


# ---------------------------------------------------------------------------------- removal
def remove_blocks(model: Model, names: Iterable[str]) -> tuple[Model, list[str]]:
    """``model`` without the blocks whose id or label (tag) is one of ``names``.

    Returns the new model (blocks shared, not copied) and the removed ids. A name that matches no
    block is an error listing close ids and labels.
    """
    names = list(names)
    if not names:
        return model, []
    doomed: set[int] = set()
    for name in names:
        hits = {k for k, b in enumerate(model.blocks) if b.id == name or name in b.tags}
        if not hits:
            known = sorted({b.id for b in model.blocks} | {t for b in model.blocks for t in b.tags})
            close = difflib.get_close_matches(name, known, n=3)
            hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
            raise ShapegenError(f"--remove {name}: no block has the id or label {name!r}{hint}")
        doomed |= hits
    kept = [b for k, b in enumerate(model.blocks) if k not in doomed]
    removed = [model.blocks[k].id for k in sorted(doomed)]
    kept_ids = {b.id for b in kept}
    loads = [load for load in model.loads if load.block in kept_ids]
    return replace(model, blocks=kept, loads=loads, metadata=dict(model.metadata)), removed


def moved_model(model: Model, frame: SimulationFrame) -> Model:
    """``model`` with each block moved by its rigid motion in ``frame``."""
    blocks: list[Block] = [
        block.transformed(rotation, translation)
        for block, rotation, translation in zip(
            model.blocks, frame.rotations, frame.translations, strict=True
        )
    ]
    return replace(model, blocks=blocks, loads=[], metadata=dict(model.metadata))


# ---------------------------------------------------------------------------------- running
def simulate(
    model: Model,
    settings: SimulationSettings | None = None,
    *,
    remove: Iterable[str] = (),
    progress: Callable[[float, float], None] | None = None,
    **overrides,
) -> SimulationResult:
    """Drop ``model`` into pybullet, run it, and measure how far every block moved.

    Parameters
    ----------
    model
        The block model (its gravity, ground, loads and friction are used).
    settings
        A :class:`SimulationSettings`; keyword ``overrides`` replace single fields
        (``simulate(model, seconds=2, shake=4)``).
    remove
        Ids or labels of blocks to delete before the run (a broken column).
    progress
        Called now and then with (simulated seconds done, total).

    Returns
    -------
    SimulationResult
        Verdict, per-block motions and recorded frames.

    Raises
    ------
    ShapegenError
        pybullet missing, a bad setting, an unknown ``remove`` name, or no blocks left.
    """
    settings = replace(settings or SimulationSettings(), **overrides)
    settings.check()
    if settings.tolerance is None:
        settings = replace(settings, tolerance=default_tolerance(model))
    model, removed = remove_blocks(model, remove)
    if not model.blocks:
        raise ShapegenError("simulation: the model has no blocks left to simulate")
    model.validate()
    friction = float(model.friction if settings.friction is None else settings.friction)
    shake_start = settings.settle if settings.shake_start is None else settings.shake_start
    settings = replace(settings, friction=friction, shake_start=shake_start)
    started = time.perf_counter()
    steps = max(1, round(settings.seconds / settings.time_step))
    settle_steps = round(settings.settle / settings.time_step)
    shake = _shake_steps(settings)
    load_index = [(model.index_of(load.block), load) for load in model.loads]
    frame_every = (
        max(1, round(1.0 / (settings.frame_rate * settings.time_step)))
        if settings.frame_rate > 0
        else steps + 1
    )
    with World(model, friction, settings.time_step, settings.solver_iterations) as world:
        frames = [_frame(world, 0.0)]
        settled = frames[0]
        shaking = False
        report_every = max(1, steps // 100)
        for step in range(steps):
            active = shake[0] <= step < shake[1]
            if active != shaking:
                world.set_gravity(model.gravity - shake[2] if active else model.gravity)
                shaking = active
            for index, load in load_index:
                world.apply_force(index, load.force, load.point)
            world.step()
            done = step + 1
            if done == settle_steps:
                settled = _frame(world, done * settings.time_step)
            if done % frame_every == 0 and done < steps:
                frames.append(_frame(world, done * settings.time_step))
            if progress is not None and done % report_every == 0:
                progress(done * settings.time_step, steps * settings.time_step)
        frames.append(_frame(world, steps * settings.time_step))
    motions = _motions(model, settled, frames[-1], settings)
    return SimulationResult(
        model=model,
        removed=removed,
        motions=motions,
        frames=frames,
        settled=settled,
        settings=settings,
        seconds=steps * settings.time_step,
        wall_seconds=time.perf_counter() - started,
        steps=steps,
    )


def default_tolerance(model: Model) -> float:
    """The verdict's default tolerance for ``model``, metres.

    1 mm (:data:`TOLERANCE`), or :data:`TOLERANCE_PER_HEIGHT` times the model's height when that
    is larger. The height is the extent of its blocks along y (up), from the ground when the model
    has one.
    """
    if not model.blocks:
        return TOLERANCE
    levels = np.concatenate([block.vertices[:, 1] for block in model.blocks])
    bottom = float(levels.min()) if model.ground is None else min(float(levels.min()), model.ground)
    return max(TOLERANCE, TOLERANCE_PER_HEIGHT * (float(levels.max()) - bottom))


def _shake_steps(settings: SimulationSettings) -> tuple[int, int, np.ndarray]:
    """First and past-the-end step of the shake, and the ground's acceleration (m/s^2)."""
    if settings.shake <= 0:
        return 0, 0, np.zeros(3)
    direction = np.asarray(settings.shake_direction, float)
    direction = direction / np.linalg.norm(direction)
    first = round(settings.shake_start / settings.time_step)
    count = max(1, round(settings.shake_duration / settings.time_step))
    # The velocity change is exactly ``shake`` over the whole steps actually simulated.
    acceleration = direction * settings.shake / (count * settings.time_step)
    return first, first + count, acceleration


def _frame(world: World, time_s: float) -> SimulationFrame:
    rotations, translations = world.poses()
    return SimulationFrame(time=float(time_s), rotations=rotations, translations=translations)


def _motions(
    model: Model, settled: SimulationFrame, final: SimulationFrame, settings: SimulationSettings
) -> list[BlockMotion]:
    motions = []
    for k, block in enumerate(model.blocks):
        start = block.vertices
        at_settle = start @ settled.rotations[k].T + settled.translations[k]
        at_end = start @ final.rotations[k].T + final.translations[k]
        shift = float(np.linalg.norm(at_end - at_settle, axis=1).max())
        settlement = float(np.linalg.norm(at_settle - start, axis=1).max())
        rotation = final.rotations[k]
        centroid_shift = float(
            np.linalg.norm(rotation @ block.centroid + final.translations[k] - block.centroid)
        )
        cosine = np.clip((np.trace(rotation) - 1.0) / 2.0, -1.0, 1.0)
        moved = shift > settings.tolerance or settlement > settings.settle_tolerance
        motions.append(
            BlockMotion(
                id=block.id,
                displacement=centroid_shift,
                rotation=float(np.arccos(cosine)),
                max_displacement=shift,
                settlement=settlement,
                moved=bool(moved and not block.fixed),
            )
        )
    return motions
