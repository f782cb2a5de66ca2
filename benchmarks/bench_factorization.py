"""CPU seconds to factor the reduced solver's block normal equations with each sparse
symmetric factorisation available: CHOLMOD through ``cvxopt`` and MKL PARDISO (shapegen's
bindings, :mod:`shapegen.statics.solvers.cholmod` and ``.pardiso``, the latter with the optional
``mkl``), ``cholespy``, and SuperLU (scipy, the fallback).

Run: ``.venv/bin/python benchmarks/bench_factorization.py [--repeat N] [SIDE ...]`` with one
thread (``OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1``). The matrix is
wall-like: ``SIDE x SIDE`` bodies of 6 rows, each coupled to its grid neighbours by contacts of
8 force columns, ``M = A A^T + 1e-3 I``, in the AMD block order the solver computes
(``normal_equations._block_ordering``). The analysis is done once; the numeric factorisation
and the solve ``N`` times (min and median printed), as the solver repeats them per iteration.
An option that is not installed is said so and skipped. The figures and the choice made from
them are in docs/journal/architecture.md ("One home per idea", point 10).
"""

from __future__ import annotations

__all__ = ["main"]

import argparse
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from shapegen.statics.solvers import cholmod, pardiso
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


REPEAT = 5  # numeric factorisations and solves of each option, after its analysis


def _cpu(work):
    start = time.process_time()
    out = work()
    return time.process_time() - start, out


def _repeated(work, repeat):
    """CPU seconds of ``repeat`` calls of ``work`` and its last result."""
    seconds = []
    for _ in range(repeat):
        cpu, out = _cpu(work)
        seconds.append(cpu)
    return seconds, out


def _superlu(m, rhs, repeat):
    symmetric = {"SymmetricMode": True}
    factor_seconds, factor = _repeated(
        lambda: splu(m, permc_spec="NATURAL", diag_pivot_thresh=0.0, options=symmetric), repeat
    )
    solve_seconds, x = _repeated(lambda: factor.solve(rhs), repeat)
    return 0.0, factor_seconds, solve_seconds, x


def _ours(module, factor_class, m, rhs, repeat):
    if not module.available():
        raise ImportError(f"{module.__name__.rsplit('.', 1)[-1]}'s library is not installed")
    upper = sp.triu(m).tocsr()
    upper.sort_indices()
    analyse, factor = _cpu(lambda: factor_class(upper.indptr, upper.indices))
    factor_seconds, _ = _repeated(lambda: factor.factor(upper.data), repeat)
    solve_seconds, x = _repeated(lambda: factor.solve(rhs), repeat)
    return analyse, factor_seconds, solve_seconds, x


def _cholespy(m, rhs, repeat):
    from cholespy import CholeskySolverD, MatrixType

    coo = m.tocoo()
    rows, cols = coo.row.astype(np.int32), coo.col.astype(np.int32)
    factor_seconds, solver = _repeated(
        lambda: CholeskySolverD(m.shape[0], rows, cols, coo.data, MatrixType.COO), repeat
    )
    x = np.zeros_like(rhs)
    solve_seconds, _ = _repeated(lambda: solver.solve(rhs.copy(), x), repeat)
    return 0.0, factor_seconds, solve_seconds, x


OPTIONS = {
    "cholmod": lambda m, rhs, repeat: _ours(cholmod, cholmod.CholmodFactor, m, rhs, repeat),
    "pardiso": lambda m, rhs, repeat: _ours(pardiso, pardiso.PardisoFactor, m, rhs, repeat),
    "cholespy": _cholespy,
    "superlu": _superlu,
}


def _spread(seconds: list[float]) -> str:
    return f"{min(seconds):6.3f} / {float(np.median(seconds)):6.3f} s"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sides", type=int, nargs="*", default=[60, 100])
    parser.add_argument("--repeat", type=int, default=REPEAT)
    args = parser.parse_args()
    if cholmod.available():
        print(f"# cvxopt's OpenBLAS runs its {cholmod.blas_kernels()} kernels")
    for side in args.sides:
        m = wall_matrix(side)
        rhs = np.ones(m.shape[0])
        print(f"{m.shape[0]} rows, {m.nnz} nonzeros (min / median of {args.repeat})")
        for name, run in OPTIONS.items():
            try:
                analyse, factor, solve, x = run(m, rhs, args.repeat)
            except ImportError as exc:
                print(f"  {name:9s} not installed ({exc})")
                continue
            residual = float(np.linalg.norm(m @ x - rhs))
            print(f"  {name:9s} analyse {analyse:6.3f} s  factor {_spread(factor)}  "
                  f"solve {_spread(solve)}  residual {residual:.1e}")  # fmt: skip


if __name__ == "__main__":
    main()
