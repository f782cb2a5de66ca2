"""The attribute catalogue: every fact of a grammar's attrs, read once, in one place.

An attr's facts are its name; its kind (from its default value and its annotations); its
default; whether it is ``@Free``; its ``@Range`` (whether it has one, its stepsize, whether it
is ``restricted``; its bounds, which may depend on other attrs, for given values:
:meth:`AttrCatalogue.ranges`); how CityEngine's Inspector shows it (its group, order, whether
hidden, description, display name, choices, unit). The command line (``--set``, ``--fix``), the
design page, the search and ``shapegen.prt`` read them here, and a name no attr has gets the
one line :meth:`AttrCatalogue.no_attr` everywhere. A loaded grammar holds its catalogue
(:attr:`shapegen.engine.grammar_api.Grammar.catalogue`).

The annotations follow CityEngine's (the cga_annotations reference):

- ``@Range(min, max, stepsize=, restricted=)``: a slider stepping by ``stepsize`` (when > 0,
  from ``min``); ``restricted=false`` lets a typed number lie outside the range (a ``@Free``
  attr's range is the search's bounds, so it stays restricted). ``@Range("a", "b")`` of
  strings (CityEngine's older form) is a drop-down of those strings.
- ``@Enum(v1, v2, ..., restricted=)`` or ``@Enum(valuesAttr=name)``: a drop-down of the values
  (numbers or strings; ``valuesAttr`` names an array attr, read at its current value);
  ``restricted`` (the default) refuses any other value.
- ``@Hidden``: not shown (the API still lists it and takes values for it); PyPRT's attribute
  listing leaves it out.
- ``@Group("level 1", ..., "level n", order)``: the Inspector's sections. It sets the group of
  this attr *and the ones after it* in its file until the next ``@Group`` (a ``@Group`` without
  names leaves the group); ``order`` sorts the groups. The attrs of an import (``lib.height``)
  are in a section of the import (``lib``), their groups within it. ``@Order(n)`` sorts the
  attrs within their group.
- ``@Description``: the help text; ``@DisplayName``: the name shown.
- ``@Color``: a string attr ``"#rrggbb"``; ``@File`` / ``@File("ext", ...)`` / ``@Directory``
  (and ``@MaterialFile``): a file (folder) name.
- ``@Angle``, ``@Percent``, ``@Distance`` on a number: its unit (degrees, a fraction shown in
  percent, metres); without a ``@Range`` the first two have CityEngine's unrestricted slider
  (:data:`UNIT_RANGES`).

Annotation arguments are constants, folded with
:func:`~shapegen.grammar.constant_folding.constant_value`; one that cannot be folded is
ignored, as CityEngine's Inspector ignores what it cannot read.

>>> import shapegen
>>> grammar = shapegen.parse_grammar('''
... @Group("Walls", 1) @Range(0.1, 0.8, stepsize=0.1)
... attr t = 0.3
... attr courses = 4
... @Hidden
... attr note = "x"
... @StartRule
... Lot --> extrude(t) Wall
... ''')
>>> catalogue = grammar.catalogue
>>> catalogue["courses"].group, catalogue["note"].hidden, catalogue["t"].step
(('Walls',), True, 0.1)
>>> catalogue.no_attr("cuorses")
"the grammar has no attr 'cuorses'; did you mean 'courses'?"
"""

from __future__ import annotations

__all__ = ["UNIT_RANGES", "UNITS", "AttrCatalogue", "AttrEntry", "no_attr_line"]

import math
from collections.abc import Collection, Iterable, Iterator, Mapping
from dataclasses import dataclass, field

from shapegen.errors import did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.constant_folding import UNKNOWN, constant_value, is_number
from shapegen.tolerances import GRID_SLACK, is_close

#: The unit annotations CityEngine's Inspector honours, by the unit they give a number.
UNITS = {"Angle": "angle", "Percent": "percent", "Distance": "distance"}
#: The slider's range of a unit without a ``@Range`` (unrestricted: any value may be typed).
UNIT_RANGES = {"angle": (0.0, 360.0), "percent": (0.0, 1.0)}
#: The most attr names a "no attr" line lists when none is close to the name given.
_LISTED = 12


