"""Block-level normal equations ``M = A D A^T`` of the reduced interior point method.

``D`` (the inverse of the objective Hessian plus barrier) is block-diagonal per vertex, so ``M``
has one 6x6 block per pair of free blocks that share an interface, plus the diagonal blocks.
Its sparsity pattern never changes between iterations (nor between solves of problems with the
same interfaces), so the pattern, the scatter map from per-interface contributions and the
fill-reducing ordering are computed once and kept in ``problem.cache``. Each iteration only
recomputes the values and factors them. A parameter search rebuilds the problem for every
design, but its block graph rarely changes: the symbolic part (ordering, pattern, scatter map
and the Cholesky factorisation's analysis) of the last few block graphs is kept by the graph's
contents and reused.

Ordering: approximate minimum degree on the *block* graph (one node per free block, expanded to
its six rows), computed once with SuiteSparse's AMD: cvxopt's where it is installed (the
default), else QDLDL's (``qdldl`` is a dependency of shapegen); the two are the same code and
give the same order.

Factorisation: CHOLMOD's supernodal Cholesky through ``cvxopt``
(:mod:`~shapegen.statics.solvers.cholmod`), of the lower triangle in this order, analysed once
per pattern and kept with it, so that phase one, the QP and every iteration only refactor
numerically; 4-5 times faster than SuperLU at 1 000 and 10 000 blocks
(docs/journal/architecture.md). MKL
PARDISO (:mod:`~shapegen.statics.solvers.pardiso`, the optional ``shapegen[pardiso]``) factors
1.7-2 times faster still; where it is installed, ``"auto"`` takes it. Without cvxopt (or
should the Cholesky factorisation stop on a matrix that is not numerically positive definite),
SuperLU factors the symmetrically pre-permuted matrix with the natural column order and no
pivoting, an LDL^T-like factorisation of the SPD matrix.
"""

from __future__ import annotations

__all__ = ["NormalEquations", "NormalPattern"]

import collections
import dataclasses
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from shapegen.errors import OptionError
from shapegen.statics.solvers import cholmod, pardiso
from shapegen.statics.solvers.symmetric_factor import SymmetricFactor
from shapegen.tolerances import DIVISION_FLOOR

if TYPE_CHECKING:
    import scipy.sparse as sp

FACTORIZATIONS = ("auto", "cholmod", "pardiso", "superlu")
# the Cholesky factorisations kept with a pattern, and the error each raises for a matrix it
# refuses (then SuperLU factors that matrix)
_LIBRARIES = {"cholmod": cholmod, "pardiso": pardiso}
_CHOLESKY: dict[str, type[SymmetricFactor]] = {
    "cholmod": cholmod.CholmodFactor,
    "pardiso": pardiso.PardisoFactor,
}
_REFUSED = (cholmod.CholmodError, pardiso.PardisoError)
# "auto" takes the first installed: MKL PARDISO factors 1.7-2x faster than CHOLMOD here, but
# its 691 MB come only with the optional shapegen[pardiso]; cvxopt's CHOLMOD comes with shapegen
_AUTO_ORDER = ("pardiso", "cholmod")


def check_factorization(factorization: str) -> None:
    """Refuse, in one line, a factorisation that is unknown or whose library is not installed
    (``"auto"`` and ``"superlu"`` are always there)."""
    if factorization not in FACTORIZATIONS:
        raise OptionError(
            f"factorization must be one of {', '.join(FACTORIZATIONS)}; got {factorization!r}"
        )
    if factorization == "pardiso" and not pardiso.available():
        raise OptionError(
            "factorization 'pardiso' needs Intel MKL, which is not installed"
            " (pip install 'shapegen[pardiso]'), or use 'auto' (CHOLMOD)"
        )
    if factorization == "cholmod" and not cholmod.available():
        raise OptionError(
            "factorization 'cholmod' needs cvxopt, which is not installed"
            " (pip install cvxopt), or use 'auto' or 'superlu'"
        )


