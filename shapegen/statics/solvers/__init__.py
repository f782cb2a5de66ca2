"""Solver back-ends for the tension-penalty problem; each one a small class in its own module.

``get_backend(name)`` returns a back-end by name: ``"reduced"`` (the structure-exploiting interior
point method, fastest), ``"clarabel"`` (Clarabel on the sparse matrices) or ``"cvxpy"`` (the
readable reference formulation).
"""

from __future__ import annotations

__all__ = ["SolveStatus", "Solution", "Backend", "BACKENDS", "get_backend"]

from shapegen.errors import StaticsError
from shapegen.statics.solvers.base import Backend, Solution, SolveStatus
from shapegen.statics.solvers.clarabel_direct import ClarabelBackend
from shapegen.statics.solvers.cvxpy_reference import CvxpyBackend
from shapegen.statics.solvers.reduced import ReducedBackend

BACKENDS: dict[str, type[Backend]] = {
    "reduced": ReducedBackend,
    "clarabel": ClarabelBackend,
    "cvxpy": CvxpyBackend,
}


def get_backend(name: str) -> Backend:
    """A new back-end instance by name; unknown names raise :class:`StaticsError`."""
    if name not in BACKENDS:
        raise StaticsError(f"solver must be one of auto, {', '.join(BACKENDS)}; got {name!r}")
    return BACKENDS[name]()
