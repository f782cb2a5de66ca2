"""Values of a grammar's attrs and consts, and the arguments of its ``@Range``, ``@Lot`` and
``@Structure`` annotations, evaluated before (and outside) a derivation.

:class:`AttributeValues` holds a grammar's compiled attrs and consts; the
:class:`~shapegen.engine.program.interpreter.Program` makes one and asks it.
"""

from __future__ import annotations

__all__ = ["DEFAULT_LOT", "AttributeValues", "checked_structure", "shown"]

import math
from collections.abc import Callable, Mapping

import numpy as np

from shapegen.engine.attr_catalogue import no_attr_line
from shapegen.engine.derivation import random_streams
from shapegen.engine.derivation.state import TOO_DEEP, Derivation, root_state
from shapegen.engine.expressions.arrays import Array, array_from
from shapegen.engine.expressions.compiler import ExpressionCompiler, format_value, type_name
from shapegen.engine.shapes.shape import FACE, Shape, lot_scope
from shapegen.errors import GrammarError, LotError, OptionError, did_you_mean
from shapegen.grammar import ast
from shapegen.grammar.names import RESERVED_ATTRIBUTES
from shapegen.model.lot import Lot
from shapegen.model.scope import Scope

DEFAULT_LOT = (10.0, 10.0)
"""Lot width and depth (m) when neither ``@Lot`` nor the caller gives one."""


class AttributeValues:
    """Evaluation of a grammar's attrs, consts and start rule annotations for given overrides.

    Parameters
    ----------
    attr_nodes, const_nodes
        ``name -> node`` of the grammar's attrs and consts, in the file's order.
    definitions
        ``name -> compiled value`` of the same attrs and consts (``value(args, state)``).
    expressions
        The grammar's expression compiler (annotation arguments, errors at their place).
    """

    def __init__(
        self,
        attr_nodes: Mapping[str, ast.Attribute],
        const_nodes: Mapping[str, ast.Constant],
        definitions: Mapping[str, Callable],
        expressions: ExpressionCompiler,
    ):
        self.attr_nodes = attr_nodes
        self.const_nodes = const_nodes
        self.definitions = definitions
        self.expressions = expressions

    def error(self, node, message: str) -> GrammarError:
        """The error at ``node`` of the grammar (file, line, column and caret)."""
        return self.expressions.error(node, message)

    def initial_values(
        self, overrides: Mapping[str, object] | None, seed: int, lot: Scope, run=None
    ) -> dict[str, object]:
        """Values of every attr and const (with ``overrides``) and of the reserved attrs;
        warnings of their evaluation (a table file not found) go to ``run``, the derivation
        they start."""
        if overrides is not None and not isinstance(overrides, Mapping):
            raise GrammarError(
                f"attrs must be a mapping of names to values, got {shown(overrides)}"
            )
        overrides = dict(overrides or {})
        for name in overrides:
            if name in self.attr_nodes or name in RESERVED_ATTRIBUTES:
                continue
            if name in self.const_nodes:
                raise GrammarError(f"{name!r} is a const and cannot be set; only attrs can")
            raise GrammarError(no_attr_line(name, list(self.attr_nodes)))
        run = run or Derivation(self, seed)
        values: dict[str, object] = {}
        resolving: list[str] = []

        def resolve(name: str) -> object:
            if name in values:
                return values[name]
            if name in resolving:
                cycle = " -> ".join(resolving[resolving.index(name) :] + [name])
                node = self.attr_nodes.get(name) or self.const_nodes.get(name)
                raise self.error(
                    node, f"attributes and constants refer to each other in a cycle: {cycle}"
                )
            resolving.append(name)
            # an attr's default draws from a stream of its own (CityEngine's, measured)
            stream = random_streams.attr_stream(seed, name)
            state = root_state(run, Shape(lot, FACE, 1), lazy, ("attr", name), stream)
            if name in self.definitions:
                value = self.definitions[name]((), state)
            else:
                value = RESERVED_ATTRIBUTES[name]
                value = float(value) if type(value) in (int, float) else value
            if name in overrides:
                value = _coerce(name, overrides[name], value)
            resolving.pop()
            values[name] = value
            return value

        lazy = LazyValues(resolve)
        try:
            for name in (*self.attr_nodes, *self.const_nodes, *RESERVED_ATTRIBUTES):
                resolve(name)
        except RecursionError:
            raise GrammarError(TOO_DEEP) from None
        return values

    def free_parameters(
        self, values: Mapping[str, object], lot: Scope, *, only_free: bool = True
    ) -> dict[str, dict]:
        """``name -> {value, min, max}`` for the ``@Free`` attrs (bounds from ``@Range``), or,
        with ``only_free=False``, for every attr that has a ``@Range``."""
        run = Derivation(self, 0)
        state = root_state(run, Shape(lot, FACE, 1), dict(values), ("free",))
        out = {}
        for name, node in self.attr_nodes.items():
            if only_free and not node.free:
                continue
            bounds = node.range
            if bounds is None and not only_free:
                continue
            if bounds is None:
                raise self.error(node, f"@Free attr {name!r} needs a @Range(min, max)")
            try:
                low, high = (self.expressions.compile(b, {})((), state) for b in bounds)
            except GrammarError:
                if node.free:
                    raise
                continue  # a .cga inspector hint the load warned of (an undefined name)
            if not node.free and not (type(low) is float and type(high) is float):
                continue  # CityEngine's old @Range("a", "b") lists a string attr's values
            for bound in (low, high):
                if type(bound) is not float:
                    raise self.error(
                        node, f"@Range of {name!r} needs numbers, got a {type_name(bound)}"
                    )
            out[name] = {"value": values[name], "min": low, "max": high}
        return out

    def lot_size(self, start: ast.Rule, values: Mapping[str, object]) -> tuple[float, float]:
        """The ``@Lot(width, depth)`` (m) of the rule ``start``, else :data:`DEFAULT_LOT`."""
        annotation = start.annotation("Lot")
        if annotation is None:
            return DEFAULT_LOT
        run = Derivation(self, 0)
        state = root_state(run, Shape(lot_scope(*DEFAULT_LOT), FACE, 1), dict(values), ("lot",))
        size = []
        for k, keyword in enumerate(("width", "depth")):
            node = annotation.argument(keyword, k)
            value = self.expressions.compile(node, {})((), state) if node is not None else None
            if type(value) is not float:
                raise self.error(annotation, f"@Lot takes numbers (m), got {value!r}")
            size.append(value)
        try:
            return Lot.rectangle(*size).size
        except LotError as exc:
            raise self.error(annotation, f"@Lot: {exc}") from None

    def structure_arguments(
        self, start: ast.Rule, values: Mapping[str, object], lot: Scope
    ) -> dict[str, object]:
        """The keyword arguments of the ``@Structure(...)`` of the rule ``start``, evaluated with
        the attr ``values`` (empty without one): what the structure reads of this design."""
        annotation = start.annotation("Structure")
        if annotation is None or not annotation.keywords:
            return {}
        run = Derivation(self, 0)
        state = root_state(run, Shape(lot, FACE, 1), dict(values), ("structure",))
        return {
            keyword.name: self.expressions.compile(keyword.value, {})((), state)
            for keyword in annotation.keywords
        }


