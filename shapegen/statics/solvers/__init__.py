"""Solver back-ends for the tension-penalty problem; each one a small class in its own module.

``get_backend(name)`` returns a back-end by name: ``"reduced"`` (the structure-exploiting interior
point method, fastest), ``"clarabel"`` (Clarabel on the sparse matrices) or ``"cvxpy"`` (the
readable reference formulation).
"""

from __future__ import annotations

__all__ = [
    "BACKENDS",
    "Backend",
    "Solution",
    "SolveRequest",
    "SolveStatus",
    "cone_refusal",
    "get_backend",
    "takes_cones",
]

import importlib
from collections.abc import Iterator, Mapping
from typing import TYPE_CHECKING

from shapegen.errors import OptionError
from shapegen.lazy_names import lazy_names

if TYPE_CHECKING:
    from shapegen.statics.solvers.base import Backend

# The back-ends' common types load with numpy on first use: checking options (and the command
# line's --help, which offers them) loads neither.
_HOMES = {name: "base" for name in ("Backend", "Solution", "SolveRequest", "SolveStatus")}
__getattr__, __dir__ = lazy_names(__name__, _HOMES, __all__)

_CLASSES = {  # name: (module, class); what each takes is declared on its class
    "reduced": ("shapegen.statics.solvers.reduced", "ReducedBackend"),
    "clarabel": ("shapegen.statics.solvers.clarabel_direct", "ClarabelBackend"),
    "cvxpy": ("shapegen.statics.solvers.cvxpy_reference", "CvxpyBackend"),
}


class _Backends(Mapping):
    """Name -> back-end class; a back-end's module (and so scipy, Clarabel or cvxpy) is imported
    when its class is first asked for. A back-end's module holds its class and what it declares
    (:attr:`~Backend.second_order_cones`, :attr:`~Backend.honours`) and imports its solver's
    library (scipy.sparse.linalg, Clarabel, cvxpy) only when it solves, so checking options
    loads no solver library."""

    def __getitem__(self, name: str) -> type[Backend]:
        module, cls = _CLASSES[name]
        return getattr(importlib.import_module(module), cls)

    def __iter__(self) -> Iterator[str]:
        return iter(_CLASSES)

    def __len__(self) -> int:
        return len(_CLASSES)


BACKENDS: Mapping[str, type[Backend]] = _Backends()


def get_backend(name: str) -> Backend:
    """A new back-end instance by name; an unknown name is an OptionError."""
    if name not in BACKENDS:
        raise OptionError(f"solver must be one of auto, {', '.join(BACKENDS)}; got {name!r}")
    return BACKENDS[name]()


def takes_cones(name: str) -> bool:
    """Whether back-end ``name`` solves the exact Coulomb cone: what its class declares
    (:attr:`~Backend.second_order_cones`), the one place it is said."""
    return BACKENDS[name].second_order_cones


def cone_refusal(solver: str) -> str:
    """Why ``solver`` cannot take pyramid 'cone', naming the solvers that can (one wording, for
    the options' check and the back-end's own)."""
    able = ["auto", *(name for name in BACKENDS if takes_cones(name))]
    return (
        f"solver {solver!r} takes only the friction pyramids (4, 4r, 8); pyramid 'cone' needs"
        f" solver {', '.join(able[:-1])} or {able[-1]}"
    )
