"""How the infeasibility of an analysis changes when the geometry moves: the adjoint gradient.

By the envelope theorem, the optimal value ``y`` of the tension-penalty QP changes to first order
as ``dy = lambda . d(A f + w)``, with the optimal forces ``f`` and equilibrium multipliers
``lambda`` of the one QP already solved: only the equilibrium matrix ``A`` and the wrench ``w``
depend on the geometry. So a search needs one QP per gradient, whatever the number of
parameters; each parameter costs only a rebuild and an assembly of the moved model (no QP).

The moved model must keep the contact topology (same interfaces, same vertex count per
interface); where it does not, :func:`infeasibility_change` returns None and the caller falls
back to a finite difference of whole analyses.

Only what a parameter moves is recomputed (:func:`infeasibility_change` with the base model at
hand, as every search has it): blocks that kept their vertices, and joints between two blocks
shifted by the same translation, keep their terms of ``A f`` (the torques are taken about the
block centroids, which shift with them); the contact polygons of the other joints are found
again among the blocks they join only, and ``w`` changes with the masses. On Cluny a parameter
moves 40-1 072 of its 1 072 blocks but only 3-85 % of its 2 275 joints change.
"""

from __future__ import annotations

__all__ = ["infeasibility_change"]

import numpy as np
from scipy.spatial import cKDTree

from shapegen.errors import ShapegenError
from shapegen.statics.analysis import Analysis
from shapegen.statics.assembly import StaticsProblem, assemble, polygon_centroids
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.options import StaticsOptions


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
        The options ``base`` was analysed with.

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
    x = (base.forces / weight).T.ravel()
    lam = base.multipliers.reshape(-1, 6).copy() / weight
    lam[:, 3:] *= length
    if base.model is not None:
        return _local_change(problem, base.model, moved, x, lam)
    try:
        moved_problem = assemble(
            moved,
            find_interfaces(moved),
            friction=options.friction,
            pyramid=options.pyramid,
            kern=options.kern,
        )
    except ShapegenError:
        return None
    order = _match_vertices(problem, moved_problem)
    if order is None or moved_problem.equality.shape != problem.equality.shape:
        return None
    m = problem.n_vertices
    x_moved = x.reshape(4, m)[:, order].ravel()
    change = moved_problem.residual(x_moved) - problem.residual(x)
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


# A block counts as shifted (not changed) when its vertices moved by one vector to this fraction
# of the model size (round-off of a rebuild is ~1e-16 of it, a parameter step of 1e-6 of a range
# moves vertices by ~1e-7 of it).
_TRANSLATION_REL = 1e-12


def _local_change(problem: StaticsProblem, old, moved, x: np.ndarray, lam: np.ndarray):
    """``lambda . d(A x + w / W)`` recomputing only the joints and weights that moved."""
    old_blocks, new_blocks = old.blocks, moved.blocks
    nb = len(old_blocks)
    if len(new_blocks) != nb or len(old.loads) != len(moved.loads):
        return None
    if any(
        a.structural != b.structural or a.fixed != b.fixed
        for a, b in zip(old_blocks, new_blocks, strict=True)
    ):
        return None
    changed, shift = _block_moves(problem, old_blocks, new_blocks)
    # joints to redo: a changed block, or two sides shifted differently (the ground never moves)
    interfaces = problem.interfaces
    first, second, old_frames, old_centroids = _base_arrays(problem, old_blocks)
    on_block = second >= 0
    second_shift = np.zeros((len(interfaces), 3))
    second_shift[on_block] = shift[second[on_block]]
    second_changed = np.zeros(len(interfaces), bool)
    second_changed[on_block] = changed[second[on_block]]
    redo = changed[first] | second_changed | np.any(shift[first] != second_shift, axis=1)
    redo_index = np.flatnonzero(redo)
    work = 0.0
    if len(redo_index):
        found = _redo_joints(problem, moved, redo_index, first[redo], second[redo])
        if found is None:
            return None
        points, frames, counts = found
        old_vertex = np.flatnonzero(redo[problem.vertex_interface])
        new_owner = np.repeat(np.arange(len(redo_index)), counts)
        order = _match(
            problem.vertex_points[old_vertex],
            points,
            problem.vertex_interface[old_vertex],
            redo_index[new_owner],
        )
        if order is None:
            return None
        local = _local_forces(x, problem.n_vertices)[old_vertex]
        new_centroids = old_centroids + shift
        for k in np.flatnonzero(changed):
            new_centroids[k] = new_blocks[k].centroid
        pairs = np.stack([first, second], axis=1)
        work -= _joint_work(
            problem,
            problem.vertex_points[old_vertex],
            old_frames[problem.vertex_interface[old_vertex]],
            pairs[problem.vertex_interface[old_vertex]],
            old_centroids,
            local,
            lam,
        )
        work += _joint_work(
            problem,
            points,
            frames[new_owner],
            pairs[redo_index[new_owner]],
            new_centroids,
            local[order],
            lam,
        )
    work += _load_work(problem, old, moved, changed, lam)
    return float(work)