def checked_structure(start: ast.Rule, error: Callable) -> str:
    """At load time: the structure named by the start rule's ``@Structure`` (the default without
    one), which must be registered and given only its own keyword arguments."""
    from shapegen.structures import DEFAULT_STRUCTURE, structure_class

    annotation = start.annotation("Structure")
    if annotation is None:
        return DEFAULT_STRUCTURE
    name = annotation.args[0].value if annotation.args else None
    if not isinstance(name, str):
        raise error(annotation, "@Structure names a structure: a string")
    try:
        structure = structure_class(name)
    except OptionError as exc:
        raise error(annotation, str(exc)) from None
    given = {keyword.name for keyword in annotation.keywords}
    for keyword in annotation.keywords:
        if keyword.name not in structure.arguments:
            known = ", ".join(structure.arguments) or "none"
            hint = did_you_mean(keyword.name, structure.arguments, parenthesised=True)
            raise error(
                keyword if getattr(keyword, "location", None) else annotation,
                f"structure {name!r} has no argument {keyword.name!r}{hint}; its arguments: "
                f"{known}",
            )
    missing = [n for n, a in structure.arguments.items() if a.required and n not in given]
    if missing:
        raise error(annotation, f"@Structure({name!r}) needs the argument(s) {', '.join(missing)}")
    return name


class LazyValues(dict):
    """Attribute values computed on first read (attrs and consts may refer to each other)."""

    def __init__(self, resolve: Callable[[str], object]):
        super().__init__()
        self._resolve = resolve

    def __missing__(self, name: str) -> object:
        return self._resolve(name)


