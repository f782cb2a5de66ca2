"""How a search runs: :class:`SearchOptions`, one frozen object checked once.

Every option's name, default, choices and one-line help live here (as lark keeps its options in
``LarkOptions``): :func:`~shapegen.search.optimize`, the pipeline, ``DesignSession``, the design
page and the city command take this object, and the command line makes its ``--optimize`` flags
from :func:`search_fields`. A new search option is a field here and its use in the search. The
module loads nothing heavy, so the command's help can show the defaults cheaply.

>>> from shapegen.search.search_options import SearchOptions
>>> SearchOptions(objective="closest", max_iter=20).margin
0.1
"""

from __future__ import annotations

__all__ = ["GRADIENTS", "OBJECTIVES", "SearchOptions", "search_fields"]

from collections.abc import Mapping
from dataclasses import Field, dataclass, field, fields, replace
from typing import TYPE_CHECKING

from shapegen.errors import OptionError
from shapegen.search.defaults import DEFAULT_MARGIN

if TYPE_CHECKING:
    from shapegen.statics.statics_options import Reserve

OBJECTIVES = ("energy", "closest")
GRADIENTS = ("adjoint", "forward", "none")


def _option(default, help: str, kind: str, **more):
    """A field with what a front end needs to offer it: its help line and its kind (``names``,
    ``assignments``, ``choice`` with ``choices``, ``count`` with ``minimum``, ``fraction``)."""
    factory = {"default_factory": default} if callable(default) else {"default": default}
    return field(**factory, metadata={"help": help, "kind": kind, **more})


@dataclass(frozen=True)
class SearchOptions:
    """How to search the free attrs for a design that stands (see
    :func:`~shapegen.search.optimize`); refused with an :class:`~shapegen.errors.OptionError`
    when a value means nothing.

    Attributes
    ----------
    free
        The attrs to search, each with a ``@Range`` (None: the ``@Free`` ones).
    fix
        Attrs held at a value, ``name -> value``.
    objective
        ``"energy"`` (the papers: bring the measure to zero, stop at the first design that
        stands) or ``"closest"`` (the standing design nearest the starting values).
    gradient
        ``"adjoint"``, ``"forward"``, ``"none"``, or None for the structure's best.
    max_iter
        Iterations per start.
    margin
        The :class:`~shapegen.statics.statics_options.Reserve` in [0, 1) the designs are judged with
        (made from a number here, the one check of a margin on its way in; default
        :data:`~shapegen.search.DEFAULT_MARGIN`; for block statics every joint shrunk and the
        friction lowered to ``1 - margin``, :func:`~shapegen.statics.reserve.with_reserve`); 0
        stops on the boundary, as the papers do.
    multistart
        Extra random starts within the bounds, seeded by the derivation's seed.
    """

    free: tuple[str, ...] | None = _option(
        None, "the attrs to tune (each needs a @Range) instead of the @Free ones", "names"
    )
    fix: Mapping[str, object] = _option(
        dict, "hold a @Free attr at a value; repeatable", "assignments"
    )
    objective: str = _option(
        "energy",
        "'energy' brings the structure's measure to zero and stops at the first design that"
        " stands (the papers); 'closest' finds the standing design nearest to the given values",
        "choice",
        choices=OBJECTIVES,
    )
    gradient: str | None = _option(
        None,
        "'adjoint' (the structure's own gradient: one QP per gradient for block statics),"
        " 'forward' finite differences (n + 1 evaluations) or 'none' (derivative-free, Powell's"
        " method); default: adjoint where the structure has one (block statics), else none"
        " (the cable model)",
        "choice",
        choices=GRADIENTS,
    )
    max_iter: int = _option(50, "iterations per start", "count", minimum=1)
    margin: Reserve = _option(
        DEFAULT_MARGIN,
        "safety margin, 0 to 1: search for a design that still stands with every joint shrunk"
        " to 1 - M of its size and the friction coefficient lowered to 1 - M of itself (block"
        " statics: a reserve against hinging and against sliding) or with the cable diameter"
        " limit lowered to 1 - M of itself (cables), a reserve for what the statics does not"
        " model (a design on the boundary falls in the simulator); 0 stops on the feasibility"
        " boundary, as the papers do",
        "fraction",
    )
    multistart: int = _option(
        0, "extra random starts within the bounds, seeded by --seed", "count", minimum=0
    )

    def __post_init__(self) -> None:
        from shapegen.statics.statics_options import (
            Reserve,  # a margin is checked as it becomes one
        )

        if self.free is not None:
            if isinstance(self.free, str) or not all(isinstance(n, str) for n in self.free):
                raise OptionError(f"free must be a list of attr names; got {self.free!r}")
            object.__setattr__(self, "free", tuple(self.free))
        if not isinstance(self.fix, Mapping):
            raise OptionError(f"fix must map attr names to values; got {self.fix!r}")
        object.__setattr__(self, "fix", dict(self.fix))
        for option in search_fields():
            value = getattr(self, option.name)
            kind, minimum = option.metadata["kind"], option.metadata.get("minimum")
            choices = option.metadata.get("choices", ())
            unset = value is None and option.default is None  # gradient: the structure's best
            if kind == "choice" and not unset and value not in choices:
                raise OptionError(
                    f"{option.name} must be one of {', '.join(choices)}; got {value!r}"
                )
            if kind == "count" and (isinstance(value, bool) or not isinstance(value, int)):
                raise OptionError(f"{option.name} must be a whole number; got {value!r}")
            if kind == "count" and value < minimum:
                raise OptionError(f"{option.name} must be at least {minimum}; got {value!r}")
            if kind == "fraction":
                object.__setattr__(self, option.name, Reserve.of(value))

    def replace(self, **changes) -> SearchOptions:
        """These options with ``changes``, checked again."""
        return replace(self, **changes)


def search_fields() -> tuple[Field, ...]:
    """The options, in order, each with ``metadata`` ``help``, ``kind`` and its ``choices`` or
    ``minimum`` (how the command line makes its flags)."""
    return fields(SearchOptions)
