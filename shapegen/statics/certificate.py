"""The feasibility certificate of a block analysis, and the forces it is tried on first.

:func:`certify` is the one test that says a design stands: the compression-only part of a set
of forces holds every free block in equilibrium to ``tolerances.feasible_rel``. The analysis
(:func:`~shapegen.statics.analysis.analyze`) tries it on the cheapest forces first, the
least-norm equilibrium (:func:`least_norm_certificate`, one factorisation), and only then on
phase one's; :func:`reserve_certificate` tries the forces of the same design judged with a
reserve, and :func:`nearby_forces` gives a nearby design's forces to start the interior point
from.
"""

from __future__ import annotations

__all__ = ["certify", "least_norm_certificate", "nearby_forces", "reserve_certificate"]

import time

import numpy as np

from shapegen.statics.assembly import StaticsProblem
from shapegen.statics.compression_only import compression_only
from shapegen.statics.solvers import Solution, SolveStatus


def certify(problem: StaticsProblem, x: np.ndarray) -> float:
    """Scaled equilibrium residual of the compression-only part of a solution.

    Tensions are dropped, compressions clipped at zero and each vertex's friction shrunk
    radially into its pyramid (or its cone). Returns the largest entry of ``|A f + w|`` with
    forces divided by ``W`` and torques by ``W L`` (dimensionless); the assembly is certified to
    stand when it is at most ``tolerances.feasible_rel``.
    """
    forces, _, _ = compression_only(problem, x)
    residual = problem.residual(forces)
    return float(np.abs(residual).max()) if residual.size else 0.0


def nearby_forces(nearby, problem: StaticsProblem) -> np.ndarray | None:
    """``nearby``'s scaled forces ``[c, s, u, t]`` when its joints are ``problem``'s (the same
    pairs of blocks in the same order, the same vertex count each), else None."""
    if nearby is None or nearby.problem is None or not np.all(np.isfinite(nearby.forces)):
        return None
    other = nearby.problem
    if other.n_vertices != problem.n_vertices or other.n_free != problem.n_free:
        return None
    if not np.array_equal(other.vertex_interface, problem.vertex_interface):
        return None
    if not np.array_equal(other.vertex_blocks, problem.vertex_blocks):
        return None
    return (nearby.forces / other.weight).T.ravel()


def least_norm_certificate(problem: StaticsProblem, tol, timings: dict) -> Solution | None:
    """The least-norm forces' compression-only part, when the certificate passes it (see
    :mod:`~shapegen.statics.solvers.least_norm`); None sends the analysis on to phase one.
    Its seconds are added to ``timings`` ("solve" for the forces, "certify" for the test)."""
    from shapegen.statics.solvers.least_norm import least_norm_forces

    start = time.perf_counter()
    x = least_norm_forces(problem)
    certifying = time.perf_counter()
    timings["solve"] += certifying - start
    certified = x is not None and certify(problem, x) <= tol.feasible_rel
    timings["certify"] += time.perf_counter() - certifying
    if not certified:
        return None
    forces = compression_only(problem, x)[0]  # what the certificate measured: no tension
    return Solution(SolveStatus.OPTIMAL, forces, np.zeros(6 * problem.n_free), 0.0)


def reserve_certificate(stood, problem: StaticsProblem, tol) -> Solution | None:
    """``stood``'s forces moved to ``problem``'s wider joints, if they certify it."""
    from shapegen.statics.reserve import widened_forces

    start = time.perf_counter()
    narrow = stood.problem
    x = widened_forces(narrow, problem, (stood.forces / narrow.weight).T.ravel())
    certified = x is not None and certify(problem, x) <= tol.feasible_rel
    timings = {"certify": time.perf_counter() - start}
    if not certified:
        return None
    m = problem.n_vertices
    y_norm = float(np.sum(x[m : 2 * m] ** 2))
    return Solution(SolveStatus.OPTIMAL, x, np.zeros(6 * problem.n_free), y_norm, info=timings)
