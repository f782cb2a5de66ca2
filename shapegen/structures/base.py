"""What a structure is: how a built design is judged to stand, and by how much it fails.

A :class:`Structure` takes a :class:`Design` (a model, built on first use, and the keyword
arguments of the grammar's ``@Structure(...)``) and returns an :class:`Assessment`: a verdict, a
scalar ``measure`` that is zero exactly when the design stands, a solver status and a report
section. A structure that knows how its measure moves with the geometry also gives
:meth:`Structure.measure_change`, from which the search builds a gradient.
"""

from __future__ import annotations

__all__ = ["UNJUDGED_STATUSES", "Assessment", "Design", "Structure", "StructureArgument"]

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import ClassVar

from shapegen.errors import OptionError
from shapegen.json_values import finite_or_none
from shapegen.model import Model
from shapegen.statics.statics_options import Reserve

_REQUIRED = object()


@dataclass(frozen=True)
class StructureArgument:
    """A keyword argument a structure reads from ``@Structure(name, keyword = expression)``."""

    description: str
    default: object = _REQUIRED

    @property
    def required(self) -> bool:
        return self.default is _REQUIRED


class Design:
    """One design to judge: its model, built on first use, and its ``@Structure`` arguments.

    Parameters
    ----------
    arguments
        ``keyword -> value`` of the grammar's ``@Structure(...)``, evaluated for this design.
    model
        The built model, or None to build it with ``build`` when a structure first asks.
    build
        Builds the model (a structure that judges from its arguments alone never calls it).
    """

    def __init__(
        self,
        arguments: Mapping[str, object] | None = None,
        *,
        model: Model | None = None,
        build: Callable[[], Model] | None = None,
    ):
        if model is None and build is None:
            raise ValueError("a Design needs a model or a way to build one")
        self.arguments = dict(arguments or {})
        self._model = model
        self._build = build

    @classmethod
    def of_model(cls, model: Model) -> Design:
        """The design of a built model, with the arguments recorded in its metadata."""
        recorded = (model.metadata or {}).get("structure") or {}
        return cls(recorded.get("arguments") or {}, model=model)

    @property
    def built(self) -> bool:
        """True once the model exists."""
        return self._model is not None

    @property
    def model(self) -> Model:
        """The model, built now if it was not yet."""
        if self._model is None:
            self._model = self._build()
        return self._model


UNJUDGED_STATUSES = frozenset({"numerical_error", "max_iterations"})
"""Solver outcomes that give no verdict: the design is taken not to stand (searches keep away
from it), and reports and printouts say the solver ended so, never a plain "no"."""


@dataclass
class Assessment:
    """A structure's judgement of one design.

    Attributes
    ----------
    structure
        The structure's registered name.
    stands
        The verdict.
    measure
        Zero exactly when the design stands, positive otherwise (dimensionless; inf when no
        equilibrium exists at all, nan when the solver failed).
    status
        The solver's outcome (``"optimal"``, ``"infeasible"``, ...), never an exception.
    section
        The structure's report section (plain JSON values).
    detail
        The structure's own result (a block :class:`~shapegen.statics.analysis.Analysis`, a
        :class:`~shapegen.statics.cables.CableSizing`), for pictures and exports.
    margin
        The reserve the verdict was judged with (0: none).
    block_analysis
        The rigid-block :class:`~shapegen.statics.analysis.Analysis` behind the verdict (joint
        forces, block tensions) that pictures, exports and the page's block readouts show; None
        when the structure judges no blocks (a bridge's cables).
    pending
        True when only the verdict is known (proven) and the measure (nan) and the detail
        follow: :meth:`Structure.complete` gives them (``reassess(measure_follows=True)``).
    """

    structure: str
    stands: bool
    measure: float
    status: str
    section: dict = field(default_factory=dict)
    detail: object = field(default=None, repr=False)
    margin: float = 0.0
    block_analysis: object = field(default=None, repr=False)
    pending: bool = False

    @property
    def ok(self) -> bool:
        """True when the measure is a finite number (the design could be judged)."""
        return math.isfinite(self.measure)

    @property
    def judged(self) -> bool:
        """False when the solver ended without an answer (:data:`UNJUDGED_STATUSES`): the
        verdict ``stands=False`` is then the safe side, not a finding, and is shown as such."""
        return self.status not in UNJUDGED_STATUSES

    def to_report(self) -> dict:
        """The ``analysis`` object of a report: the verdict first, then the structure's section."""
        return {
            "structure": self.structure,
            "stands": bool(self.stands),
            "measure": finite_or_none(self.measure),
            "status": self.status,
            "margin": self.margin,
            **self.section,
        }


