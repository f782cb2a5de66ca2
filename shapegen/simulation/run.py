"""Run a block model in the rigid-body simulator and judge whether it stands.

Settling: Bullet's contacts carry load only after a small penetration and a few steps of the
iterative solver, so during the first instants every block sinks into its joints by hundredths
of a millimetre and a long chain of joints (an arch, a tall pier) settles by up to a millimetre
or two, then stays still or creeps slowly. The first ``settle`` seconds (default 0.5 s) are a
settling window: the check that the motion has stopped looks only at the time after it, and the
motion within it is reported separately as the *settlement*.

The verdict (:mod:`shapegen.simulation.verdict`): every block is judged by its own motion relative
to its own smallest width; it fell when it ended more than 10 % of that width from where it
started, and it is still moving when it moved more than 1 % of it over the last quarter of the
run and that motion is not dying out. The model *stands* when no block fell or is still moving,
and *collapses* otherwise. The evidence (each block's relative displacement, its peak and final
speed, the displacement over time) is in the result and its report.

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
    "SIMULATION_MARGIN",
    "SimulationSettings",
    "BlockMotion",
    "SimulationFrame",
    "SimulationResult",
    "simulate",
    "remove_blocks",
    "moved_model",
]

import math
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace

import numpy as np

from shapegen.errors import ShapegenError, did_you_mean
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.simulation.settings import SIMULATION_MARGIN, SimulationSettings
from shapegen.simulation.verdict import BlockMotion, BlockShapes, Checkpoints, MotionTrack, judge
from shapegen.simulation.world import World
from shapegen.tolerances import (
    SIMULATION_DECAY_RATIO,
    SIMULATION_FALL_REL,
    SIMULATION_MOVING_REL,
)

# How many blocks the report names as the ones that moved most.
LARGEST_MOVERS = 5


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
        One :class:`BlockMotion` per block of ``model``: its evidence and whether it moved.
    frames
        Recorded frames, the first at t = 0 and the last at the end.
    settled
        The frame at the end of the settling window.
    track
        Every block's displacement and speed sampled ``sample_rate`` times per simulated second.
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
    track: MotionTrack
    settings: SimulationSettings
    seconds: float
    wall_seconds: float
    steps: int = 0

    @property
    def max_displacement(self) -> float:
        """Largest distance any vertex of any block moved after the settling window, metres."""
        return max((m.max_displacement for m in self.motions), default=0.0)

    @property
    def max_relative_displacement(self) -> float:
        """Largest distance any vertex ended from its start, over its block's smallest width."""
        return max((m.relative_displacement for m in self._judged), default=0.0)

    @property
    def settlement(self) -> float:
        """Largest distance any vertex moved during the settling window, metres."""
        return max((m.settlement for m in self.motions), default=0.0)

    @property
    def peak_speed(self) -> float:
        """Largest sampled speed of any vertex of any non-fixed block, m/s."""
        return max((m.peak_speed for m in self._judged), default=0.0)

    @property
    def final_speed(self) -> float:
        """Largest speed of any vertex of any non-fixed block at the end, m/s."""
        return max((m.final_speed for m in self._judged), default=0.0)

    @property
    def moved_blocks(self) -> int:
        """How many blocks fell or are still moving."""
        return sum(m.moved for m in self.motions)

    @property
    def fallen_blocks(self) -> int:
        """How many blocks fell."""
        return sum(m.fell for m in self.motions)

    @property
    def moving_blocks(self) -> int:
        """How many blocks are still moving at the end."""
        return sum(m.still_moving for m in self.motions)

    @property
    def verdict(self) -> str:
        """``"stands"`` when no block fell or is still moving, else ``"collapses"``."""
        return "collapses" if self.moved_blocks else "stands"

    @property
    def stands(self) -> bool:
        return self.verdict == "stands"

    @property
    def speed(self) -> float:
        """Simulated seconds per wall-clock second."""
        return self.seconds / self.wall_seconds if self.wall_seconds > 0 else math.inf

    @property
    def _judged(self) -> list[BlockMotion]:
        """The motions of the non-fixed blocks."""
        return [m for m, b in zip(self.motions, self.model.blocks, strict=True) if not b.fixed]

    def largest_movers(self, count: int = LARGEST_MOVERS) -> list[BlockMotion]:
        """The ``count`` non-fixed blocks that moved most relative to their size, largest first."""
        return sorted(self._judged, key=lambda m: -m.relative_displacement)[:count]

    def displacement_over_time(self) -> dict[str, list[float]]:
        """The sampled track, largest over the blocks: ``time`` (s), ``max_displacement`` (m,
        from the start), ``max_relative_displacement`` and ``max_speed`` (m/s)."""
        judged = np.array([not b.fixed for b in self.model.blocks])
        track = self.track
        if not judged.any():
            zeros = [0.0] * len(track.times)
            return {"time": track.times.tolist(), "max_displacement": zeros,
                    "max_relative_displacement": zeros, "max_speed": zeros}  # fmt: skip
        widths = np.array([m.width for m in self.motions])[judged]
        moved = track.displacements[:, judged]
        return {
            "time": track.times.tolist(),
            "max_displacement": moved.max(axis=1).tolist(),
            "max_relative_displacement": (moved / widths).max(axis=1).tolist(),
            "max_speed": track.speeds[:, judged].max(axis=1).tolist(),
        }

    def explanation(self) -> str:
        """One line saying why the model stands or collapses."""
        if self.settings.tolerance is None:
            fall = f"moved more than {SIMULATION_FALL_REL:.0%} of its smallest width"
        else:
            fall = f"moved more than {self.settings.tolerance * 1000:.3g} mm after settling"
        if self.stands:
            return (
                f"no block {fall} (largest: {self.max_relative_displacement:.2%}) and none is"
                " still moving"
            )
        parts = []
        if self.fallen_blocks:
            parts.append(f"{_blocks(self.fallen_blocks)} fell (each {fall})")
        if self.moving_blocks:
            parts.append(f"{_blocks(self.moving_blocks)} still moving at the end")
        return "; ".join(parts)

    def final_model(self) -> Model:
        """The model with every block in its final position."""
        return moved_model(self.model, self.frames[-1])

    def to_report(self) -> dict:
        """A JSON-ready summary (units: metres, radians, seconds, m/s)."""
        settings = self.settings
        return {
            "verdict": self.verdict,
            "explanation": self.explanation(),
            "criterion": {
                "fall_relative_displacement": SIMULATION_FALL_REL,
                "moving_relative_displacement": SIMULATION_MOVING_REL,
                "decay_ratio": SIMULATION_DECAY_RATIO,
                "tolerance": settings.tolerance,
                "settle_tolerance": settings.settle_tolerance,
            },
            "max_relative_displacement": self.max_relative_displacement,
            "max_displacement": self.max_displacement,
            "peak_speed": self.peak_speed,
            "final_speed": self.final_speed,
            "moved_blocks": self.moved_blocks,
            "fallen_blocks": self.fallen_blocks,
            "moving_blocks": self.moving_blocks,
            "largest_movers": [m.to_report() for m in self.largest_movers()],
            "displacement_over_time": self.displacement_over_time(),
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
            "sample_rate": settings.sample_rate,
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
            hint = did_you_mean(name, known, most=3)
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
    model, removed = remove_blocks(model, remove)
    if not model.blocks:
        raise ShapegenError("simulation: the model has no blocks left to simulate")
    model.validate()
    friction = float(model.friction if settings.friction is None else settings.friction)
    shake_start = settings.settle if settings.shake_start is None else settings.shake_start
    settings = replace(settings, friction=friction, shake_start=shake_start)
    started = time.perf_counter()
    steps = max(1, round(settings.seconds / settings.time_step))
    shake = _shake_steps(settings)
    load_index = [(model.index_of(load.block), load) for load in model.loads]
    with World(model, friction, settings.time_step, settings.solver_iterations) as world:
        recorder = _Recorder(world, BlockShapes.of(model.blocks), settings, steps)
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
            recorder.after_step(step + 1)
            if progress is not None and (step + 1) % report_every == 0:
                progress((step + 1) * settings.time_step, steps * settings.time_step)
    track = recorder.track()
    motions = judge(model.blocks, recorder.shapes, recorder.checkpoints(), track, settings)
    return SimulationResult(
        model=model,
        removed=removed,
        motions=motions,
        frames=recorder.frames,
        settled=recorder.poses[recorder.settle_step],
        track=track,
        settings=settings,
        seconds=steps * settings.time_step,
        wall_seconds=time.perf_counter() - started,
        steps=steps,
    )


class _Recorder:
    """Records, while the world runs, the frames for pictures, the poses the verdict compares
    (:class:`~shapegen.simulation.verdict.Checkpoints`) and the sampled motion track."""

    def __init__(self, world: World, shapes: BlockShapes, settings: SimulationSettings, steps):
        self.world, self.shapes, self.steps = world, shapes, steps
        self.time_step = settings.time_step
        self.settle_step = min(round(settings.settle / settings.time_step), steps - 1)
        # The judged window (after settling) ends in two equal quarters compared by the verdict.
        quarter = max(1, round((steps - self.settle_step) / 4))
        self.tail_step = max(0, steps - quarter)
        self.before_tail_step = max(0, steps - 2 * quarter)
        self.frame_every = (
            max(1, round(1.0 / (settings.frame_rate * settings.time_step)))
            if settings.frame_rate > 0
            else steps + 1
        )
        self.sample_every = max(1, round(1.0 / (settings.sample_rate * settings.time_step)))
        self.poses: dict[int, SimulationFrame] = {}
        self.frames: list[SimulationFrame] = []
        self._times: list[float] = []
        self._displacements: list[np.ndarray] = []
        self._speeds: list[np.ndarray] = []
        self.after_step(0)

    def after_step(self, done: int) -> None:
        """Record what is due after ``done`` steps."""
        last = done == self.steps
        pictured = done == 0 or last or done % self.frame_every == 0
        checkpoint = done in (self.settle_step, self.before_tail_step, self.tail_step) or last
        sampled = done % self.sample_every == 0 or last
        if not (pictured or checkpoint or sampled):
            return
        frame = _frame(self.world, done * self.time_step)
        if pictured:
            self.frames.append(frame)
        if checkpoint:
            self.poses[done] = frame
        if sampled:
            linear, angular = self.world.velocities()
            self._times.append(frame.time)
            self._displacements.append(
                self.shapes.displacements(frame.rotations, frame.translations)
            )
            self._speeds.append(
                self.shapes.speeds(frame.rotations, frame.translations, linear, angular)
            )

    def checkpoints(self) -> Checkpoints:
        def pose(step: int) -> tuple[np.ndarray, np.ndarray]:
            return self.poses[step].rotations, self.poses[step].translations

        return Checkpoints(
            settled=pose(self.settle_step),
            before_tail=pose(self.before_tail_step),
            tail=pose(self.tail_step),
            final=pose(self.steps),
        )

    def track(self) -> MotionTrack:
        return MotionTrack(
            times=np.array(self._times),
            displacements=np.array(self._displacements),
            speeds=np.array(self._speeds),
        )


def _blocks(count: int) -> str:
    return f"{count} block" if count == 1 else f"{count} blocks"


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
