"""Sparse symmetric factorisation with Intel MKL PARDISO (supernodal Cholesky), through ctypes.

An alternative to the default CHOLMOD (:mod:`~shapegen.statics.solvers.cholmod`), asked for by
name (``factorization="pardiso"`` of the reduced back-end), with the same interface: a symbolic
analysis once per pattern, a numeric factorisation per iteration, solves. Its numeric
factorisation of the walls' normal equations takes half to 0.6 times CHOLMOD's (an analysis of
the 10 000-block wall about 8 % less; docs/journal/architecture.md), but the ``mkl`` wheel installs
691 MB and has no macOS or ARM build, so it is the optional ``shapegen[pardiso]`` rather than a
dependency.

The library comes from the ``mkl`` wheel (``libmkl_rt``); when it cannot be loaded,
:func:`available` is False and asking for PARDISO is refused in one line. MKL runs in its
sequential layer: one thread, so that CPU seconds stay the measure of the work and several
processes can share a machine without spinning threads.
"""

from __future__ import annotations

__all__ = ["PardisoError", "PardisoFactor", "available"]

import ctypes
import ctypes.util
import functools
import glob
import os
import sys

import numpy as np

from shapegen.statics.solvers.symmetric_factor import SymmetricFactor

# real symmetric positive definite (Cholesky): its solves took 0.6 times the time of the
# indefinite type's (-2) at 1 000 and 10 000 blocks, for the same factorisation time; a matrix
# that is not numerically positive definite raises PardisoError and the caller uses SuperLU
_MTYPE = 2
_MESSAGES = {
    -1: "input inconsistent",
    -2: "not enough memory",
    -3: "reordering problem",
    -4: "zero pivot",
    -5: "unclassified internal error",
    -6: "reordering failed",
    -7: "diagonal matrix is singular",
    -8: "32-bit integer overflow",
    -9: "not enough memory for out-of-core",
    -10: "error opening out-of-core files",
    -11: "read/write error with out-of-core files",
}


class PardisoError(RuntimeError):
    """PARDISO reported an error (its code and meaning in the message)."""


def _candidates() -> list[str]:
    names = []
    found = ctypes.util.find_library("mkl_rt")
    if found:
        names.append(found)
    for prefix in dict.fromkeys((sys.prefix, sys.base_prefix)):
        for pattern in ("lib/libmkl_rt.so*", "Library/bin/mkl_rt*.dll", "lib/libmkl_rt*.dylib"):
            names.extend(sorted(glob.glob(os.path.join(prefix, pattern)), key=len))
    return names


@functools.cache
def _library():
    """The loaded ``libmkl_rt`` with ``pardiso`` declared, or None."""
    for name in _candidates():
        try:
            lib = ctypes.CDLL(name)
            pardiso = lib.pardiso
        except (OSError, AttributeError):
            continue
        # 32-bit integers (LP64) and the sequential layer, whatever the environment says; a
        # process that already used MKL keeps its layers (the calls then return the old ones)
        lib.MKL_Set_Interface_Layer.argtypes = [ctypes.c_int]
        lib.MKL_Set_Threading_Layer.argtypes = [ctypes.c_int]
        if lib.MKL_Set_Interface_Layer(0) != 0:  # MKL_INTERFACE_LP64
            continue
        lib.MKL_Set_Threading_Layer(1)  # MKL_THREADING_SEQUENTIAL
        int_p = ctypes.POINTER(ctypes.c_int32)
        pardiso.argtypes = [
            ctypes.c_void_p,  # pt
            int_p,  # maxfct
            int_p,  # mnum
            int_p,  # mtype
            int_p,  # phase
            int_p,  # n
            ctypes.c_void_p,  # a
            ctypes.c_void_p,  # ia
            ctypes.c_void_p,  # ja
            ctypes.c_void_p,  # perm
            int_p,  # nrhs
            ctypes.c_void_p,  # iparm
            int_p,  # msglvl
            ctypes.c_void_p,  # b
            ctypes.c_void_p,  # x
            int_p,  # error
        ]
        pardiso.restype = None
        return lib
    return None


def available() -> bool:
    """True when MKL's PARDISO can be loaded."""
    return _library() is not None


class PardisoFactor(SymmetricFactor):
    """A :class:`~shapegen.statics.solvers.symmetric_factor.SymmetricFactor` by PARDISO."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray):
        lib = _library()
        if lib is None:
            raise PardisoError("MKL PARDISO is not available (the mkl package is not installed)")
        self._pardiso = lib.pardiso
        self.n = len(indptr) - 1
        self._indptr = np.ascontiguousarray(indptr, dtype=np.int32)
        self._indices = np.ascontiguousarray(indices, dtype=np.int32)
        self._data = np.zeros(len(self._indices))
        self._handle = np.zeros(64, dtype=np.int64)  # PARDISO's opaque state
        self._perm = np.arange(self.n, dtype=np.int32)  # zero-based: the identity
        iparm = np.zeros(64, dtype=np.int32)
        iparm[0] = 1  # these settings, not the defaults
        iparm[4] = 1  # the ordering is given (perm)
        iparm[9] = 8  # pivots below 1e-8 of the norm are perturbed (then refined by the caller)
        iparm[17] = -1  # report the nonzeros of the factor
        iparm[34] = 1  # zero-based indices
        self._iparm = iparm
        self._open = False
        self._call(11)  # symbolic analysis
        self._open = True

    @property
    def factor_nonzeros(self) -> int:
        """Nonzeros in the factor (PARDISO's count after the analysis)."""
        return int(self._iparm[17])

    def _call(self, phase: int, rhs: np.ndarray | None = None) -> np.ndarray | None:
        i32 = ctypes.c_int32
        error = i32(0)
        if rhs is None:
            b = x = np.zeros(1)
            nrhs = 1
        else:
            b = np.ascontiguousarray(rhs, dtype=float)
            x = np.empty_like(b)
            nrhs = 1
        self._pardiso(
            self._handle.ctypes.data,
            ctypes.byref(i32(1)),
            ctypes.byref(i32(1)),
            ctypes.byref(i32(_MTYPE)),
            ctypes.byref(i32(phase)),
            ctypes.byref(i32(self.n)),
            self._data.ctypes.data,
            self._indptr.ctypes.data,
            self._indices.ctypes.data,
            self._perm.ctypes.data,
            ctypes.byref(i32(nrhs)),
            self._iparm.ctypes.data,
            ctypes.byref(i32(0)),
            b.ctypes.data,
            x.ctypes.data,
            ctypes.byref(error),
        )
        if error.value != 0:
            meaning = _MESSAGES.get(error.value, "unknown error")
            raise PardisoError(f"PARDISO phase {phase} failed: {meaning} ({error.value})")
        return None if rhs is None else x

    def factor(self, data: np.ndarray) -> None:
        """Numeric factorisation for the values ``data`` (aligned with ``indices``)."""
        np.copyto(self._data, data)
        self._call(22)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``M^-1 rhs`` for the last factored values (one right-hand side)."""
        return self._call(33, rhs)

    def release_factor(self) -> None:
        """Free the numeric factor and keep the analysis (the next :meth:`factor` reuses it)."""
        if self._open:
            self._call(0)

    def close(self) -> None:
        """Free everything PARDISO holds for this pattern."""
        if self._open:
            self._open = False
            self._call(-1)

    def __del__(self):
        try:
            self.close()
        except Exception:  # never raise from a finaliser
            pass