def _coerce(name: str, value: object, default: object) -> object:
    """An overriding value converted to the type of the attr's default."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(default, bool):
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in ("true", "false"):
            return value.strip().lower() == "true"
        raise GrammarError(f"attr {name!r} is true or false, got {shown(value)}")
    if isinstance(default, float):
        if isinstance(value, bool):
            raise GrammarError(f"attr {name!r} is a number, got {shown(value)}")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise GrammarError(f"attr {name!r} is a number, got {shown(value)}") from None
        except OverflowError:  # an int beyond float range (10**400)
            number = math.inf
        if not math.isfinite(number):
            raise GrammarError(f"attr {name!r} must be a finite number, got {shown(value)}")
        return number
    if isinstance(default, str):
        if isinstance(value, str):
            return value
        if isinstance(value, list | tuple | np.ndarray | Array | dict | set):
            raise GrammarError(f"attr {name!r} is a string, got {shown(value)}")
        if isinstance(value, int) and not isinstance(value, bool):
            return str(value) if abs(value) >= 10**15 else format_value(float(value))
        return format_value(value)
    if isinstance(default, Array):
        return _coerce_array(name, value, default)
    return value


_ELEMENT_NAMES = {float: "numbers", bool: "booleans", str: "strings"}


def _coerce_array(name: str, value: object, default: Array) -> Array:
    """An overriding value for an array attr: an array, a (nested) list, tuple or numpy array,
    or CGA's text of one (``"[1, 2, 3]"``, ``"[1, 2; 3, 4]"``, or ``"1, 2, 3"`` for --set),
    its elements converted to the type of the default's (numbers if it is empty)."""
    element = default.element_type()
    kind = f"an array of {_ELEMENT_NAMES.get(element, 'values')}"
    if isinstance(value, Array):
        rows = [
            list(value.values[r * value.columns : (r + 1) * value.columns])
            for r in range(value.rows)
        ]
    elif isinstance(value, np.ndarray):
        if value.ndim > 2:
            raise GrammarError(f"attr {name!r} is {kind} (at most 2 dimensions), got {value.ndim}")
        rows = value.tolist() if value.ndim == 2 else [value.tolist()]
    elif isinstance(value, list | tuple):
        nested = [isinstance(item, list | tuple) for item in value]
        if any(nested) and not all(nested):
            raise GrammarError(f"attr {name!r} is {kind}: rows and values mixed in {shown(value)}")
        rows = [list(row) for row in value] if value and all(nested) else [list(value)]
    elif isinstance(value, str):
        text = value.strip()
        if text.startswith("[") and text.endswith("]"):
            text = text[1:-1]
        rows = [[_unquoted(item.strip()) for item in row.split(",")] for row in text.split(";")]
        if rows == [[""]]:
            rows = []
    else:
        raise GrammarError(f"attr {name!r} is {kind}, got {shown(value)}")
    if element is None:  # an empty default: the text or values say which
        element = _element_type(rows)
    converted = []
    for row in rows:
        converted.append([])
        for item in row:
            try:
                converted[-1].append(_coerce(name, item, element()))
            except GrammarError:
                raise GrammarError(
                    f"attr {name!r} is {kind}, and {shown(item)} is not one of them"
                ) from None
    try:
        return array_from(converted) if converted else Array((), 0, 0, element)
    except ValueError as exc:
        raise GrammarError(f"attr {name!r}: {exc}") from None


def _unquoted(item: str) -> str:
    return item[1:-1] if len(item) >= 2 and item[0] == item[-1] == '"' else item


def _element_type(rows: list[list]) -> type:
    items = [item for row in rows for item in row]
    if items and all(isinstance(i, bool) or str(i).lower() in ("true", "false") for i in items):
        return bool
    try:
        for item in items:
            float(item)
    except (TypeError, ValueError):
        return str
    return float


def shown(value: object, width: int = 60) -> str:
    """``repr(value)`` cut to ``width`` characters (a 5 000-digit number is not echoed whole)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**20:
        return f"an integer of {round(value.bit_length() * 0.30103)} digits"
    try:
        text = repr(value)
    except ValueError:  # holds an int too long for Python to print in decimal
        return f"a {type(value).__name__} holding a number too long to print"
    return text if len(text) <= width else text[: width - 3] + "..."
