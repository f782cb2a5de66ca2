"""Sparse symmetric factorisation with CHOLMOD (supernodal Cholesky), through ``cvxopt``.

The reduced interior point method factors the block-level normal equations ``M`` a dozen times
per solve with the same sparsity pattern. CHOLMOD's supernodal Cholesky runs dense BLAS-3
kernels on the supernodes (4-5 times faster than SuperLU on the walls' ``M``) and
separates the symbolic analysis, done once per pattern and kept, from the numeric factorisation,
done per iteration.

``cvxopt`` ships CHOLMOD with its BLAS in a wheel for every platform shapegen runs on; it is
imported on the first factorisation, never by a plain import of shapegen. Settings, the same at
every call (``cvxopt.cholmod.options`` is shared with any other user of cvxopt in the process, so
it is set around each of our calls and given back as it was):

- ``supernodal = 2``: ``L L^T``; a matrix that is not numerically positive definite stops the
  factorisation (:class:`CholmodError`, and the caller factors it with SuperLU instead);
- ``nmethods = 1`` with the identity permutation: the rows are taken in the given order (the
  caller's block AMD), no second ordering is computed and compared;
- ``postorder = True``: CHOLMOD may postorder the elimination tree, which changes no fill;
- ``print = 0``: nothing is printed.

The BLAS bundled with cvxopt (OpenBLAS) is asked for one thread, so that CPU seconds stay the
measure of the work and several processes can share a machine without spinning threads. On
x86-64 Linux it is also told which kernels to run (see :func:`_kernels_hint`): the OpenBLAS
0.3.15 of cvxopt 1.3's wheels does not recognise processors newer than itself and falls back to
its SSE3 kernels, which made CHOLMOD 2-3 times slower on a 2023 Xeon.

cvxopt holds the interpreter lock during a call: two threads factor one after the other, never
at once (its CHOLMOD settings are one shared object, so that is also what keeps them apart).
"""

from __future__ import annotations

__all__ = ["CholmodError", "CholmodFactor", "available", "blas_kernels", "minimum_degree_order"]

import ctypes
import functools
import glob
import os
import platform
import sys

import numpy as np

from shapegen.statics.solvers.symmetric_factor import SymmetricFactor

_OPTIONS = {"supernodal": 2, "nmethods": 1, "postorder": True, "print": 0}
# Above this many stored entries (upper triangle) a released factor is freed whole and the next
# factorisation analyses the pattern again: cvxopt cannot free the numeric part alone, and the
# factor of a 100 000-block wall (2-3 GB) should not outlive its solve in the pattern cache (four
# block graphs). The 10 000-block wall's M has 1.3 M entries and a factor of ~90 MB, kept; its
# analysis (0.05 s) is a fifth of one numeric factorisation, so a larger model analyses its
# pattern once per solve of a dozen factorisations at little cost.
_KEEP_ENTRIES = 2_000_000


class CholmodError(RuntimeError):
    """CHOLMOD refused a matrix (not positive definite) or failed (its words in the message)."""


def _kernels_hint() -> str | None:
    """``"Haswell"`` where cvxopt's OpenBLAS should be told its kernels, else None.

    OpenBLAS picks its kernels when it loads, from the processor's model number. The 0.3.15 in
    cvxopt 1.3's wheels does not know later models (a 2023 Xeon, model 207) and takes its SSE3
    kernels ("Prescott"): CHOLMOD then factored the 10 000-block wall's ``M`` in 0.47-0.60 s
    instead of 0.20-0.22 s. Its AVX2 kernels ("Haswell", also what it runs on AMD's Zen; on
    that Xeon as fast as its AVX-512 ones) run on any processor with AVX2 and FMA. A choice made
    in ``OPENBLAS_CORETYPE`` is left alone; only Linux says its flags in /proc/cpuinfo.
    """
    if "OPENBLAS_CORETYPE" in os.environ or platform.machine().lower() not in ("x86_64", "amd64"):
        return None
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as info:
            line = next((line for line in info if line.startswith("flags")), "")
    except OSError:
        return None
    return "Haswell" if {"avx2", "fma"} <= set(line.partition(":")[2].split()) else None


def _openblas(package_dir: str):
    """The OpenBLAS that cvxopt's wheel bundles (already loaded by cvxopt), or None."""
    parent = os.path.dirname(package_dir)
    patterns = (
        os.path.join(parent, "cvxopt.libs", "libopenblas*"),  # manylinux (auditwheel)
        os.path.join(package_dir, ".dylibs", "libopenblas*"),  # macOS (delocate)
        os.path.join(parent, "cvxopt.libs", "*openblas*.dll"),  # Windows (delvewheel)
    )
    for pattern in patterns:
        for path in sorted(glob.glob(pattern)):
            try:
                library = ctypes.CDLL(path)  # the loaded library, not a second copy
                library.openblas_set_num_threads.argtypes = [ctypes.c_int]
                library.openblas_get_corename.restype = ctypes.c_char_p
                return library
            except (OSError, AttributeError):
                continue
    return None


@functools.cache
def _cvxopt():
    """``(cvxopt, cvxopt.cholmod)``, or None when cvxopt is not installed."""
    hint = _kernels_hint() if "cvxopt" not in sys.modules else None
    if hint is not None:
        os.environ["OPENBLAS_CORETYPE"] = hint  # read once, when OpenBLAS loads
    try:
        import cvxopt
        from cvxopt import cholmod
    except ImportError:
        return None
    finally:
        if hint is not None:
            del os.environ["OPENBLAS_CORETYPE"]  # not passed on to other libraries or children
    openblas = _openblas(os.path.dirname(cvxopt.__file__))
    if openblas is not None:
        openblas.openblas_set_num_threads(1)
    return cvxopt, cholmod


