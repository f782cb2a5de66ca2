"""The simulator's verdict: every block judged by its own motion, relative to its own size.

A standing model is not still in a rigid-body simulator: its contacts carry load through a small
penetration, so it settles by hundredths of a millimetre to a few millimetres in the first
instants and may creep a little after. A collapse moves blocks by their own size and more, and
speeds up. So each non-fixed block is judged on two counts:

- it **fell** when one of its vertices ended farther from where it started than
  ``SIMULATION_FALL_REL`` (10 %) of the block's smallest width;
- it is **still moving** when, over the last quarter of the judged window (the time after the
  settling window), one of its vertices moved more than ``SIMULATION_MOVING_REL`` (1 %) of the
  block's smallest width and that motion is not dying out: it is at least
  ``SIMULATION_DECAY_RATIO`` (half) of the motion over the quarter before. This catches a fall
  that began too late to have gone far by the end of the run.

A block that fell or is still moving *moved*; the model stands when no block moved. The smallest
width of a convex block is the least of its extents along its faces' normals (a box's shortest
side, a voussoir's chord). The thresholds and their measurements are in
:mod:`shapegen.tolerances` and docs/simulation.md ("Verdict").
"""

from __future__ import annotations

__all__ = ["BlockMotion", "BlockShapes", "MotionTrack", "Checkpoints", "judge", "smallest_width"]

from dataclasses import dataclass

import numpy as np

from shapegen.model.block import Block
from shapegen.simulation.settings import SimulationSettings
from shapegen.tolerances import (
    SIMULATION_DECAY_RATIO,
    SIMULATION_FALL_REL,
    SIMULATION_MOVING_REL,
)


def smallest_width(block: Block) -> float:
    """The least extent of ``block`` along any of its face normals, metres."""
    levels = block.vertices @ block.face_normals.T  # (vertices, faces)
    return float((levels.max(axis=0) - levels.min(axis=0)).min())