def _base_arrays(problem: StaticsProblem, blocks) -> tuple[np.ndarray, ...]:
    """The base's joint blocks, frames and block centroids, kept in ``problem.cache`` for the
    next parameter."""
    if "adjoint" not in problem.cache:
        interfaces = problem.interfaces
        problem.cache["adjoint"] = (
            np.array([i.first for i in interfaces], dtype=np.int64),
            np.array([i.second for i in interfaces], dtype=np.int64),
            np.array([(i.normal, i.tangent1, i.tangent2) for i in interfaces], float).reshape(
                -1, 3, 3
            ),
            np.array([b.centroid for b in blocks], float).reshape(-1, 3),
            np.concatenate([b.vertices for b in blocks]) if blocks else np.zeros((0, 3)),
            np.array([len(b.vertices) for b in blocks], dtype=np.int64),
        )
    return problem.cache["adjoint"][:4]


def _block_moves(problem: StaticsProblem, old_blocks, new_blocks):
    """Per block: changed (its shape, not just its place), and the shift of the others."""
    nb = len(old_blocks)
    changed = np.zeros(nb, bool)
    shift = np.zeros((nb, 3))
    if nb == 0:
        return changed, shift
    _base_arrays(problem, old_blocks)
    old_vertices, counts = problem.cache["adjoint"][4:]
    new_counts = np.array([len(b.vertices) for b in new_blocks], dtype=np.int64)
    changed |= new_counts != counts
    pairs = zip(old_blocks, new_blocks, strict=True)
    changed |= np.array([a.faces is not b.faces and a.faces != b.faces for a, b in pairs])
    if changed.any():  # different vertex counts: compare the others block by block
        for k in np.flatnonzero(~changed):
            d = new_blocks[k].vertices - old_blocks[k].vertices
            changed[k] = np.abs(d - d[0]).max() > _TRANSLATION_REL * problem.length
            shift[k] = 0.0 if changed[k] else d[0]
        return changed, shift
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    d = np.concatenate([b.vertices for b in new_blocks]) - old_vertices
    first_move = d[starts]
    spread = np.abs(d - np.repeat(first_move, counts, axis=0)).max(axis=1)
    changed = np.maximum.reduceat(spread, starts) > _TRANSLATION_REL * problem.length
    shift[~changed] = first_move[~changed]
    return changed, shift


def _local_forces(x: np.ndarray, m: int) -> np.ndarray:
    """``(m, 3)`` per vertex: normal force ``c - s`` and the two friction components."""
    c, s, u, t = x.reshape(4, m)
    return np.stack([c - s, u, t], axis=1)


