"""The interface of a sparse symmetric factorisation of the reduced solver's normal equations,
declared once: CHOLMOD (:class:`~shapegen.statics.solvers.cholmod.CholmodFactor`) and MKL
PARDISO (:class:`~shapegen.statics.solvers.pardiso.PardisoFactor`) implement it, and
:mod:`~shapegen.statics.solvers.normal_equations` keeps one per pattern and library.
"""

from __future__ import annotations

__all__ = ["SymmetricFactor"]

from abc import ABC, abstractmethod

import numpy as np


class SymmetricFactor(ABC):
    """One symmetric matrix pattern, analysed once, factored for any values on that pattern.

    Parameters
    ----------
    indptr, indices
        CSR pattern of the *upper* triangle (diagonal included) of an ``n x n`` symmetric
        matrix, zero-based, column indices sorted within each row. The rows are taken in the
        given order (the caller has already applied a fill-reducing ordering).

    A matrix the library finds not numerically positive definite raises the library's error
    (``CholmodError``, ``PardisoError``), and the caller factors it with SuperLU instead.
    """

    n: int  # rows of the matrix

    @abstractmethod
    def __init__(self, indptr: np.ndarray, indices: np.ndarray): ...

    @abstractmethod
    def factor(self, data: np.ndarray) -> None:
        """Numeric factorisation for the values ``data`` (aligned with ``indices``)."""

    @abstractmethod
    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``M^-1 rhs`` for the last factored values."""

    @abstractmethod
    def release_factor(self) -> None:
        """Done with the numeric factor; the analysis is kept for the next :meth:`factor`
        where the library can keep it apart."""

    @abstractmethod
    def close(self) -> None:
        """Free everything the library holds for this pattern."""