@dataclass(frozen=True)
class AttrEntry:
    """The facts of one attr.

    ``kind`` is ``number``, ``bool``, ``string``, ``color`` (``@Color``), ``file``
    (``@File``, ``@MaterialFile``), ``directory`` (``@Directory``) or ``array``. ``ranged``
    says it has a ``@Range(min, max)``; ``step`` is the ``@Range`` stepsize (None without
    one); ``restricted`` False lets a value lie outside the range or the choices.
    ``choices`` are the values of an ``@Enum`` or a ``@Range`` of strings (None without),
    ``values_attr`` the attr an ``@Enum(valuesAttr=...)`` reads them from, ``extensions``
    those a ``@File`` names. ``group`` is the Inspector's section, outermost first (an
    import's prefix, then the ``@Group`` names that hold for it), ``group_annotation`` the
    ``@Group`` it lies under, its own or carried from an attr before it. ``unit`` is that of
    ``@Angle``, ``@Percent`` or ``@Distance`` (``angle``, ``percent``, ``distance``; None
    without). ``node`` is its definition.
    """

    name: str
    kind: str
    default: object
    free: bool = False
    ranged: bool = False
    step: float | None = None
    restricted: bool = True
    choices: tuple | None = None
    values_attr: str | None = None
    extensions: tuple[str, ...] = ()
    group: tuple[str, ...] = ()
    group_order: float | None = None
    order: float | None = None
    description: str = ""
    display_name: str = ""
    hidden: bool = False
    unit: str | None = None
    group_annotation: ast.Annotation | None = field(default=None, compare=False, repr=False)
    node: ast.Attribute | None = field(default=None, compare=False, repr=False)


def no_attr_line(name: object, known: Collection[str], *, most: int = 1) -> str:
    """The one line for a name no attr has: the closest attrs (up to ``most``), or, when none
    is close, the attrs there are (the first :data:`_LISTED` of them)."""
    hint = did_you_mean(name, known, most=most)
    if not hint:
        listed = ", ".join(list(known)[:_LISTED]) + (", ..." if len(known) > _LISTED else "")
        hint = f" (its attrs: {listed})" if known else " (it has no attrs)"
    return f"the grammar has no attr {name!r}{hint}"


