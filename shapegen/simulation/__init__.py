"""Dynamic check: run a block model in a rigid-body simulator (pybullet, the ``sim`` extra).

>>> from shapegen.simulation import simulate          # doctest: +SKIP
>>> result = simulate(model, seconds=5, shake=4.0)     # doctest: +SKIP
>>> result.verdict, result.max_relative_displacement   # doctest: +SKIP
('collapses', 41.5)

Each block is judged by its own motion relative to its smallest width (it fell, or it is still
moving at the end): :mod:`shapegen.simulation.verdict`. pybullet is imported only when a
simulation runs; without it a :class:`ShapegenError` says how to install it.
"""

from shapegen.lazy_names import lazy_names

_HOMES = {
    "PrincipalInertia": "shapegen.simulation.inertia",
    "inertia_tensor": "shapegen.simulation.inertia",
    "principal_inertia": "shapegen.simulation.inertia",
    "SimulationFrame": "shapegen.simulation.run",
    "SimulationResult": "shapegen.simulation.run",
    "moved_model": "shapegen.simulation.run",
    "remove_blocks": "shapegen.simulation.run",
    "simulate": "shapegen.simulation.run",
    "SIMULATION_MARGIN": "shapegen.simulation.settings",
    "SimulationSettings": "shapegen.simulation.settings",
    "BlockMotion": "shapegen.simulation.verdict",
    "MotionTrack": "shapegen.simulation.verdict",
    "smallest_width": "shapegen.simulation.verdict",
}

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


__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)
