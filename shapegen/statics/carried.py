"""Proofs carried from the last analysis to the next design, a small change away.

- :func:`carried_certificate`: the last forces of a design that stood, moved onto the new
  joints (turned into each joint's frame), tensions dropped, and brought back into equilibrium
  by weighted least-squares steps ``dx = -D A^T (A D A^T)^-1 r`` whose weights ``D`` are the
  squared slacks of each vertex (its compression, its friction reserve): one affine-scaling
  step of an interior point method at a time, with the reduced solver's normal equations. If
  they pass :func:`~shapegen.statics.analysis.certify` (the full analysis's test), the design
  stands.
- :func:`carried_tension_proof`: the last multipliers of a design that did not stand, mended
  into a Farkas certificate that the new one does not stand either.

Both return None when they do not prove the verdict; the caller then judges in full
(:func:`~shapegen.statics.incremental.reanalyze`).
"""

from __future__ import annotations

__all__ = ["carried_certificate", "carried_tension_proof"]

import numpy as np

from shapegen.statics.compression_only import compression_only
from shapegen.statics.interface import Interface
from shapegen.tolerances import Tolerances

# Correction steps tried before the full analysis is run instead (each one factorisation).
CORRECTION_STEPS = 5
# Regularisation of the correction's normal equations, relative to their mean diagonal: keeps
# a block whose every joint is at a limit (zero weight) from making them singular.
CORRECTION_REGULARIZATION = 1e-10
# Mending steps of the carried multipliers before the full analysis is run instead.
PROOF_STEPS = 40
# How far inside the dual cone a mended vertex is lifted, as a share of its |A^T lam|: enough
# that the next step's spread does not push it out again.
PROOF_INSIDE = 1e-3
# The proof's bound must exceed the certificate's tolerance this many times (round-off).
PROOF_FACTOR = 10.0


def _carried_forces(previous, problem, correspondence: np.ndarray) -> np.ndarray:
    """The last analysis's forces moved onto ``problem``'s vertices, ``(4 m,)`` scaled by the
    last weight, zero where a joint has no counterpart with as many vertices."""
    old = previous.problem
    m = problem.n_vertices
    x = np.zeros(4 * m)
    if old is None or not old.n_vertices or not previous.total_weight:
        return x
    # the k-th joint of a pair of blocks is matched with the k-th joint of the same pair before
    # (interfaces come sorted by their pair; the new pairs are renumbered into the old blocks)
    old_pairs = _pairs(old.interfaces)
    new_pairs = _pairs(problem.interfaces)
    known = new_pairs >= 0
    new_pairs[known] = np.asarray(correspondence)[new_pairs[known]]
    lost = (new_pairs[:, 0] < 0) | ((new_pairs[:, 1] < 0) & known[:, 1])
    if not len(old_pairs) or not len(new_pairs):
        return x
    # pairs run from GROUND (-1) up: shifted by 2 they are small positives, one key base
    span = int(max(old_pairs.max(), new_pairs.max())) + 3
    width = max(len(old_pairs), len(new_pairs)) + 1
    old_keys, new_keys = _keyed(old_pairs, span, width), _keyed(new_pairs, span, width)
    position = np.minimum(np.searchsorted(old_keys[:, 0], new_keys[:, 0]), len(old_keys) - 1)
    match = (old_keys[position, 0] == new_keys[:, 0]) & ~lost[new_keys[:, 1]]
    new_joint = new_keys[match, 1]
    old_joint = old_keys[position[match], 1]
    old_starts = np.searchsorted(old.vertex_interface, np.arange(len(old.interfaces) + 1))
    new_starts = np.searchsorted(problem.vertex_interface, np.arange(len(problem.interfaces) + 1))
    found = old_joint >= 0
    size = np.diff(new_starts)[new_joint]
    found[found] &= size[found] == np.diff(old_starts)[old_joint[found]]
    new_joint, old_joint, size = new_joint[found], old_joint[found], size[found]
    if not len(new_joint):
        return x
    # vertex k of a matched joint takes the force of vertex k of its counterpart
    offset = np.arange(int(size.sum())) - np.repeat(np.cumsum(size) - size, size)
    to = np.repeat(new_starts[new_joint], size) + offset
    source = np.repeat(old_starts[old_joint], size) + offset
    frames_old = _frames(old.interfaces)[old.vertex_interface[source]]  # (k, 3, 3) rows n, t1, t2
    frames_new = _frames(problem.interfaces)[problem.vertex_interface[to]]
    forces = previous.forces[source]  # (k, 4) N: compression, tension, friction t1, t2
    local = np.stack([forces[:, 0] - forces[:, 1], forces[:, 2], forces[:, 3]], axis=1)
    world = np.einsum("ki,kij->kj", local, frames_old)
    turned = np.einsum("kij,kj->ki", frames_new, world) / previous.total_weight
    x[to] = np.maximum(turned[:, 0], 0.0)
    x[2 * m + to] = turned[:, 1]
    x[3 * m + to] = turned[:, 2]
    return x


