"""Judging a design again after a small change: contacts and a certificate carried from the last.

A slider on the design page changes one attr; most blocks of the new model are often exactly
the old ones, and the forces that held the old design are close to forces that hold the new
one. Two things are carried over, each only where it provably gives the full answer:

- **Contacts** (:func:`incremental_interfaces`). A contact depends on its two blocks'
  geometry (vertices, faces, ``structural``, ``fixed``), the ground and the tolerances alone.
  Blocks are matched to the last model's by that geometry (:func:`matched_blocks`); the
  contacts between two unchanged blocks are kept, renumbered, and those of the blocks that
  moved (or are new) are found by :func:`~shapegen.statics.contacts.find_interfaces` on a
  small model of the moved blocks and the blocks whose boxes touch them. The list is the one
  ``find_interfaces`` gives for the whole model, in its order. When the tolerances differ
  (the model's size changed), or most blocks moved, the whole model is searched.
- **The verdict "stands"** (:func:`carried_certificate`). The last analysis's forces are moved
  to the new joints (matched by their blocks, turned into each joint's frame), tensions
  dropped, and corrected back into equilibrium by a weighted least-squares step
  ``dx = -D A^T (A D A^T)^-1 r`` whose weights ``D`` are the squared slacks of each vertex
  (its compression, its friction reserve), so that a vertex far from its limits takes most of
  the change and a vertex at a limit hardly moves: one affine-scaling step of an interior point
  method, with the normal equations of the reduced solver (same pattern, same factorisation).
  The result is judged by :func:`~shapegen.statics.analysis.certify` with the same tolerance
  as a full analysis: a certified set of forces *is* the proof that the design stands. When it
  does not certify (a large change, a design that no longer stands), the full analysis runs.

The forces of a carried certificate are one valid set of compression-only forces; per-vertex
forces of a statically indeterminate assembly are not unique, so they may differ from a fresh
solve's (the verdict cannot). The measure is then ``0``: the certified forces carry no tension.
"""

from __future__ import annotations

__all__ = [
    "carried_certificate",
    "incremental_interfaces",
    "matched_blocks",
    "reanalyze",
]

import time
from collections import defaultdict

import numpy as np

from shapegen.model.model import Model
from shapegen.statics.contacts import candidate_pairs, find_interfaces
from shapegen.statics.interface import GROUND, Interface
from shapegen.tolerances import DEFAULT, Tolerances

# Above this share of moved blocks, the whole model is searched for contacts at once (the small
# model of the moved blocks and their neighbours would be most of it anyway).
MOVED_SHARE_FULL = 0.6
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


def _geometry_key(block) -> tuple:
    """What a block's contacts depend on: its exact geometry and its support flags."""
    vertices = np.ascontiguousarray(block.vertices, dtype=float)
    return (vertices.shape, vertices.tobytes(), block.faces, bool(block.structural),
            bool(block.fixed))  # fmt: skip


def matched_blocks(previous: list, blocks: list) -> np.ndarray:
    """For each block of ``blocks`` the index of a block of ``previous`` with exactly the same
    geometry and flags, else -1 (each block of ``previous`` is matched at most once, in order).
    """
    waiting: dict[tuple, list[int]] = defaultdict(list)
    for k, block in enumerate(previous):
        waiting[_geometry_key(block)].append(k)
    match = np.full(len(blocks), -1, dtype=np.int64)
    for k, block in enumerate(blocks):
        same = waiting.get(_geometry_key(block))
        if same:
            match[k] = same.pop(0)
    return match


def _boxes(blocks: list) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([np.min(b.vertices, axis=0) for b in blocks]).reshape(-1, 3)
    upper = np.array([np.max(b.vertices, axis=0) for b in blocks]).reshape(-1, 3)
    return lower, upper