def _redo_joints(problem: StaticsProblem, moved, redo, first: np.ndarray, second: np.ndarray):
    """The moved contact polygons of the base's joints number ``redo``, which join the blocks
    ``(first, second)``, in that order and scaled by the base's kern: ``(points, frames
    (ni, 3, 3), counts)``, or None when they differ in number or vertex count from the base's."""
    involved = np.unique(np.concatenate([first, second[second >= 0]]))
    wanted = set(zip(first.tolist(), second.tolist(), strict=True))
    try:
        found = find_interfaces(moved, blocks=involved)
    except ShapegenError:
        return None
    found = [i for i in found if (i.first, i.second) in wanted]
    if [(i.first, i.second) for i in found] != list(
        zip(first.tolist(), second.tolist(), strict=True)
    ):
        return None
    counts = np.array([len(i.vertices) for i in found])
    old_counts = np.bincount(problem.vertex_interface, minlength=len(problem.interfaces))
    if not np.array_equal(counts, old_counts[redo]):
        return None
    points = np.concatenate([np.asarray(i.vertices, float) for i in found])
    frames = np.array([(i.normal, i.tangent1, i.tangent2) for i in found], float)
    if problem.kern != 1.0:
        starts = np.concatenate([[0], np.cumsum(counts)])
        owner = np.repeat(np.arange(len(found)), counts)
        centres = polygon_centroids(points, frames[:, 0], starts)[owner]
        points = centres + problem.kern * (points - centres)
    return points, frames, counts


def _match(old_points, new_points, old_owner, new_owner) -> np.ndarray | None:
    """For each new vertex, the old vertex (same joint, nearest) it continues, or None."""
    if len(new_points) != len(old_points):
        return None
    apart = 1e3 * (1.0 + float(np.ptp(old_points)) + float(np.abs(old_points).max()))
    _, nearest = cKDTree(np.column_stack([old_points, old_owner * apart])).query(
        np.column_stack([new_points, new_owner * apart])
    )
    if not np.array_equal(old_owner[nearest], new_owner):
        return None
    if len(np.unique(nearest)) != len(nearest):
        return None
    return nearest


def _joint_work(problem, points, frames, pairs, centroids, local, lam) -> float:
    """``lambda . (A x)`` restricted to the given vertices: ``points`` (k, 3), ``frames`` (k, 3, 3)
    rows n, t1, t2, ``pairs`` (k, 2) the blocks of their joints, ``local`` (k, 3) forces."""
    force = np.einsum("vi,vij->vj", local, frames)  # on ``second``, world axes
    total = 0.0
    for side, sign in ((0, -1.0), (1, 1.0)):
        block = pairs[:, side]
        row = np.full(len(block), -1)
        real = block >= 0
        row[real] = problem.free_index[block[real]]
        on = row >= 0
        lever = (points[on] - centroids[block[on]]) / problem.length
        moment = np.cross(lever, force[on])
        weights = lam[row[on]]
        total += sign * float(
            np.einsum("vi,vi->", weights[:, :3], force[on])
            + np.einsum("vi,vi->", weights[:, 3:], moment)
        )
    return total


def _load_work(problem: StaticsProblem, old, moved, changed: np.ndarray, lam) -> float:
    """``lambda . d(w / W)``: the self-weights (the masses of changed blocks, and ``W``) and
    the point loads."""
    free = problem.free_blocks
    gravity = np.asarray(moved.gravity, float)
    g = float(np.linalg.norm(gravity))
    old_mass = np.array([old.blocks[k].mass for k in free])
    new_mass = old_mass.copy()
    for j in np.flatnonzero(changed[free]):
        new_mass[j] = moved.blocks[free[j]].mass
    old_weight = problem.weight
    new_weight = g * float(new_mass.sum())
    new_weight = new_weight if new_weight > 0 else 1.0
    per_mass = new_mass / new_weight - old_mass / old_weight
    work = float((lam[:, :3] @ gravity) @ per_mass)
    for model, sign, scale in ((old, -1.0, old_weight), (moved, 1.0, new_weight)):
        for point_load in model.loads:
            k = model.index_of(point_load.block)
            row = problem.free_index[k]
            if row < 0:
                continue
            lever = np.asarray(point_load.point, float) - model.blocks[k].centroid
            lever /= problem.length
            force = np.asarray(point_load.force, float) / scale
            work += sign * float(lam[row, :3] @ force + lam[row, 3:] @ np.cross(lever, force))
    return work