class Structure(ABC):
    """How a design is judged. Subclasses are registered with
    :func:`~shapegen.structures.registry.register_structure`.

    Class attributes
    ----------------
    name
        The name used in ``@Structure("name")`` (``"blocks"``, the default, needs none).
    description
        One line for help texts.
    measure_name
        What the measure is, for reports and plots (``"y/W²"``).
    fails_as
        What a design that does not stand is said to do, in a word or three (``"needs
        tension"``), for the design page's verdict.
    arguments
        The ``@Structure`` keyword arguments it reads.
    options_type
        The type of its settings object (None: it has none).
    needs_model
        False when it judges from its arguments alone: a search then builds no model.
    has_gradient
        True when :meth:`measure_change` gives first-order changes of the measure.
    has_capacity
        True when :meth:`lateral_capacity` gives the largest tilt at which a design stands.
    judges_blocks
        True when it judges the model's blocks by rigid-block statics: it takes the statics
        options (friction, tilt, selection...), its assessments carry ``block_analysis`` and its
        report section is block statics'. Front ends ask this, never the name.
    """

    name: ClassVar[str]
    description: ClassVar[str] = ""
    measure_name: ClassVar[str] = "measure"
    fails_as: ClassVar[str] = "does not stand"
    arguments: ClassVar[Mapping[str, StructureArgument]] = {}
    options_type: ClassVar[type | None] = None
    needs_model: ClassVar[bool] = True
    has_gradient: ClassVar[bool] = False
    has_capacity: ClassVar[bool] = False
    judges_blocks: ClassVar[bool] = False

    def __init__(self, options: object | None = None):
        if options is not None and (
            self.options_type is None or not isinstance(options, self.options_type)
        ):
            raise OptionError(
                f"{type(options).__name__} does not apply to the structure {self.name!r}"
                f" ({self.description})"
            )
        self.options = (
            options if options is not None or self.options_type is None else (self.options_type())
        )

    @abstractmethod
    def assess(self, design: Design, *, margin: Reserve | float = 0.0) -> Assessment:
        """Judge ``design``; with a ``margin`` above 0, judge it with that reserve (a design that
        stands with a margin stands without one). ``margin`` is a
        :class:`~shapegen.statics.statics_options.Reserve`, checked when it was made (the search
        passes its own), or a number that ``Reserve.of(margin)`` checks."""

    def reassess(
        self, design: Design, previous: Assessment | None, *, measure_follows: bool = False
    ) -> Assessment:
        """Judge ``design`` (without a margin) where ``previous`` judged the design before it,
        a small change away (the design page's last): the same answer as :meth:`assess`, which
        a structure may reach faster from the last one. With ``measure_follows`` it may answer
        with the verdict alone (a :attr:`Assessment.pending` one) when the rest would take
        longer; :meth:`complete` gives the rest. By default it is :meth:`assess`."""
        return self.assess(design)

    def complete(self, assessment: Assessment) -> Assessment:
        """The full assessment of a pending one (see :meth:`reassess`); any other as it is."""
        return assessment

    @classmethod
    def summary(cls, section: Mapping[str, object]) -> list[tuple[str, str]]:
        """The figures a front end prints under the verdict of a report's ``analysis`` object
        (``section``), as ``(label, text)`` lines: by default the measure and what it is."""
        return [("measure", f"{figure_text(section.get('measure'))} ({cls.measure_name})")]

    @classmethod
    def panel(cls, section: Mapping[str, object]) -> dict | None:
        """The design page's panel of the structure's own figures beside the verdict, from an
        assessment's ``section``: ``{"title": ..., "rows": [[label, text], ...]}`` in the
        structure's words, or None for none (block statics' figures are the blocks' own,
        shown on the model and in a block's readout)."""
        return None

    def measure_change(self, base: Assessment, moved: Design) -> float | None:
        """First-order change of the measure from ``base``'s design to ``moved`` (a design a
        small step away), or None when it is not known there."""
        return None

    def lateral_capacity(self, design: Design, azimuths: Sequence[float] | None = None):
        """The largest tilt at which ``design`` stands, towards each of ``azimuths`` (degrees in
        the ground plane from +x towards +z) or over a sweep of directions and the worst; an
        object with ``to_report()``. Only for structures that declare :attr:`has_capacity`."""
        raise OptionError(
            f"the lateral capacity is a rigid-block figure; the {self.name!r} structure"
            f" ({self.description}) has none"
        )

    def checked_arguments(self, arguments: Mapping[str, object]) -> dict[str, object]:
        """The arguments with defaults filled in; a missing or unknown one is an error."""
        unknown = sorted(set(arguments) - set(self.arguments))
        if unknown:
            raise OptionError(
                f"@Structure({self.name!r}) has no argument {unknown[0]!r}; its arguments: "
                + (", ".join(self.arguments) or "none")
            )
        missing = [n for n, a in self.arguments.items() if a.required and n not in arguments]
        if missing:
            raise OptionError(
                f"@Structure({self.name!r}) needs the argument(s) {', '.join(missing)}"
            )
        return {
            name: arguments.get(name, argument.default) for name, argument in self.arguments.items()
        }


def figure_text(value: object) -> str:
    """A report's number in 4 significant digits ('-' for none), as the command prints it."""
    if value is None:
        return "-"
    return f"{value:.4g}" if isinstance(value, int | float) else str(value)
