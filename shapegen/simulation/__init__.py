"""Dynamic check: run a block model in a rigid-body simulator (pybullet, the ``sim`` extra).

>>> from shapegen.simulation import simulate          # doctest: +SKIP
>>> result = simulate(model, seconds=5, shake=4.0)     # doctest: +SKIP
>>> result.verdict, result.max_relative_displacement   # doctest: +SKIP
('collapses', 41.5)

Each block is judged by its own motion relative to its smallest width (it fell, or it is still
moving at the end): :mod:`shapegen.simulation.verdict`. pybullet is imported only when a
simulation runs; without it a :class:`ShapegenError` says how to install it.
"""

from shapegen.simulation.inertia import PrincipalInertia, inertia_tensor, principal_inertia
from shapegen.simulation.run import (
    SimulationFrame,
    SimulationResult,
    moved_model,
    remove_blocks,
    simulate,
)
from shapegen.simulation.settings import SIMULATION_MARGIN, SimulationSettings
from shapegen.simulation.verdict import BlockMotion, MotionTrack, smallest_width

__all__ = [
    "SIMULATION_MARGIN",
    "BlockMotion",
    "MotionTrack",
    "PrincipalInertia",
    "SimulationFrame",
    "SimulationResult",
    "SimulationSettings",
    "inertia_tensor",
    "moved_model",
    "principal_inertia",
    "remove_blocks",
    "simulate",
    "smallest_width",
]