def available() -> bool:
    """True when cvxopt (and so CHOLMOD) can be imported."""
    return _cvxopt() is not None


def minimum_degree_order(rows: np.ndarray, columns: np.ndarray, n: int) -> np.ndarray | None:
    """SuiteSparse AMD's order of the symmetric pattern with entries ``(rows, columns)`` (either
    triangle or both, the diagonal included), through cvxopt; None without cvxopt.

    cvxopt's AMD and QDLDL's are the same code with the same settings: on the block graphs of
    walls, an arch and the bundled rules they give the same order, 3-10 times faster (no
    scipy.sparse matrix to make, and no factorisation done for its ordering).
    """
    loaded = _cvxopt()
    if loaded is None:
        return None
    cvxopt = loaded[0]
    from cvxopt import amd

    lower = np.maximum(rows, columns).astype(np.int64)
    upper = np.minimum(rows, columns).astype(np.int64)
    pattern = cvxopt.spmatrix(
        cvxopt.matrix(np.ones(len(lower))), cvxopt.matrix(lower), cvxopt.matrix(upper), (n, n)
    )
    return np.asarray(amd.order(pattern, uplo="L"), dtype=np.int64).ravel()


def blas_kernels() -> str:
    """The kernels cvxopt's OpenBLAS runs (``"Haswell"``...), for benchmarks; ``"unknown"``
    where they cannot be asked."""
    loaded = _cvxopt()
    openblas = None if loaded is None else _openblas(os.path.dirname(loaded[0].__file__))
    if openblas is None:
        return "unknown"
    return openblas.openblas_get_corename().decode(errors="replace")


class _Settings:
    """Our CHOLMOD options in ``cvxopt.cholmod.options`` for the duration of one call."""

    def __init__(self, cholmod):
        self._options = cholmod.options

    def __enter__(self):
        self._saved = dict(self._options)
        self._options.clear()
        self._options.update(_OPTIONS)

    def __exit__(self, *exc):
        self._options.clear()
        self._options.update(self._saved)


class CholmodFactor(SymmetricFactor):
    """A :class:`~shapegen.statics.solvers.symmetric_factor.SymmetricFactor` by CHOLMOD.

    The CSR arrays of the upper triangle are, read by columns, the CSC arrays of the lower
    triangle, which is what CHOLMOD is given (``uplo="L"``): the values need no reordering.
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray):
        loaded = _cvxopt()
        if loaded is None:
            raise CholmodError("CHOLMOD is not available (the cvxopt package is not installed)")
        cvxopt, self._cholmod = loaded
        self._settings = _Settings(self._cholmod)
        self.n = len(indptr) - 1
        indptr = np.asarray(indptr, dtype=np.int64)
        rows = np.asarray(indices, dtype=np.int64)
        self.entries = len(rows)
        columns = np.repeat(np.arange(self.n, dtype=np.int64), np.diff(indptr))
        if np.any(rows < columns):
            raise ValueError("the pattern must be the upper triangle in CSR order")
        self._matrix = cvxopt.spmatrix(
            cvxopt.matrix(np.zeros(self.entries)),
            cvxopt.matrix(rows),
            cvxopt.matrix(columns),
            (self.n, self.n),
        )
        stored = np.asarray(self._matrix.CCS[1], dtype=np.int64).ravel()
        if len(stored) != self.entries or np.any(stored != rows):
            raise ValueError("the pattern has repeated or unsorted entries")
        self._identity = cvxopt.matrix(np.arange(self.n, dtype=np.int64), tc="i")
        self._dense = cvxopt.matrix
        self._symbolic = None
        self._factored = False
        self._analyse()

    def _analyse(self) -> None:
        self._factored = False
        try:
            with self._settings:
                self._symbolic = self._cholmod.symbolic(self._matrix, p=self._identity, uplo="L")
        except ValueError as exc:
            raise CholmodError(f"CHOLMOD analysis failed: {exc}") from None

    def factor(self, data: np.ndarray) -> None:
        """Numeric factorisation for the values ``data`` (aligned with ``indices``)."""
        if self._symbolic is None:
            self._analyse()
        self._factored = False
        self._matrix.V = self._dense(np.asarray(data, dtype=float))
        try:
            with self._settings:
                self._cholmod.numeric(self._matrix, self._symbolic)
        except ArithmeticError as exc:
            column = exc.args[0] if exc.args else "?"
            raise CholmodError(
                f"CHOLMOD: the matrix is not positive definite (column {column})"
            ) from None
        except ValueError as exc:
            raise CholmodError(f"CHOLMOD factorisation failed: {exc}") from None
        self._factored = True

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``M^-1 rhs`` for the last factored values; ``rhs`` of shape ``(n,)`` or ``(n, k)``."""
        if not self._factored:
            raise CholmodError("no numeric factor: call factor() first")
        rhs = np.asarray(rhs, dtype=float)
        columns = rhs.reshape(self.n, -1)
        if columns.shape[1] == 0:
            return np.empty_like(rhs)
        # cvxopt's dense matrices are column-major: one column per right-hand side
        work = self._dense(np.asfortranarray(columns))
        with self._settings:
            self._cholmod.solve(self._symbolic, work)
        return np.array(work).reshape(rhs.shape)

    def release_factor(self) -> None:
        """Done with the numeric factor. The analysis is kept for the next :meth:`factor` when
        the pattern is small; a large one's factor is freed with it (see ``_KEEP_ENTRIES``)."""
        self._factored = False
        if self.entries > _KEEP_ENTRIES:
            self._symbolic = None

    def close(self) -> None:
        """Free everything CHOLMOD holds for this pattern."""
        self._factored = False
        self._symbolic = None
