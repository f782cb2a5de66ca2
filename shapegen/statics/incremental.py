"""Judging a design again after a small change, from the last judgement.

A slider on the design page changes one attr; most blocks of the new model are often exactly
the old ones, and the forces that held the old design nearly hold the new one. What is carried
over, each only where it provably gives the answer of a judgement from scratch:

- **Contacts** (:func:`incremental_interfaces`). A contact depends on its two blocks'
  geometry (vertices, faces, ``structural``, ``fixed``), the ground and the tolerances alone.
  Blocks are matched to the last model's by that geometry (:func:`matched_blocks`); the
  contacts between two unchanged blocks are kept, renumbered, and those of the blocks that
  moved (or are new) are found by :func:`~shapegen.statics.contacts.find_interfaces` on a
  small model of the moved blocks and the blocks whose boxes touch them. The list is the one
  ``find_interfaces`` gives for the whole model, in its order. When the tolerances differ
  (the model's size changed), or most blocks moved, the whole model is searched.
- **The verdict** (:mod:`shapegen.statics.carried`): a design that stood leaves forces that,
  brought back into equilibrium, certify the next one with the full analysis's test; a
  design that needed tension leaves multipliers that, mended, prove the next one needs it
  too. Either way no solve runs for the verdict; a design proven not to stand needs the QP
  alone for its measure, and with ``measure_follows`` not even that at once (:func:`complete`).

When nothing proves the verdict (a large change, a design crossing the boundary or near it),
:func:`~shapegen.statics.analysis.analyze` runs, with the contacts found as above.

The forces of a carried certificate are one valid set of compression-only forces; per-vertex
forces of a statically indeterminate assembly are not unique, so they may differ from a fresh
solve's (the verdict cannot). The measure is then ``0``: the certified forces carry no tension.
"""

from __future__ import annotations

__all__ = [
    "complete",
    "incremental_interfaces",
    "matched_blocks",
    "pending",
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
    """``(n, 3)`` lower and upper corners of the blocks' bounding boxes, m."""
    if not blocks:
        return np.zeros((0, 3)), np.zeros((0, 3))
    vertices = np.concatenate([b.vertices for b in blocks])
    starts = np.cumsum([0] + [len(b.vertices) for b in blocks[:-1]])
    return np.minimum.reduceat(vertices, starts), np.maximum.reduceat(vertices, starts)


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
    from shapegen.statics.carried import carried_certificate, carried_tension_proof
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
                                       timings, decided_by="carried")  # fmt: skip
            return _noted(analysis, options, {**summary, "carried": True})
    else:
        proof = carried_tension_proof(problem, previous, correspondence, tol)
        timings["certify"] = time.perf_counter() - started
        if proof is not None:
            summary = {**summary, "carried": True, "proof": proof}
            if measure_follows:
                pending = Solution(SolveStatus.OPTIMAL, None, None, float("nan"))
                analysis = _build_analysis(model, problem, pending, previous.solver, False,
                                           float("nan"), timings,
                                           decided_by="carried")  # fmt: skip
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
    # the verdict is the carried proof's; the QP gives the measure
    return _build_analysis(model, problem, solution, used, False, y_norm, timings,
                           decided_by="carried")  # fmt: skip


def _noted(analysis, options, summary: dict):
    """The analysis, with its options and what was carried over in its problem's cache
    (``"options"``, ``"incremental"``): the next :func:`reanalyze` reads them."""
    if analysis.problem is not None:
        analysis.problem.cache["options"] = options
        analysis.problem.cache["incremental"] = summary
        # the model's size, read again from its blocks, costs as much as a contact search step
        analysis.problem.cache["tolerances"] = DEFAULT.for_size(analysis.problem.length)
    return analysis
