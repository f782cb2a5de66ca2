"""How the infeasibility of an analysis changes when the geometry moves: the adjoint gradient.

By the envelope theorem, the optimal value ``y`` of the tension-penalty QP changes to first order
as ``dy = lambda . d(A f + w)``, with the optimal forces ``f`` and equilibrium multipliers
``lambda`` of the one QP already solved: only the equilibrium matrix ``A`` and the wrench ``w``
depend on the geometry. So a search needs one QP per gradient, whatever the number of
parameters; each parameter costs only a rebuild and an assembly of the moved model (no QP).

The moved model must keep the contact topology (same interfaces, same vertex count per
interface); where it does not, :func:`infeasibility_change` returns None and the caller falls
back to a finite difference of whole analyses. A parameter step moves some blocks only (a
window's width, not the nave's walls): the moved model's contacts are those of the base's
unchanged blocks plus a search around the moved ones
(:func:`~shapegen.statics.incremental.incremental_interfaces`, the list a full search gives).
"""

from __future__ import annotations

__all__ = ["infeasibility_change"]

import numpy as np
from scipy.spatial import cKDTree

from shapegen.errors import ShapegenError
from shapegen.statics.analysis import Analysis
from shapegen.statics.assembly import StaticsProblem, assemble, tilted
from shapegen.statics.incremental import incremental_interfaces
from shapegen.statics.standins import statics_model
from shapegen.statics.statics_options import StaticsOptions
from shapegen.tolerances import DEFAULT


def infeasibility_change(base: Analysis, moved, options: StaticsOptions) -> float | None:
    """First-order change of ``y / W^2`` from ``base``'s model to the ``moved`` model.

    Parameters
    ----------
    base
        The analysis of the original model (it carries the assembled problem, the forces and
        the multipliers).
    moved
        The model after a small change of its geometry (same blocks, slightly moved).
    options
        The options ``base`` was analysed with (a tilt is read from ``base``'s problem, which
        knows the direction it was turned towards).

    Returns
    -------
    float or None
        ``lambda . (A' f + w' - A f - w)`` in units of ``y / W^2``; divide by the parameter step
        for a derivative. None when ``base`` has no multipliers, the moved model cannot be
        assembled, or its contact topology differs.
    """
    problem = base.problem
    if problem is None or base.multipliers is None:
        return None
    weight, length = problem.weight, problem.length
    moved = statics_model(moved)  # with its stand-ins, as the base was judged
    x = (base.forces / weight).T.ravel()
    lam = base.multipliers.reshape(-1, 6).copy() / weight
    lam[:, 3:] *= length
    try:
        interfaces, _ = incremental_interfaces(
            moved,
            DEFAULT.for_size(float(moved.size)),
            base.model,
            problem.cache.get("interfaces"),
            problem.cache.get("tolerances") or DEFAULT.for_size(problem.length),
        )
        bodies = None
        if problem.bodies is not None:  # the moved model's bodies, found as the base's were
            from shapegen.statics.bodies import find_bodies

            bodies = find_bodies(
                moved, interfaces, structural=options.structural, ignore=options.ignore,
                unsupported=problem.bodies.unsupported,
            )  # fmt: skip
            if bodies.count != problem.bodies.count:
                return None
        moved_problem = assemble(
            moved,
            interfaces,
            friction=options.friction,
            pyramid=options.pyramid,
            kern=options.kern,
            bodies=bodies,
        )
        if problem.tilt:  # the same tilt, towards the same direction as the base analysis
            moved_problem = tilted(moved_problem, moved, problem.tilt, problem.azimuth)
    except ShapegenError:
        return None
    order = _match_vertices(problem, moved_problem)  # the same vertices and free blocks
    if order is None:
        return None
    m = problem.n_vertices
    x_moved = x.reshape(4, m)[:, order].ravel()
    # the base's residual, once for every parameter's step (kept with the forces and loads it
    # is of: a tilted copy of the problem shares this cache)
    known = problem.cache.get("residual_of_forces")
    if known is None or known[0] is not base.forces or known[1] is not problem.load:
        known = (base.forces, problem.load, problem.residual(x))
        problem.cache["residual_of_forces"] = known
    change = moved_problem.residual(x_moved) - known[2]
    return float(lam.ravel() @ change)


def _match_vertices(problem: StaticsProblem, moved: StaticsProblem) -> np.ndarray | None:
    """For each vertex of ``moved``, the vertex of ``problem`` it continues (same interface,
    nearest position), or None when the contact topology differs."""
    if moved.n_vertices != problem.n_vertices or moved.n_free != problem.n_free:
        return None
    if not np.array_equal(moved.vertex_interface, problem.vertex_interface):
        return None
    pairs_old = [(i.first, i.second) for i in problem.interfaces]
    pairs_new = [(i.first, i.second) for i in moved.interfaces]
    if pairs_old != pairs_new:
        return None
    if problem.n_vertices == 0:
        return np.zeros(0, int)
    # Neighbouring joints share corners (four course joints meet at a block's corner), so match
    # each vertex among its own interface's vertices only: a fourth coordinate, the interface
    # number times a length far beyond the model, keeps interfaces apart in the search.
    points_old, points_new = problem.vertex_points, moved.vertex_points
    apart = 1e3 * (1.0 + float(np.ptp(points_old)) + float(np.abs(points_old).max()))
    _, nearest = cKDTree(np.column_stack([points_old, problem.vertex_interface * apart])).query(
        np.column_stack([points_new, moved.vertex_interface * apart])
    )
    if not np.array_equal(problem.vertex_interface[nearest], moved.vertex_interface):
        return None
    if len(np.unique(nearest)) != len(nearest):
        return None
    return nearest