def incremental_interfaces(
    model: Model,
    tol: Tolerances,
    previous_model: Model | None,
    previous_interfaces: list[Interface] | None,
    previous_tol: Tolerances | None,
) -> tuple[list[Interface], dict]:
    """The contacts of ``model``, equal to ``find_interfaces(model, tol)``, reusing those of
    ``previous_model`` between blocks that did not change (see the module docstring).

    Returns the interfaces and a summary: ``moved`` (blocks new or changed), ``searched``
    (blocks given to ``find_interfaces``), ``reused`` (contacts kept).
    """
    blocks = model.blocks
    if (
        previous_model is None
        or previous_interfaces is None
        or previous_tol != tol
        or previous_model.ground != model.ground
    ):
        return find_interfaces(model, tol), {"moved": len(blocks), "searched": len(blocks),
                                             "reused": 0}  # fmt: skip
    match = matched_blocks(previous_model.blocks, blocks)
    structural = np.array([b.structural for b in blocks], dtype=bool)
    moved = (match < 0) & structural
    renumber = np.full(len(previous_model.blocks), -1, dtype=np.int64)
    renumber[match[match >= 0]] = np.flatnonzero(match >= 0)
    fixed = np.array([b.fixed for b in blocks], dtype=bool)
    kept = []
    for face in previous_interfaces:
        first = int(renumber[face.first])
        second = GROUND if face.second == GROUND else int(renumber[face.second])
        if first < 0 or (face.second != GROUND and second < 0):
            continue  # a block of it changed or is gone: found again below
        if second >= 0 and not fixed[second] and second < first:
            # the two blocks swapped places in the model's order: the contact's "first" would
            # be the other block, so both are searched again
            moved[[first, second]] = True
            continue
        kept.append((first, second, face))
    n_moved = int(moved.sum())
    if n_moved > MOVED_SHARE_FULL * max(int(structural.sum()), 1):
        return find_interfaces(model, tol), {"moved": n_moved, "searched": len(blocks),
                                             "reused": 0}  # fmt: skip
    searched = moved.copy()
    if n_moved:
        candidates = np.flatnonzero(structural)
        lower, upper = _boxes([blocks[k] for k in candidates])
        pairs = candidates[candidate_pairs(lower, upper, padding=2.0 * tol.planar)]
        touching = moved[pairs[:, 0]] | moved[pairs[:, 1]]
        searched[pairs[touching].ravel()] = True
    sub = np.flatnonzero(searched)
    found = []
    if len(sub):
        part = Model(blocks=[blocks[k] for k in sub], ground=model.ground)
        for face in find_interfaces(part, tol):
            first = int(sub[face.first])
            second = GROUND if face.second == GROUND else int(sub[face.second])
            if moved[first] or (second != GROUND and moved[second]):
                found.append((first, second, _renumbered(face, first, second)))
    kept = [(a, b, f if (f.first, f.second) == (a, b) else _renumbered(f, a, b))
            for a, b, f in kept if not (moved[a] or (b != GROUND and moved[b]))]  # fmt: skip
    # find_interfaces sorts by (first, second) and, within a pair, by its faces' numbers, whose
    # order a renumbering keeps; the contacts of one pair all come from one of the two lists
    merged = sorted(kept + found, key=lambda item: (item[0], item[1]))
    summary = {"moved": n_moved, "searched": len(sub), "reused": len(kept)}
    return [face for _, _, face in merged], summary


def _renumbered(face: Interface, first: int, second: int) -> Interface:
    return Interface(first, second, face.normal, face.tangent1, face.tangent2, face.vertices)


# ------------------------------------------------------------------------- the carried certificate
def _carried_forces(previous, problem, correspondence: np.ndarray) -> np.ndarray:
    """The last analysis's forces moved onto ``problem``'s vertices, ``(4 m,)`` scaled by the
    last weight, zero where a joint has no counterpart with as many vertices."""
    old = previous.problem
    m = problem.n_vertices
    x = np.zeros(4 * m)
    if old is None or not old.n_vertices or not previous.total_weight:
        return x
    # the k-th joint of a pair of blocks is matched with the k-th joint of the same pair before
    counterpart: dict[tuple[int, int, int], int] = {}
    seen: dict[tuple[int, int], int] = defaultdict(int)
    for k, face in enumerate(old.interfaces):
        pair = (face.first, face.second)
        counterpart[(*pair, seen[pair])] = k
        seen[pair] += 1
    seen.clear()
    pairs = []
    for k, face in enumerate(problem.interfaces):
        second = int(correspondence[face.second]) if face.second >= 0 else face.second
        pair = (int(correspondence[face.first]), second)
        j = counterpart.get((*pair, seen[pair]), -1)
        seen[pair] += 1
        pairs.append((k, j))
    new_joint, old_joint = np.array(pairs, dtype=np.int64).reshape(-1, 2).T
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


