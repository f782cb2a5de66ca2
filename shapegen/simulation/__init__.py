"""Dynamic check: run a block model in a rigid-body simulator (pybullet, the ``sim`` extra).

>>> from shapegen.simulation import simulate          # doctest: +SKIP
>>> result = simulate(model, seconds=5, shake=4.0)     # doctest: +SKIP
>>> result.verdict, result.max_displacement            # doctest: +SKIP
('collapses', 3.2)

pybullet is imported only when a simulation runs; without it a :class:`ShapegenError` says how to
install it.
"""

from shapegen.simulation.inertia import PrincipalInertia, inertia_tensor, principal_inertia
from shapegen.simulation.run import (
    SIMULATION_MARGIN,
    TOLERANCE,
    TOLERANCE_PER_HEIGHT,
    BlockMotion,
    SimulationFrame,
    SimulationResult,
    SimulationSettings,
    default_tolerance,
    moved_model,
    remove_blocks,
    simulate,
)

__all__ = [
    "SIMULATION_MARGIN",
    "TOLERANCE",
    "TOLERANCE_PER_HEIGHT",
    "BlockMotion",
    "PrincipalInertia",
    "SimulationFrame",
    "SimulationResult",
    "SimulationSettings",
    "default_tolerance",
    "inertia_tensor",
    "moved_model",
    "principal_inertia",
    "remove_blocks",
    "simulate",
]
