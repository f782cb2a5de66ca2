"""The compilers of CityEngine operations that have no AST node of their own.

The parser makes a generic :class:`~shapegen.grammar.ast.Operation` for them (``color``,
``offset``, ``roofHip``, ``alignScopeToAxes``...); the interpreter looks the name up here. A
compiler is registered with :func:`compiles` and is called as ``compiler(program, node, params)``
when the rule is compiled; it returns the operation closure ``op(state, args, out) -> bool`` of
:data:`~shapegen.engine.derivation.state.Operation`. ``program`` is the grammar's
:class:`~shapegen.engine.operations.compiler.OperationCompiler`: ``program.expressions``
(compile an argument), ``program.number(node, expression, params, what)`` (an argument that
must be a finite number), ``program.body(body, params)`` (compile a branch's body),
``program.error(node, message)`` (an error at load time) and
``program.operation_error(node, message)`` (a CGA error while deriving), ``program.cga_dialect``
and ``program.grammar``.

Each area of the language has its own module below; importing this package registers them all.
An operation honoured with a difference from CityEngine's reference (a form it refuses, a
texture-only operation accepted and ignored with a warning) is registered with the difference in
a few words, ``@compiles("name", partial="...")``; :func:`partial_notes` lists them (the
coverage table of docs/cga-compatibility.md is made from them).
"""

from __future__ import annotations

__all__ = ["DEDICATED_NOTES", "compiles", "compiler_for", "partial_notes", "warn_at"]

from collections.abc import Callable

Compiler = Callable[..., Callable]

_COMPILERS: dict[str, Compiler] = {}
_PARTIAL: dict[str, str] = {}

#: What the operations with a node of their own (compiled by
#: shapegen.engine.operations.compiler) do not honour of the reference, in a few words.
DEDICATED_NOTES: dict[str, str] = {
    "i": "reads OBJ, glTF, COLLADA, PLY and STL assets, and FBX with the optional ufbx "
    "(`shapegen[fbx]`), cleaned as CityEngine cleans them; a .usd, .dwg or .ifc asset (or an "
    ".fbx without ufbx) is a box with a warning in .cga rules (refused in .grammar ones)",
    "r": "turns about the scope's own axes: rotate(rel, pivot, ...) while they are the pivot's",
    "set": "seedian and scope.elevation cannot be set (refused when the file loads); scope.* "
    "and pivot.* are set in .cga rules",
    "split": "split(u|v, ...) runs along the scope's x or y, with a warning (no texture "
    "coordinates)",
}


def compiles(*names: str, partial: str | dict[str, str] | None = None):
    """Register the decorated function as the compiler of the operations ``names``; ``partial``
    says what of the reference it does not honour (one text for all the names, or per name)."""

    def register(function: Compiler) -> Compiler:
        for name in names:
            if name in _COMPILERS:
                raise AssertionError(f"two compilers for the operation {name!r}")
            _COMPILERS[name] = function
            note = partial.get(name) if isinstance(partial, dict) else partial
            if note:
                _PARTIAL[name] = note
        return function

    return register


def warn_at(state, node, message: str) -> None:
    """A warning of the derivation (CityEngine's runtime warns and carries on), located at the
    operation ``node`` as ``file:line:col: message``."""
    location = getattr(node, "location", None)
    state.run.warn(f"{location}: {message}" if location is not None else message)


def partial_notes() -> dict[str, str]:
    """``operation -> what of the reference it does not honour``, for those registered so."""
    return dict(_PARTIAL)


def compiler_for(name: str) -> Compiler | None:
    """The compiler of operation ``name``, or None when shapegen does not implement it."""
    return _COMPILERS.get(name)


# The modules register their compilers when imported (at the end: they import `compiles`).
from shapegen.engine.operations.cga import (  # noqa: E402, F401
    appearance,
    assets,
    extrusion,
    inline,
    modify,
    offset,
    perimeter,
    polygons,
    rectify,
    roofs,
    scatter,
    scope_fit,
    scope_ops,
    setbacks,
    split_area,
    tags,
    topology,
    transforms,
    uv_insert,
)
