"""CPU seconds to factor the reduced solver's block normal equations with each sparse
symmetric factorisation available: MKL PARDISO (shapegen's binding, the ``mkl`` wheel), CHOLMOD
through ``cvxopt``, ``cholespy``, and SuperLU (scipy, the fallback).

Run: ``.venv/bin/python benchmarks/bench_factorization.py [SIDE ...]`` with one thread
(``OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1``). The matrix is wall-like:
``SIDE x SIDE`` bodies of 6 rows, each coupled to its grid neighbours by contacts of 8 force
columns, ``M = A A^T + 1e-3 I``, in the AMD block order the solver computes
(``normal_equations._block_ordering``). An option that is not installed is said so and skipped.
The figures and the choice made from them are in docs/architecture.md (issue #29, point 10).
"""

from __future__ import annotations

__all__ = ["main"]

import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from shapegen.statics.solvers import pardiso
from shapegen.statics.solvers.normal_equations import _block_ordering

FORCE_COLUMNS = 8  # force components per contact
SHIFT = 1e-3  # keeps M positive definite, as the solver's regularisation does


def wall_matrix(side: int, seed: int = 0) -> sp.csc_matrix:
    """The ``6 side^2`` square symmetric positive definite matrix, in the solver's order."""
    rng = np.random.default_rng(seed)
    pairs = [
        (i * side + j, (i + di) * side + (j + dj))
        for i in range(side)
        for j in range(side)
        for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1))
        if 0 <= i + di < side and 0 <= j + dj < side
    ]
    rows, cols, values = [], [], []
    for contact, pair in enumerate(pairs):
        for body in pair:
            rows.append(np.repeat(np.arange(6) + 6 * body, FORCE_COLUMNS))
            cols.append(np.tile(np.arange(FORCE_COLUMNS) + FORCE_COLUMNS * contact, 6))
            values.append(rng.standard_normal(6 * FORCE_COLUMNS))
    a = sp.csr_matrix(
        (np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
        shape=(6 * side * side, FORCE_COLUMNS * len(pairs)),
    )
    m = (a @ a.T + SHIFT * sp.identity(a.shape[0])).tocsc()
    first, second = np.array(pairs).T
    order = _block_ordering(first, second, side * side)
    permutation = (6 * order[:, None] + np.arange(6)).ravel()
    return m[permutation][:, permutation].tocsc()


def _cpu(work):
    start = time.process_time()
    out = work()
    return time.process_time() - start, out


def _superlu(m, rhs):
    symmetric = {"SymmetricMode": True}
    seconds, factor = _cpu(
        lambda: splu(m, permc_spec="NATURAL", diag_pivot_thresh=0.0, options=symmetric)
    )
    return 0.0, seconds, factor.solve(rhs)


def _pardiso(m, rhs):
    if not pardiso.available():
        raise ImportError("mkl is not installed")
    upper = sp.triu(m).tocsr()
    upper.sort_indices()
    analyse, factor = _cpu(lambda: pardiso.SymmetricFactor(upper.indptr, upper.indices))
    numeric, _ = _cpu(lambda: factor.factor(upper.data))
    return analyse, numeric, factor.solve(rhs)


def _cholmod(m, rhs):
    from cvxopt import cholmod, matrix, spmatrix

    lower = sp.tril(m).tocoo()
    a = spmatrix(matrix(lower.data), matrix(lower.row), matrix(lower.col), m.shape)
    analyse, symbolic = _cpu(lambda: cholmod.symbolic(a))
    numeric, _ = _cpu(lambda: cholmod.numeric(a, symbolic))
    x = matrix(rhs)
    cholmod.solve(symbolic, x)
    return analyse, numeric, np.array(x).ravel()


def _cholespy(m, rhs):
    from cholespy import CholeskySolverD, MatrixType

    coo = m.tocoo()
    rows, cols = coo.row.astype(np.int32), coo.col.astype(np.int32)
    seconds, solver = _cpu(
        lambda: CholeskySolverD(m.shape[0], rows, cols, coo.data, MatrixType.COO)
    )
    x = np.zeros_like(rhs)
    solver.solve(rhs.copy(), x)
    return 0.0, seconds, x


OPTIONS = {"pardiso": _pardiso, "cholmod": _cholmod, "cholespy": _cholespy, "superlu": _superlu}


def main(argv: list[str]) -> None:
    for side in [int(a) for a in argv] or [60, 100]:
        m = wall_matrix(side)
        rhs = np.ones(m.shape[0])
        print(f"{m.shape[0]} rows, {m.nnz} nonzeros")
        for name, run in OPTIONS.items():
            try:
                analyse, numeric, x = run(m, rhs)
            except ImportError as exc:
                print(f"  {name:9s} not installed ({exc})")
                continue
            residual = float(np.linalg.norm(m @ x - rhs))
            print(f"  {name:9s} analyse {analyse:6.2f} s  factor {numeric:6.2f} s  "
                  f"residual {residual:.1e}")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
