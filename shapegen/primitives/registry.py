"""The registry of template primitives and the validation every primitive gets for free.

A primitive is a function ``f(scope, **params) -> list[Block]`` registered under a name::

    from shapegen.primitives import primitive, Choice

    @primitive("slab")
    def slab(scope, *, thickness: float = 0.2, finish: Choice("rough", "smooth") = "rough"):
        ...
        return [Block.from_hull(scope.to_world(corners))]

Its keyword parameters, their defaults and their annotations (``float``, ``int``, ``bool``,
``str`` or a :class:`Choice`) are read from the signature. ``insert(name, scope, **params)``
checks the names and types of the parameters, calls the function and checks its blocks (convex,
non-degenerate, finite), so authors write only the geometry; checks of values that depend on
the geometry (a thickness below the span, a count of at least 2) go through :func:`require`, so
every message names the primitive and the parameter the same way. Primitives from other
installed packages are discovered through the entry-point group ``shapegen.primitives``.
"""

from __future__ import annotations

__all__ = [
    "Choice",
    "Primitive",
    "primitive",
    "require",
    "require_blocks",
    "require_vertices",
    "REGISTRY",
]

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from shapegen.errors import GeometryError, PluginError, did_you_mean
from shapegen.limits import current_limits, limit_hint
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.model.validation import first_invalid_block
from shapegen.primitives.placement import Template, TemplateCache, canonical_scope, place
from shapegen.tolerances import DEFAULT


def require(condition: bool, primitive: str, parameter: str, problem: str) -> None:
    """Raise :class:`GeometryError` naming ``primitive`` and ``parameter`` unless ``condition``.

    ``problem`` completes the sentence "primitive 'x': parameter 'p' ...", e.g.
    ``f"must be positive, got {thickness:g} m"``.
    """
    if not condition:
        raise _parameter_error(primitive, parameter, problem)


def require_blocks(primitive: str, count: float, what: str) -> None:
    """Refuse, before any array is allocated, a primitive that would make more than
    ``max_primitive_blocks`` blocks (:class:`~shapegen.limits.WorkLimits`).

    ``count`` is the number of blocks the parameters ask for, computed as a float so that a
    tiny size (``block_length = 1e-9``) gives a huge or infinite count rather than an overflow;
    ``what`` says where it comes from (``"segments x courses"``).
    """
    limit = current_limits().max_primitive_blocks
    if not count <= limit:  # also refuses an infinite or NaN count
        shown = f"{count:.4g}" if math.isfinite(count) else "too many"
        raise GeometryError(
            f"primitive {primitive!r} would make {shown} blocks ({what}), more than "
            f"{limit} {limit_hint('max_primitive_blocks')}"
        )


VERTICES_PER_BLOCK = 64
"""A primitive may make at most this many vertices per block of ``max_primitive_blocks``: a
few blocks of very many sides (a round column of 10 000 sides) cost as much as many blocks."""


def require_vertices(primitive: str, count: float, what: str) -> None:
    """Like :func:`require_blocks`, for the vertices a primitive would make (at most
    ``VERTICES_PER_BLOCK * max_primitive_blocks``)."""
    limit = VERTICES_PER_BLOCK * current_limits().max_primitive_blocks
    if not count <= limit:
        shown = f"{count:.4g}" if math.isfinite(count) else "too many"
        raise GeometryError(
            f"primitive {primitive!r} would make {shown} vertices ({what}), more than {limit} "
            f"({VERTICES_PER_BLOCK} per block of the limit) {limit_hint('max_primitive_blocks')}"
        )


def _parameter_error(primitive: str, parameter: str, problem: str) -> GeometryError:
    return GeometryError(f"primitive {primitive!r}: parameter {parameter!r} {problem}")


class Choice:
    """A string parameter restricted to a few values; a wrong value's error lists them."""

    def __init__(self, *values: str):
        self.values = tuple(values)

    def __repr__(self) -> str:
        return "Choice(" + ", ".join(repr(v) for v in self.values) + ")"


@dataclass(frozen=True)
class PrimitiveParameter:
    """One keyword parameter of a primitive: its name, its kind (float, int, bool, str or a
    :class:`Choice`) and its default."""

    name: str
    kind: object  # float, int, bool, str or a Choice
    default: object