@dataclass(frozen=True)
class BlockShapes:
    """Every block's vertices padded to one count, to measure all the blocks' motions at once.

    Attributes
    ----------
    vertices
        ``(n, m, 3)`` starting vertices, metres; a block with fewer than ``m`` repeats its first.
    centroids
        ``(n, 3)`` starting centres of mass, metres.
    widths
        ``(n,)`` smallest widths (:func:`smallest_width`), metres.
    """

    vertices: np.ndarray
    centroids: np.ndarray
    widths: np.ndarray

    @classmethod
    def of(cls, blocks: list[Block]) -> BlockShapes:
        count = max(len(block.vertices) for block in blocks)
        vertices = np.empty((len(blocks), count, 3))
        for k, block in enumerate(blocks):
            own = len(block.vertices)
            vertices[k, :own] = block.vertices
            vertices[k, own:] = block.vertices[0]
        return cls(
            vertices=vertices,
            centroids=np.array([block.centroid for block in blocks], float),
            widths=np.array([smallest_width(block) for block in blocks], float),
        )

    def positions(self, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
        """``(n, m, 3)`` vertices moved by each block's rigid map ``x -> R x + t``, metres."""
        return np.einsum("nij,nmj->nmi", rotations, self.vertices) + translations[:, None, :]

    def displacements(
        self,
        rotations: np.ndarray,
        translations: np.ndarray,
        since: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> np.ndarray:
        """``(n,)`` largest distance any vertex of each block moved, metres.

        From the start, or from the pose ``since`` (rotations, translations).
        """
        before = self.vertices if since is None else self.positions(*since)
        moved = self.positions(rotations, translations) - before
        return np.sqrt(np.einsum("nmi,nmi->nm", moved, moved)).max(axis=1)

    def speeds(
        self,
        rotations: np.ndarray,
        translations: np.ndarray,
        linear: np.ndarray,
        angular: np.ndarray,
    ) -> np.ndarray:
        """``(n,)`` largest speed of any vertex of each block, m/s.

        ``linear`` (m/s) and ``angular`` (rad/s), ``(n, 3)`` each, are the velocities of each
        block's centre of mass and its spin, in world axes.
        """
        centres = np.einsum("nij,nj->ni", rotations, self.centroids) + translations
        arms = self.positions(rotations, translations) - centres[:, None, :]
        velocity = linear[:, None, :] + np.cross(angular[:, None, :], arms)
        return np.sqrt(np.einsum("nmi,nmi->nm", velocity, velocity)).max(axis=1)


@dataclass(frozen=True)
class MotionTrack:
    """Every block's motion sampled over the run.

    Attributes
    ----------
    times
        ``(s,)`` simulated seconds of the samples (the first at 0, the last at the end).
    displacements
        ``(s, n)`` largest distance any vertex of each block is from where it started, metres.
    speeds
        ``(s, n)`` largest speed of any vertex of each block, m/s.
    """

    times: np.ndarray
    displacements: np.ndarray
    speeds: np.ndarray


@dataclass(frozen=True)
class Checkpoints:
    """Every block's pose (rotations ``(n, 3, 3)``, translations ``(n, 3)`` metres) at the
    instants the verdict compares: the end of the settling window, the start of the quarter
    before the last, the start of the last quarter, and the end."""

    settled: tuple[np.ndarray, np.ndarray]
    before_tail: tuple[np.ndarray, np.ndarray]
    tail: tuple[np.ndarray, np.ndarray]
    final: tuple[np.ndarray, np.ndarray]


@dataclass(frozen=True)
class BlockMotion:
    """Where one block ended, how it got there, and whether it moved.

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
    width
        Its smallest width (:func:`smallest_width`), metres.
    relative_displacement
        Largest distance any of its vertices ended from where it started, over ``width``.
    peak_speed
        Largest sampled speed of any of its vertices, m/s.
    final_speed
        Largest speed of any of its vertices at the end, m/s.
    tail_motion
        Largest distance any of its vertices moved over the last quarter of the judged window,
        metres.
    earlier_motion
        The same over the quarter before it, metres.
    fell
        ``relative_displacement`` exceeds ``SIMULATION_FALL_REL`` (or, with a fixed tolerance,
        ``max_displacement`` exceeds it or ``settlement`` the settling tolerance).
    still_moving
        ``tail_motion`` exceeds ``SIMULATION_MOVING_REL * width`` and is at least
        ``SIMULATION_DECAY_RATIO * earlier_motion``.
    moved
        It fell or is still moving (never true for a fixed block).
    """

    id: str
    displacement: float
    rotation: float
    max_displacement: float
    settlement: float
    width: float
    relative_displacement: float
    peak_speed: float
    final_speed: float
    tail_motion: float
    earlier_motion: float
    fell: bool
    still_moving: bool
    moved: bool

    def to_report(self) -> dict:
        return {
            "id": self.id,
            "displacement": self.displacement,
            "rotation": self.rotation,
            "max_displacement": self.max_displacement,
            "settlement": self.settlement,
            "width": self.width,
            "relative_displacement": self.relative_displacement,
            "peak_speed": self.peak_speed,
            "final_speed": self.final_speed,
            "tail_motion": self.tail_motion,
            "earlier_motion": self.earlier_motion,
            "fell": self.fell,
            "still_moving": self.still_moving,
            "moved": self.moved,
        }


def judge(
    blocks: list[Block],
    shapes: BlockShapes,
    checkpoints: Checkpoints,
    track: MotionTrack,
    settings: SimulationSettings,
) -> list[BlockMotion]:
    """One :class:`BlockMotion` per block: its evidence and whether it fell or is still moving."""
    rotations, translations = checkpoints.final
    from_start = shapes.displacements(rotations, translations)
    after_settling = shapes.displacements(rotations, translations, since=checkpoints.settled)
    settlement = shapes.displacements(*checkpoints.settled)
    tail = shapes.displacements(rotations, translations, since=checkpoints.tail)
    earlier = shapes.displacements(*checkpoints.tail, since=checkpoints.before_tail)
    relative = from_start / shapes.widths
    if settings.tolerance is None:
        fell = relative > SIMULATION_FALL_REL
    else:
        fell = (after_settling > settings.tolerance) | (settlement > settings.settle_tolerance)
    still_moving = (tail > SIMULATION_MOVING_REL * shapes.widths) & (
        tail >= SIMULATION_DECAY_RATIO * earlier
    )
    centroid_shift = np.linalg.norm(
        np.einsum("nij,nj->ni", rotations, shapes.centroids) + translations - shapes.centroids,
        axis=1,
    )
    turned = np.arccos(np.clip((np.trace(rotations, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0))
    peak = track.speeds.max(axis=0)
    motions = []
    for k, block in enumerate(blocks):
        fell_k = bool(fell[k] and not block.fixed)
        moving_k = bool(still_moving[k] and not block.fixed)
        motions.append(
            BlockMotion(
                id=block.id,
                displacement=float(centroid_shift[k]),
                rotation=float(turned[k]),
                max_displacement=float(after_settling[k]),
                settlement=float(settlement[k]),
                width=float(shapes.widths[k]),
                relative_displacement=float(relative[k]),
                peak_speed=float(peak[k]),
                final_speed=float(track.speeds[-1, k]),
                tail_motion=float(tail[k]),
                earlier_motion=float(earlier[k]),
                fell=fell_k,
                still_moving=moving_k,
                moved=fell_k or moving_k,
            )
        )
    return motions