class AttrCatalogue(Mapping[str, AttrEntry]):
    """``name -> AttrEntry`` of a loaded grammar's attrs, in file order (imported attrs under
    their import's prefix), with the checks every front end makes of attr names and values."""

    def __init__(self, grammar):
        self._grammar = grammar
        self._entries = _entries(grammar)

    def __getitem__(self, name: str) -> AttrEntry:
        return self._entries[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    @property
    def free(self) -> tuple[str, ...]:
        """The ``@Free`` attrs: those a search varies unless told otherwise."""
        return tuple(name for name, entry in self._entries.items() if entry.free)

    def no_attr(self, name: object, *, most: int = 1) -> str:
        """The line for a name no attr of this grammar has (:func:`no_attr_line`)."""
        return no_attr_line(name, list(self._entries), most=most)

    def first_unknown(self, names: Iterable[object]) -> object | None:
        """The first of ``names`` that is no attr's, or None."""
        return next((n for n in names if n not in self._entries), None)

    def ranges(self, values: Mapping[str, object] | None = None) -> dict[str, dict]:
        """``name -> {"value", "min", "max"}`` of the number attrs with a ``@Range``, its
        bounds evaluated with the attr ``values`` (defaults where not given): the attrs a
        search can vary."""
        found = self._grammar.parameter_ranges(dict(values or {}))
        return {n: spec for n, spec in found.items() if self._entries[n].kind == "number"}

    def range_warnings(
        self,
        values: Mapping[str, object],
        given: Mapping[str, object] | None = None,
        free: Collection[str] = (),
    ) -> dict[str, str]:
        """``name -> warning`` for each number of ``values`` outside its attr's ``@Range`` or
        off the range's stepsize: the one rule of ``--set``/``--fix`` and the design page.

        A range is a hint, as in CityEngine, whose annotations "do not affect the semantics of
        a rule" (they shape the Inspector's slider): such a value is used as given, never
        clamped nor refused, and gets one warning. ``restricted=false`` says any value is
        meant and gets none, except for a ``@Free`` attr (or one named in ``free``), whose
        range is the search's bounds. ``given`` holds the other attrs a bound may depend on.

        >>> import shapegen
        >>> grammar = shapegen.parse_grammar('''
        ... @Range(min=0.1, max=0.8, stepsize=0.1)
        ... attr t = 0.3
        ... @StartRule
        ... Lot --> extrude(t) Wall
        ... ''')
        >>> grammar.catalogue.range_warnings({"t": 2.0})["t"]
        't=2 is outside its @Range [0.1, 0.8]: built as given (a range is a hint, as in CityEngine)'
        >>> grammar.catalogue.range_warnings({"t": 0.5})
        {}
        """
        numbers = {
            name: float(value)
            for name, value in values.items()
            if isinstance(value, int | float) and not isinstance(value, bool)
        }
        if not numbers:
            return {}
        ranges = self.ranges({**(given or {}), **values})
        hint = "built as given (a range is a hint, as in CityEngine)"
        warnings = {}
        for name, value in numbers.items():
            spec, entry = ranges.get(name), self._entries.get(name)
            if spec is None or entry is None:
                continue
            if not entry.restricted and not (entry.free or name in free):
                continue
            low, high = spec["min"], spec["max"]
            if not low <= value <= high:
                warnings[name] = (
                    f"{name}={value:g} is outside its @Range [{low:g}, {high:g}]: {hint}"
                )
                continue
            step = entry.step
            if step is not None:
                k = (value - low) / step
                if not is_close(k, round(k), GRID_SLACK):
                    below = low + math.floor(k) * step
                    warnings[name] = (
                        f"{name}={value:g} is off its @Range stepsize {step:g} from {low:g} (the"
                        f" values nearest are {below:g} and {below + step:g}): {hint}"
                    )
        return warnings


def _entries(grammar) -> dict[str, AttrEntry]:
    nodes: Mapping[str, ast.Attribute] = grammar.program.attr_nodes
    fold = _Folder({**{c.name: c for c in grammar.ast.consts}, **nodes})
    defaults = grammar.attrs
    # CityEngine's: a @Group holds for its attr and the ones after it in its own file (an
    # import's attrs carry their import's prefix), until the next @Group
    groups: dict[tuple[str, ...], ast.Annotation] = {}
    entries = {}
    for name, node in nodes.items():
        prefix = tuple(name.split(".")[:-1])
        own = [a for a in node.annotations if a.name == "Group"]
        if own:
            groups[prefix] = own[-1]
        carried = groups.get(prefix)
        group, group_order = fold.group(carried) if carried is not None else ((), None)
        default = defaults[name]
        entries[name] = AttrEntry(
            name=name,
            kind=_kind(default, node),
            default=default,
            free=node.free,
            ranged=node.range is not None,
            **fold.choices(node),
            group=prefix + group,
            group_order=group_order if group else None,
            order=fold.number(node.annotation("Order"), 0),
            description=fold.text(node.annotation("Description")),
            display_name=fold.text(node.annotation("DisplayName")),
            hidden=node.has_annotation("Hidden"),
            unit=_unit(default, node),
            group_annotation=carried,
            node=node,
        )
    return entries


def _kind(default: object, node: ast.Attribute) -> str:
    if isinstance(default, bool):
        return "bool"
    if isinstance(default, int | float):
        return "number"
    if not isinstance(default, str):
        return "array"
    if node.has_annotation("Color"):
        return "color"
    if node.has_annotation("File") or node.has_annotation("MaterialFile"):
        return "file"
    if node.has_annotation("Directory"):
        return "directory"
    return "string"


def _unit(default: object, node: ast.Attribute) -> str | None:
    if isinstance(default, bool) or not isinstance(default, int | float):
        return None  # CityEngine's units are for numbers (of an array too: shown, not edited)
    return next((unit for name, unit in UNITS.items() if node.has_annotation(name)), None)


class _Folder:
    """Folds annotation arguments to constants (:data:`UNKNOWN` when they are not)."""

    def __init__(self, definitions: Mapping[str, object]):
        self.definitions = definitions

    def value(self, expression: ast.Expression | None):
        if expression is None:
            return UNKNOWN
        return constant_value(expression, dict(self.definitions))

    def number(self, annotation: ast.Annotation | None, position: int) -> float | None:
        if annotation is None or position >= len(annotation.args):
            return None
        value = self.value(annotation.args[position])
        return float(value) if is_number(value) else None

    def text(self, annotation: ast.Annotation | None) -> str:
        if annotation is None or not annotation.args:
            return ""
        value = self.value(annotation.args[0])
        return value if isinstance(value, str) else ""

    def flag(self, annotation: ast.Annotation, keyword: str, default: bool) -> bool:
        for given in annotation.keywords:
            if given.name == keyword:
                value = self.value(given.value)
                return value if isinstance(value, bool) else default
        return default

    def group(self, annotation: ast.Annotation) -> tuple[tuple[str, ...], float | None]:
        names, order = [], None
        for argument in annotation.args:
            value = self.value(argument)
            if isinstance(value, str):
                names.append(value)
            elif is_number(value):
                order = float(value)  # the last argument: the group's place among groups
        return tuple(names), order if names else None

    def choices(self, node: ast.Attribute) -> dict:
        """``step``, ``restricted``, ``choices``, ``values_attr``, ``extensions``."""
        found: dict = {}
        enum = node.annotation("Enum")
        ranged = node.annotation("Range")
        files = node.annotation("File")
        if ranged is not None:
            found["restricted"] = self.flag(ranged, "restricted", True)
            step = self.value(ranged.argument("stepsize", 2))
            if is_number(step) and step > 0:
                found["step"] = float(step)
            values = [self.value(a) for a in ranged.args]
            if values and all(isinstance(v, str) for v in values):
                found["choices"] = tuple(values)  # CityEngine's older @Range("a", "b")
        if enum is not None:
            found["restricted"] = self.flag(enum, "restricted", True)
            source = next((k.value for k in enum.keywords if k.name == "valuesAttr"), None)
            if isinstance(source, ast.Name):
                found["values_attr"] = source.name
            else:
                values = [self.value(a) for a in enum.args]
                values = [float(v) if is_number(v) else v for v in values]
                found["choices"] = tuple(v for v in values if isinstance(v, str) or is_number(v))
        if files is not None:
            extensions = [self.value(a) for a in files.args]
            found["extensions"] = tuple(
                e.lower().lstrip(".") for e in extensions if isinstance(e, str) and e
            )
        return found