@dataclass(frozen=True)
class Primitive:
    """A registered primitive: its name, function and parameters."""

    name: str
    function: Callable[..., list[Block]]
    parameters: dict[str, PrimitiveParameter]
    doc: str
    scope_relative: bool = False
    templates: TemplateCache = field(default_factory=TemplateCache, compare=False, repr=False)

    def __call__(self, scope: Scope, **params) -> list[Block]:
        values = self.resolve(params)
        valid = bool(np.all(np.isfinite(scope.size)) and np.all(scope.size >= 0))
        require(
            valid, self.name, "scope", f"needs finite sides, none negative, got {scope.size_text}"
        )
        if not self.scope_relative:
            return self._checked(scope, values)
        canonical = canonical_scope(scope)
        key = (tuple(sorted(values.items())), tuple(scope.size.tolist()), canonical.rotation[2, 2])
        template = self.templates.get(key)
        if template is None:
            template = Template.of(self._checked(canonical, values), canonical)
            self.templates.put(key, template)
        else:  # the limits may have been lowered since the template was made
            require_blocks(self.name, len(template.blocks), "blocks returned")
        return place(template, scope)

    def _checked(self, scope: Scope, values: dict) -> list[Block]:
        """The function's blocks in ``scope``, each checked (convex, closed, finite)."""
        blocks = list(self.function(scope, **values))
        # A plug-in that does not call require_blocks is still held to the limit (after the
        # fact: its count parameters were bounded before the call).
        require_blocks(self.name, len(blocks), "blocks returned")
        tol = DEFAULT.for_size(float(np.linalg.norm(scope.size)) or 1.0)
        foreign = next((k for k, b in enumerate(blocks) if not isinstance(b, Block)), None)
        # All pieces at once; a bad piece before the first non-Block is the one reported.
        invalid = first_invalid_block(blocks[:foreign], tol)
        if invalid is not None:
            k, exc = invalid
            raise GeometryError(f"primitive {self.name!r}, piece {k}: {exc}") from None
        if foreign is not None:
            raise GeometryError(
                f"primitive {self.name!r} returned {type(blocks[foreign]).__name__}, not a Block"
            )
        return blocks

    def resolve(self, params: dict) -> dict:
        """Check names and types of ``params``; fill in defaults."""
        values = {}
        for key, value in params.items():
            if key not in self.parameters:
                known = ", ".join(sorted(self.parameters)) or "none"
                hint = did_you_mean(key, self.parameters, parenthesised=True)
                raise GeometryError(
                    f"primitive {self.name!r} has no parameter {key!r}{hint}; "
                    f"its parameters: {known}"
                )
            values[key] = _convert(self.name, self.parameters[key], value)
        for name, parameter in self.parameters.items():
            values.setdefault(name, parameter.default)
        return values


REGISTRY: dict[str, Primitive] = {}


def primitive(
    name: str, *, replace: bool = False, scope_relative: bool = False
) -> Callable[[Callable], Callable]:
    """Register ``function(scope, **params) -> list[Block]`` as the primitive ``name``.

    A name already taken by another function is refused unless ``replace=True`` (a plug-in that
    means to supersede a built-in primitive says so). ``scope_relative=True`` declares that the
    blocks depend only on the scope's size and the parameters, the scope's place and frame
    entering only through ``scope.to_world``: the blocks are then made and checked once per
    (size, parameters) and moved into each scope (:mod:`~shapegen.primitives.placement`).
    """

    def register(function: Callable) -> Callable:
        taken = REGISTRY.get(name)
        if taken is not None and not replace and _origin(taken.function) != _origin(function):
            raise PluginError(
                f"primitive {name!r} is already registered by {_origin(taken.function)}; choose"
                f" another name for {_origin(function)}, or pass replace=True to supersede it"
            )
        signature = inspect.signature(function)
        parameters = {}
        for param in list(signature.parameters.values())[1:]:
            if param.default is inspect.Parameter.empty:
                raise PluginError(f"primitive {name!r}: parameter {param.name!r} needs a default")
            kind = param.annotation
            if isinstance(kind, str):  # postponed annotations
                kind = eval(kind, function.__globals__, {"Choice": Choice})  # noqa: S307
            if kind is inspect.Parameter.empty:
                kind = type(param.default)
            parameters[param.name] = PrimitiveParameter(param.name, kind, param.default)
        doc = inspect.getdoc(function) or ""
        REGISTRY[name] = Primitive(name, function, parameters, doc, scope_relative)
        return function

    return register


def _origin(function: Callable) -> str:
    """``module.qualified_name`` of a function (the same after a module is reloaded)."""
    return f"{getattr(function, '__module__', '?')}.{getattr(function, '__qualname__', '?')}"


def _convert(owner: str, parameter: PrimitiveParameter, value: object) -> object:
    def problem(text: str) -> GeometryError:
        return _parameter_error(owner, parameter.name, text)

    kind = parameter.kind
    if isinstance(kind, Choice):
        if value not in kind.values:
            valid = ", ".join(repr(v) for v in kind.values)
            raise problem(f"must be one of {valid}, got {value!r}")
        return value
    if kind is bool:
        if isinstance(value, bool):
            return value
        raise problem(f"must be true or false, got {value!r}")
    if kind is int:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise problem(f"must be a whole number, got {_shown(value)}")
        if isinstance(value, float) and (not math.isfinite(value) or value != int(value)):
            raise problem(f"must be a whole number, got {value!r}")
        limit = current_limits().max_primitive_blocks
        if abs(value) > limit:  # a count (segments, rings, sides...) beyond any block budget
            raise problem(
                f"is {_shown(value)}, more than {limit} {limit_hint('max_primitive_blocks')}"
            )
        return int(value)
    if kind is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise problem(f"must be a number, got {_shown(value)}")
        try:
            number = float(value)
        except OverflowError:  # an int beyond float range
            number = math.inf
        if not math.isfinite(number):
            raise problem(f"must be a finite number, got {_shown(value)}")
        return number
    if kind is str:
        if not isinstance(value, str):
            raise problem(f"must be a string, got {value!r}")
        return value
    return value


def _shown(value: object) -> str:
    """A parameter value for a message: numbers in ``%g`` form, anything else cut short."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        try:
            return f"{value:.6g}"
        except OverflowError:
            return "a number beyond float range"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