def _pairs(interfaces: list[Interface]) -> np.ndarray:
    """``(ni, 2)`` the blocks of each joint (``GROUND`` for the ground)."""
    return np.array([(f.first, f.second) for f in interfaces], dtype=np.int64).reshape(-1, 2)


def _keyed(pairs: np.ndarray, span: int, width: int) -> np.ndarray:
    """``(ni, 2)``: a sortable key per joint (its pair and its rank within the pair), sorted,
    with the joint's index."""
    order = np.lexsort((np.arange(len(pairs)), pairs[:, 1], pairs[:, 0]))
    ordered = pairs[order]
    start = np.ones(len(ordered), dtype=bool)
    start[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
    first = np.maximum.accumulate(np.where(start, np.arange(len(ordered)), 0))
    rank = np.arange(len(ordered)) - first
    key = ((ordered[:, 0] + 2) * span + (ordered[:, 1] + 2)) * width + rank
    keyed = np.stack([key, order], axis=1)
    return keyed[np.argsort(keyed[:, 0], kind="stable")]


def _frames(interfaces: list[Interface]) -> np.ndarray:
    """``(ni, 3, 3)``: each joint's normal, tangent1 and tangent2 as rows."""
    if not interfaces:
        return np.zeros((0, 3, 3))
    return np.array([(f.normal, f.tangent1, f.tangent2) for f in interfaces], dtype=float)


def carried_certificate(problem, previous, correspondence: np.ndarray, tol: Tolerances):
    """Compression-only forces that hold ``problem`` in equilibrium, found from ``previous``'s
    (an :class:`~shapegen.statics.analysis.Analysis` that stands), or None.

    ``correspondence`` gives, per block of the new model, its block in the previous one (-1
    for none). The forces returned certify (:func:`~shapegen.statics.analysis.certify` at most
    ``tol.feasible_rel``): the design stands.
    """
    from shapegen.statics.certificate import certify
    from shapegen.statics.solvers.normal_equations import NormalEquations

    if not problem.n_vertices or not problem.n_free:
        return None
    m = problem.n_vertices
    x = _carried_forces(previous, problem, correspondence)
    if not np.any(x[:m] > 0):
        return None
    typical = float(np.median(x[:m][x[:m] > 0]))
    equations = None
    try:
        for _ in range(CORRECTION_STEPS + 1):
            x, c, reserve = compression_only(problem, x)
            if certify(problem, x) <= tol.feasible_rel:
                return x
            if equations is None:
                equations = NormalEquations(problem)
            # a joint with nothing carried over may take force as a typical vertex does
            weight_c = np.where(c > 0, c, typical) ** 2
            weight_f = np.where(c > 0, reserve, problem.friction * typical) ** 2
            local = np.zeros((m, 3, 3))
            local[:, 0, 0], local[:, 1, 1], local[:, 2, 2] = weight_c, weight_f, weight_f
            equations.assemble(local, CORRECTION_REGULARIZATION)
            lam = equations.solve(problem.residual(x))
            pull = problem.equality.T @ lam  # (4 m,): A^T lam per variable
            x[:m] -= weight_c * pull[:m]
            x[2 * m : 3 * m] -= weight_f * pull[2 * m : 3 * m]
            x[3 * m :] -= weight_f * pull[3 * m :]
    finally:
        if equations is not None:
            equations.release()
    return None


def _dual_demand(problem, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per vertex, the normal part ``a`` of ``z = A^T lam`` and the least ``a`` that puts
    ``(a, b)`` in the dual cone of the friction cone or pyramid (``mu |b|`` for the cone,
    ``mu max_k b . e_k`` over the dual polygon's edge normals ``e_k`` for a pyramid)."""
    m = problem.n_vertices
    a, b1, b2 = z[:m], z[2 * m : 3 * m], z[3 * m :]
    if problem.second_order:
        return a, problem.friction * np.hypot(b1, b2)
    sides = len(problem.cone) - 1
    angle = np.arctan2(problem.cone[:sides, 2], problem.cone[:sides, 1]) + np.pi / sides
    return a, problem.friction * np.max(np.outer(b1, np.cos(angle)) + np.outer(b2, np.sin(angle)),
                                        axis=1)  # fmt: skip


def carried_tension_proof(problem, previous, correspondence: np.ndarray, tol: Tolerances):
    """A proof that ``problem`` does not stand, from ``previous``'s multipliers (an analysis
    whose design needed tension), or None.

    The proof is a Farkas certificate: equilibrium multipliers ``lam`` with ``A^T lam`` in the
    dual of the friction cone at every vertex and ``lam . w > 0``. For any compression-only
    forces ``x`` the residual ``r = A x + w`` then has ``lam . r >= lam . w``, so its largest
    entry is at least ``lam . w / |lam|_1``; when that exceeds ``PROOF_FACTOR`` times
    ``tol.feasible_rel`` no set of forces certifies the design (the full analysis could not
    find one either). The last multipliers are moved to the new blocks and mended by
    least-squares steps that lift the vertices outside the dual cone a little inside it.
    Returns the bound ``lam . w / |lam|_1``.
    """
    from shapegen.statics.solvers.normal_equations import NormalEquations

    old = previous.problem
    carried = previous.multipliers
    if carried is None and old is not None:
        carried = old.cache.get("proof_multipliers")  # a pending analysis's mended ones
    if carried is None or old is None or not problem.n_vertices:
        return None
    lam = np.zeros((problem.n_free, 6))
    ours = correspondence[problem.free_blocks]
    theirs = np.where(ours >= 0, old.free_index[np.maximum(ours, 0)], -1)
    known = theirs >= 0
    # per block in N and N / m (as dy/dw), into the new problem's scaled rows
    lam[known] = carried.reshape(-1, 6)[theirs[known]] / problem.weight
    lam[:, 3:] *= problem.length
    lam = lam.ravel()
    if not np.any(lam):
        return None
    m = problem.n_vertices
    normal_columns = problem.equality[:, :m]
    equations = NormalEquations(problem)
    try:
        equations.assemble(np.broadcast_to(np.eye(3), (m, 3, 3)), CORRECTION_REGULARIZATION)
        for _ in range(PROOF_STEPS + 1):
            z = problem.equality.T @ lam
            a, least = _dual_demand(problem, z)
            short = least - a
            if np.all(short <= 0.0):
                bound = float(lam @ problem.load) / float(np.abs(lam).sum())
                if bound <= PROOF_FACTOR * tol.feasible_rel:
                    return None
                physical = lam.reshape(-1, 6) * problem.weight
                physical[:, 3:] /= problem.length
                problem.cache["proof_multipliers"] = physical.ravel()
                return bound
            # every vertex at least this deep inside: those at the cone's apex (a joint that
            # carried compression) too, else the next step's spread pushes them out again
            inside = PROOF_INSIDE * float(np.abs(a).max())
            lift = np.maximum(short + inside, 0.0)
            lam = lam + equations.solve(normal_columns @ lift)
    finally:
        equations.release()
    return None