def _frames(interfaces: list[Interface]) -> np.ndarray:
    """``(ni, 3, 3)``: each joint's normal, tangent1 and tangent2 as rows."""
    if not interfaces:
        return np.zeros((0, 3, 3))
    return np.array([(f.normal, f.tangent1, f.tangent2) for f in interfaces], dtype=float)


def _into_cone(problem, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``x`` with tensions dropped, compressions clipped and friction shrunk radially into the
    pyramid or the cone (as :func:`~shapegen.statics.analysis.certify` does); and each vertex's
    compression and friction reserve (the correction's slacks)."""
    m = problem.n_vertices
    c, _, u, t = x.reshape(4, m)
    c = np.maximum(c, 0.0)
    if problem.second_order:
        capacity = problem.friction * c
        demand = np.hypot(u, t)
    else:
        sides = problem.cone[:-1]
        capacity = -sides[0, 0] * c
        demand = np.max(np.outer(u, sides[:, 1]) + np.outer(t, sides[:, 2]), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        shrink = np.where(demand > capacity, capacity / np.where(demand > 0, demand, 1.0), 1.0)
    shrink = np.clip(shrink, 0.0, 1.0)
    u, t = u * shrink, t * shrink
    reserve = np.maximum(capacity - demand * shrink, 0.0)
    return np.concatenate([c, np.zeros(m), u, t]), c, reserve


def carried_certificate(problem, previous, correspondence: np.ndarray, tol: Tolerances):
    """Compression-only forces that hold ``problem`` in equilibrium, found from ``previous``'s
    (an :class:`~shapegen.statics.analysis.Analysis` that stands), or None.

    ``correspondence`` gives, per block of the new model, its block in the previous one (-1
    for none). The forces returned certify (:func:`~shapegen.statics.analysis.certify` at most
    ``tol.feasible_rel``): the design stands.
    """
    from shapegen.statics.analysis import certify
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
            x, c, reserve = _into_cone(problem, x)
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


def reanalyze(model, options, previous, *, check: bool = True, measure_follows: bool = False):
    """:func:`~shapegen.statics.analysis.analyze` ``(model, options)``, reusing the contacts
    of ``previous`` (the last :class:`~shapegen.statics.analysis.Analysis`, with the same
    options) where blocks did not change, and its forces (when it stood) or its multipliers
    (when it did not) as the proof of the verdict; see the module docstring. The verdict is
    the full analysis's.

    When the design is proven not to stand, only the QP is solved, for the measure; with
    ``measure_follows`` not even that: the analysis returned is *pending* (its verdict proven,
    its measure nan, no forces; ``problem.cache["incremental"]["pending"]``) and
    :func:`complete` gives the full one.
    """
    from shapegen.statics.analysis import _build_analysis, analyze
    from shapegen.statics.assembly import assemble
    from shapegen.statics.bodies import contacts_and_bodies
    from shapegen.statics.solvers import Solution, SolveStatus
    from shapegen.statics.standins import statics_model

    model = statics_model(model)
    if previous is None or previous.problem is None or options.tilted or not options.backends():
        return _noted(analyze(model, options, check=check), options, {"carried": False})
    started = time.perf_counter()
    size = float(model.size)
    tol = DEFAULT.for_size(size)
    old_model = previous.model
    old_tol = previous.problem.cache.get("tolerances") or DEFAULT.for_size(float(old_model.size))
    interfaces, summary = incremental_interfaces(
        model, tol, old_model, previous.problem.cache.get("interfaces"), old_tol
    )
    interfaces, bodies = contacts_and_bodies(model, options, tol, interfaces=interfaces,
                                             check=check)  # fmt: skip
    timings = {"interfaces": time.perf_counter() - started}
    if not bodies.trivial:  # rows per body: judged in full
        analysis = analyze(model, options, interfaces=interfaces, bodies=bodies, check=False)
        analysis.timings["interfaces"] = timings["interfaces"]
        return _noted(analysis, options, {**summary, "carried": False})
    started = time.perf_counter()
    problem = assemble(model, interfaces, friction=options.friction, pyramid=options.pyramid,
                       kern=float(options.kern), length=size)  # fmt: skip
    problem.cache["interfaces"] = interfaces
    problem.cache["bodies"] = bodies
    timings["assembly"] = time.perf_counter() - started
    started = time.perf_counter()
    if len(old_model.blocks) == len(model.blocks):
        correspondence = np.arange(len(model.blocks))
    else:
        correspondence = matched_blocks(old_model.blocks, model.blocks)
    if previous.feasible:
        x = carried_certificate(problem, previous, correspondence, tol)
        timings["certify"] = time.perf_counter() - started
        if x is not None:
            timings["solve"] = 0.0
            solution = Solution(SolveStatus.OPTIMAL, x, np.zeros(6 * problem.n_free), 0.0)
            analysis = _build_analysis(model, problem, solution, previous.solver, True, 0.0,
                                       timings)  # fmt: skip
            return _noted(analysis, options, {**summary, "carried": True})
    else:
        proof = carried_tension_proof(problem, previous, correspondence, tol)
        timings["certify"] = time.perf_counter() - started
        if proof is not None:
            summary = {**summary, "carried": True, "proof": proof}
            if measure_follows:
                pending = Solution(SolveStatus.OPTIMAL, None, None, float("nan"))
                analysis = _build_analysis(model, problem, pending, previous.solver, False,
                                           float("nan"), timings)  # fmt: skip
                return _noted(analysis, options, {**summary, "pending": True})
            return _noted(_tension_analysis(model, problem, options, timings), options, summary)
    analysis = analyze(model, options, interfaces=interfaces, bodies=bodies, check=False)
    analysis.timings["interfaces"] = timings["interfaces"]
    analysis.timings["certify"] += timings.get("certify", 0.0)
    return _noted(analysis, options, {**summary, "carried": False})


def pending(analysis) -> bool:
    """True for an analysis of :func:`reanalyze` whose measure follows (:func:`complete`)."""
    problem = analysis.problem if analysis is not None else None
    return bool(problem is not None and problem.cache.get("incremental", {}).get("pending"))


def complete(analysis):
    """The full analysis of a :func:`pending` one (its QP solved: the measure, the forces,
    the multipliers); any other analysis as it is."""
    if not pending(analysis):
        return analysis
    problem = analysis.problem
    options = problem.cache["options"]
    timings = dict(analysis.timings)
    summary = {**problem.cache["incremental"], "pending": False}
    return _noted(_tension_analysis(analysis.model, problem, options, timings), options, summary)


def _tension_analysis(model, problem, options, timings: dict):
    """The analysis of a design proven not to stand: the QP alone gives its measure."""
    from shapegen.statics.analysis import _build_analysis
    from shapegen.statics.solvers import SolveRequest, get_backend

    started = time.perf_counter()
    solution, used = None, None
    for name in options.backends():
        solution, used = get_backend(name).take(SolveRequest()).solve(problem), name
        if solution.status.solved or solution.status.value == "infeasible":
            break
    timings = {**timings, "solve": time.perf_counter() - started}
    m = problem.n_vertices
    if solution.x is not None and solution.status.solved:
        y_norm = float(np.sum(solution.x[m : 2 * m] ** 2))
    else:
        y_norm = float("inf") if solution.status.value == "infeasible" else float("nan")
    return _build_analysis(model, problem, solution, used, False, y_norm, timings)


def _noted(analysis, options, summary: dict):
    """The analysis, with its options and what was carried over in its problem's cache
    (``"options"``, ``"incremental"``): the next :func:`reanalyze` reads them."""
    if analysis.problem is not None:
        analysis.problem.cache["options"] = options
        analysis.problem.cache["incremental"] = summary
        # the model's size, read again from its blocks, costs as much as a contact search step
        analysis.problem.cache["tolerances"] = DEFAULT.for_size(analysis.problem.length)
    return analysis