class _Analysis:
    """The Cholesky factorisations' symbolic analyses of one block graph (one per library),
    each lent to one solve at a time."""

    def __init__(self):
        self.factors: dict[str, object] = {}
        self.locks = {name: threading.Lock() for name in _CHOLESKY}

    def borrow(self, method: str, indptr: np.ndarray, indices: np.ndarray):
        """The shared factor object of ``method``, or a private one while another solve holds
        it."""
        make = _CHOLESKY[method]
        lock = self.locks[method]
        if not lock.acquire(blocking=False):
            return make(indptr, indices)
        factor = self.factors.get(method)
        if factor is None:
            try:
                factor = self.factors[method] = make(indptr, indices)
            except BaseException:
                lock.release()
                raise
        return factor

    def give_back(self, method: str, factor) -> None:
        factor.release_factor()
        if factor is self.factors.get(method):
            self.locks[method].release()
        else:
            factor.close()


@dataclass
class NormalPattern:
    """Symbolic data of ``M``: the upper triangle's CSR pattern in the permuted order and the
    scatter map.

    ``target[k]`` is the position in the permuted upper-triangle ``data`` array that the
    ``source[k]``-th entry of the flattened per-interface ``(ni, 12, 12)`` contributions adds to
    (entries below the diagonal are not computed: ``M`` is symmetric).
    """

    size: int
    indptr: np.ndarray
    indices: np.ndarray
    target: np.ndarray
    source: np.ndarray
    diagonal: np.ndarray
    permutation: np.ndarray  # row i of the permuted matrix is row permutation[i] of M
    interface_starts: np.ndarray
    vertex_frames: np.ndarray  # (m, 6, 3) K_v = [R; skew(q_v) R], q_v lever from the first vertex
    interface_shifts: np.ndarray  # (ni, 12, 6) sign_s [I 0; skew(d_s) I] for both sides s
    analysis: _Analysis | None = None  # the Cholesky analyses, shared by every user of the graph

    def full_matrix(self, data: np.ndarray) -> sp.csc_matrix:
        """The whole symmetric (permuted) ``M`` from its upper-triangle ``data``."""
        import scipy.sparse as sp  # for SuperLU, the factorisation of last resort

        shape = (self.size, self.size)
        upper = sp.csr_matrix((data, self.indices, self.indptr), shape=shape)
        return (upper + upper.T - sp.diags(data[self.diagonal])).tocsc()


def _block_ordering(block_rows: np.ndarray, block_cols: np.ndarray, nf: int) -> np.ndarray:
    """AMD order of the block adjacency graph (the diagonal among its entries)."""
    if nf == 0:
        return np.empty(0, dtype=np.int64)  # QDLDL refuses an empty matrix
    order = cholmod.minimum_degree_order(block_rows, block_cols, nf)
    if order is not None:
        return order
    # without cvxopt: QDLDL's AMD, through the scipy.sparse matrix it takes
    import qdldl
    import scipy.sparse as sp

    pattern = sp.coo_matrix((np.ones(len(block_rows)), (block_rows, block_cols)), shape=(nf, nf))
    pattern = (pattern + pattern.T).tocsc()
    pattern.data[:] = -1.0
    # strictly diagonally dominant, so QDLDL's factorisation (only used for its ordering) succeeds
    graph = (pattern + sp.diags(np.full(nf, float(nf + 2)))).tocsc()
    return np.asarray(qdldl.Solver(graph).factors()[2], dtype=np.int64)


def _skew_vector(matrix: np.ndarray) -> np.ndarray:
    """``l`` from ``(n, 3, 3)`` cross-product matrices ``skew(l)``."""
    return np.stack([matrix[:, 2, 1], matrix[:, 0, 2], matrix[:, 1, 0]], axis=1)


def _skew(vectors: np.ndarray) -> np.ndarray:
    out = np.zeros((len(vectors), 3, 3))
    out[:, 0, 1], out[:, 0, 2] = -vectors[:, 2], vectors[:, 1]
    out[:, 1, 0], out[:, 1, 2] = vectors[:, 2], -vectors[:, 0]
    out[:, 2, 0], out[:, 2, 1] = -vectors[:, 1], vectors[:, 0]
    return out


