"""How a simulation runs and how its outcome is judged: :class:`SimulationSettings`."""

from __future__ import annotations

__all__ = ["SIMULATION_MARGIN", "SimulationSettings"]

import math
from dataclasses import dataclass

import numpy as np

from shapegen.errors import OptionError, ShapegenError
from shapegen.model.friction import checked_friction
from shapegen.search.defaults import DEFAULT_MARGIN

# The geometric safety margin with which a design is optimized before it is simulated (``shapegen
# simulate --optimize``): the first design the search finds stands exactly on the statics
# boundary, and the simulator's contact compliance tips such a design over (docs/simulation.md,
# "Bundled rules after --optimize"). It is the search's own default, chosen for this reason.
SIMULATION_MARGIN = DEFAULT_MARGIN


@dataclass(frozen=True)
class SimulationSettings:
    """How a simulation runs and how its outcome is judged.

    Attributes
    ----------
    seconds
        Simulated time, s.
    time_step
        Bullet step, s (1/2000 s: at 1/1000 s the 40-voussoir arch of t/R 0.12, which the
        statics says stands, fell or stood by the solver's iteration count; docs/simulation.md).
    solver_iterations
        Contact-solver iterations per step.
    settle
        Settling window at the start, s: the check that the motion has stopped looks at the
        time after it, and ``max_displacement`` is measured from its end.
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
        None (the default) judges each block by its motion relative to its own smallest width
        (docs/simulation.md, "Verdict"). A distance, metres, judges by a fixed bar instead: a
        block fell when, after settling, one of its vertices moved farther than this, or when
        it settled by more than ``settle_tolerance``.
    settle_tolerance
        With a fixed ``tolerance``: a block also fell when it settled by more than this during
        the window, metres.
    sample_rate
        Samples per simulated second of every block's displacement and speed (the evidence in
        the report: displacement over time, peak and final speed).
    frame_rate
        Frames recorded per simulated second for pictures (0 = only the first and last).
    """

    seconds: float = 5.0
    time_step: float = 1.0 / 2000.0
    solver_iterations: int = 50
    settle: float = 0.5
    friction: float | None = None
    shake: float = 0.0
    shake_direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    shake_duration: float = 1.0 / 60.0
    shake_start: float | None = None
    tolerance: float | None = None
    settle_tolerance: float = 1e-2
    sample_rate: float = 20.0
    frame_rate: float = 0.0

    def check(self) -> None:
        """Raise a :class:`ShapegenError` naming the first bad setting."""
        positive = {
            "seconds": self.seconds,
            "time_step": self.time_step,
            "shake_duration": self.shake_duration,
            "tolerance": 1.0 if self.tolerance is None else self.tolerance,
            "settle_tolerance": self.settle_tolerance,
            "sample_rate": self.sample_rate,
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
        if self.friction is not None:
            try:
                checked_friction(self.friction)
            except OptionError as exc:
                raise ShapegenError(f"simulation: {exc}") from None
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