def _interface_frames(problem, interface_starts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split each vertex's ``12 x 3`` Jacobian into a per-vertex ``6 x 3`` part and a per-interface
    ``12 x 6`` part: ``J_v = W_i K_v``.

    The wrench of a unit force at vertex ``v`` on side ``s`` is ``sign_s [R; skew(l_sv) R]`` with
    the interface frame ``R`` and the lever ``l_sv`` from the block's centroid. Writing
    ``l_sv = q_v + d_s`` with ``q_v`` the vertex's offset from the interface's first vertex and
    ``d_s`` that vertex's lever gives ``J_v = W_i K_v``, ``K_v = [R; skew(q_v) R]`` and
    ``W_i = [sign_s [I 0; skew(d_s) I]]_s``. Summing ``K_v D_v K_v^T`` over an interface's
    vertices (6 x 6) before applying ``W_i`` costs a quarter of the 12 x 12 products per vertex.
    """
    jac = problem.vertex_jacobian
    m = len(jac)
    side = np.where(problem.vertex_blocks[:, 0] >= 0, 0, 1)  # a side with a free block
    sign = np.where(side == 0, -1.0, 1.0)[:, None, None]
    rows = 6 * side[:, None] + np.arange(6)
    own = jac[np.arange(m)[:, None], rows] * sign  # (m, 6, 3) = [R; skew(l) R]
    rotation = own[:, :3]
    lever = _skew_vector(own[:, 3:] @ np.transpose(rotation, (0, 2, 1)))
    ni = len(interface_starts)
    counts = np.diff(np.append(interface_starts, m))
    first = np.repeat(interface_starts, counts)
    offset = lever - lever[first]  # q_v, measured on the vertex's own side
    frames = np.concatenate([rotation, _skew(offset) @ rotation], axis=1)
    shifts = np.zeros((ni, 12, 6))
    for s, s_sign in ((0, -1.0), (1, 1.0)):
        head = jac[interface_starts, 6 * s : 6 * s + 6] * s_sign  # zero for a support side
        valid = np.abs(head[:, :3]).sum(axis=(1, 2)) > 0
        d = np.zeros((ni, 3))
        d[valid] = _skew_vector(head[valid, 3:] @ np.transpose(head[valid, :3], (0, 2, 1)))
        block = np.zeros((ni, 6, 6))
        block[:, [0, 1, 2, 3, 4, 5], [0, 1, 2, 3, 4, 5]] = 1.0
        block[:, 3:, :3] = _skew(d)
        shifts[:, 6 * s : 6 * s + 6] = s_sign * block * valid[:, None, None]
    return frames, shifts


_RECENT: collections.OrderedDict[bytes, NormalPattern] = collections.OrderedDict()
_RECENT_SIZE = 4  # block graphs whose symbolic analysis is kept (a search moves between a few)
_RECENT_LOCK = threading.Lock()


def build_pattern(problem) -> NormalPattern:
    """The symbolic analysis of ``M`` for ``problem`` (done once per block graph)."""
    interface_starts = np.flatnonzero(np.diff(np.concatenate([[-1], problem.vertex_interface])))
    blocks = problem.vertex_blocks[interface_starts]  # (ni, 2)
    key = np.int64(problem.n_free).tobytes() + np.ascontiguousarray(blocks, np.int64).tobytes()
    with _RECENT_LOCK:
        known = _RECENT.get(key)
        if known is not None:
            _RECENT.move_to_end(key)
    if known is None:
        known = _symbolic_pattern(problem.n_free, blocks)
        with _RECENT_LOCK:
            _RECENT[key] = known
            while len(_RECENT) > _RECENT_SIZE:
                _RECENT.popitem(last=False)
    frames, shifts = _interface_frames(problem, interface_starts)
    return dataclasses.replace(
        known, interface_starts=interface_starts, vertex_frames=frames, interface_shifts=shifts
    )


def _symbolic_pattern(nf: int, blocks: np.ndarray) -> NormalPattern:
    """Ordering, pattern and scatter map for the block pairs ``blocks`` ``(ni, 2)``."""
    size = 6 * nf
    ni = len(blocks)
    both = (blocks >= 0).all(axis=1)
    order = _block_ordering(
        np.concatenate([blocks[both, 0], np.arange(nf)]),
        np.concatenate([blocks[both, 1], np.arange(nf)]),
        nf,
    )
    position = np.empty(nf, dtype=np.int64)
    position[order] = np.arange(nf)
    local = np.arange(12)
    row_block = blocks[:, local // 6]  # (ni, 12)
    valid = row_block >= 0
    rows = 6 * position[np.where(valid, row_block, 0)] + local % 6  # permuted row numbers
    ok = valid[:, :, None] & valid[:, None, :]
    source = np.flatnonzero(ok.ravel())
    r = np.broadcast_to(rows[:, :, None], (ni, 12, 12))[ok]
    c = np.broadcast_to(rows[:, None, :], (ni, 12, 12))[ok]
    upper = c >= r  # CSR row r, column c >= r
    source, r, c = source[upper], r[upper], c[upper]
    indptr, indices, target = _upper_pattern(nf, position[blocks[both]], r, c)
    diagonal = indptr[:-1].astype(np.int64)  # each row's first entry: its diagonal
    permutation = (6 * order[:, None] + np.arange(6)).ravel()
    empty = np.zeros(0)
    return NormalPattern(
        size,
        indptr,
        indices,
        target,
        source,
        diagonal,
        permutation,
        empty,
        empty,
        empty,
        analysis=_Analysis(),
    )


def _upper_pattern(
    nf: int, pairs: np.ndarray, r: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The upper triangle's CSR ``indptr``, ``indices`` of ``M`` (permuted) and the position of
    each entry ``(r[k], c[k])`` in it, from the block graph alone.

    ``pairs`` ``(k, 2)`` are the permuted positions of the two free blocks of each interface
    between free blocks. Row ``6 I + a`` holds its diagonal block's columns ``6 I + a .. 6 I + 5``
    (the diagonal alone for a block with no contact), then the six columns of each block
    ``J > I`` it shares an interface with, in increasing ``J``: the entries and order that the
    sorted set of every contribution's ``(row, column)`` gives, without sorting them (0.06 s of
    a 2 001-brick wall's first analysis).
    """
    size = 6 * nf
    low, high = np.minimum(pairs[:, 0], pairs[:, 1]), np.maximum(pairs[:, 0], pairs[:, 1])
    links = np.unique(low.astype(np.int64) * nf + high)  # block pairs I < J, sorted
    link_row, link_col = links // nf, links % nf
    degree = np.bincount(link_row, minlength=nf)  # blocks J > I sharing a joint with I
    touched = np.zeros(nf, dtype=bool)  # blocks with a contact: a full diagonal block
    touched[(r // 6)[c // 6 == r // 6]] = True
    a = np.arange(size) % 6
    block = np.arange(size) // 6
    own = np.where(touched[block], 6 - a, 1)  # columns of the diagonal block in each row
    counts = own + 6 * degree[block]
    indptr = np.concatenate([[0], np.cumsum(counts)])
    # the columns: each row's diagonal block, then the blocks of its links
    indices = np.empty(int(indptr[-1]), dtype=np.int64)
    row = np.repeat(np.arange(size), counts)
    slot = np.arange(len(indices)) - indptr[row]
    in_own = slot < own[row]
    indices[in_own] = row[in_own] + slot[in_own]
    link_start = np.concatenate([[0], np.cumsum(degree)])
    later = ~in_own
    rank = (slot[later] - own[row[later]]) // 6
    indices[later] = 6 * link_col[link_start[block[row[later]]] + rank] + (
        (slot[later] - own[row[later]]) % 6
    )
    # each contribution's place in its row
    row_block, column_block = r // 6, c // 6
    offset = c - r  # within the diagonal block
    other = column_block != row_block
    rank = np.searchsorted(links, row_block[other].astype(np.int64) * nf + column_block[other])
    offset[other] = own[r[other]] + 6 * (rank - link_start[row_block[other]]) + c[other] % 6
    target = indptr[r] + offset
    return indptr.astype(np.int32), indices.astype(np.int32), target


class NormalEquations:
    """Assembles and factors ``M = A D A^T`` for per-vertex ``D_v`` (3x3, local frame).

    Parameters
    ----------
    problem
        The :class:`~shapegen.statics.assembly.StaticsProblem`; its ``vertex_jacobian`` holds the
        per-vertex ``12 x 3`` blocks of ``A``.
    factorization
        ``"auto"`` (PARDISO when MKL is installed, else CHOLMOD when cvxopt imports, else
        SuperLU), ``"cholmod"``, ``"pardiso"``
        (needs MKL) or ``"superlu"``; a name that cannot be honoured raises
        :class:`~shapegen.errors.OptionError` (see :func:`check_factorization`).
    """

    def __init__(self, problem, factorization: str = "auto"):
        check_factorization(factorization)
        self.problem = problem
        pattern = problem.cache.get("normal_pattern")
        if pattern is None:
            pattern = build_pattern(problem)
            problem.cache["normal_pattern"] = pattern
        self.pattern = pattern
        method = factorization
        if method == "auto":  # the fastest installed: PARDISO only when asked for at install
            method = next((name for name in _AUTO_ORDER if _LIBRARIES[name].available()), "superlu")
        self._cholesky = None
        if method in _CHOLESKY and pattern.size:
            self._cholesky = pattern.analysis.borrow(method, pattern.indptr, pattern.indices)
        self._lu = None
        self.values = None
        self.fallbacks = 0  # factorisations the Cholesky factorisation refused and SuperLU did
        self.assembly_cpu = 0.0  # CPU seconds assembling M's values
        self.factor_cpu = 0.0  # CPU seconds in the numeric factorisations
        self.factorizations = 0
        self.method = method

    def assemble(self, local_inverse: np.ndarray, regularization: float) -> None:
        """Compute and factor ``M`` for ``D_v = local_inverse[v]`` ``(m, 3, 3)``, with
        ``regularization`` times the mean diagonal added to the diagonal of the factored copy."""
        pattern = self.pattern
        started = time.process_time()
        frames = pattern.vertex_frames
        per_vertex = np.matmul(np.matmul(frames, local_inverse), np.transpose(frames, (0, 2, 1)))
        summed = np.add.reduceat(per_vertex, pattern.interface_starts, axis=0)  # (ni, 6, 6)
        shifts = pattern.interface_shifts
        per_interface = np.matmul(np.matmul(shifts, summed), np.transpose(shifts, (0, 2, 1)))
        values = np.bincount(
            pattern.target,
            per_interface.reshape(-1)[pattern.source],
            minlength=len(pattern.indices),
        )
        values[pattern.diagonal] += (
            regularization * float(values[pattern.diagonal].mean()) + DIVISION_FLOOR
        )
        self.values = values  # the upper triangle of the permuted, shifted M
        self._lu = None
        factoring = time.process_time()
        self.assembly_cpu += factoring - started
        try:
            if self._cholesky is not None:
                try:
                    self._cholesky.factor(values)
                    return
                except _REFUSED:
                    self.fallbacks += 1
            # scipy.sparse.linalg (0.1 s to import) only for a matrix CHOLMOD refused
            import scipy.sparse.linalg as spla

            self._lu = spla.splu(
                pattern.full_matrix(values),
                permc_spec="NATURAL",
                diag_pivot_thresh=0.0,
                options={"SymmetricMode": True},
            )
        finally:
            self.factor_cpu += time.process_time() - factoring
            self.factorizations += 1

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``M^-1 rhs`` (in the original row order)."""
        permutation = self.pattern.permutation
        solution = np.empty_like(rhs)
        permuted = rhs[permutation]
        if self._lu is not None:
            solution[permutation] = self._lu.solve(permuted)
        else:
            solution[permutation] = self._cholesky.solve(permuted)
        return solution

    def release(self) -> None:
        """Free the numeric factor (the symbolic analysis stays with the pattern)."""
        self._lu = None
        if self._cholesky is not None:
            self.pattern.analysis.give_back(self.method, self._cholesky)
            self._cholesky = None
