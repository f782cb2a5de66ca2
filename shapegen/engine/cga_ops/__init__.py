"""The compilers of CityEngine operations that have no AST node of their own.

The parser makes a generic :class:`~shapegen.grammar.ast.Operation` for them (``color``,
``offset``, ``roofHip``, ``alignScopeToAxes``...); the interpreter looks the name up here. A
compiler is registered with :func:`compiles` and is called as ``compiler(program, node, params)``
when the rule is compiled; it returns the operation closure ``op(state, args, out) -> bool`` of
:data:`~shapegen.engine.derivation.Operation`. ``program`` gives ``program.expressions``
(compile an argument), ``program.error(node, message)`` and ``program._body(body, params)``
(compile a branch's body).

Each area of the language has its own module below; importing this package registers them all.
"""

from __future__ import annotations

__all__ = ["compiles", "compiler_for", "registered"]

from collections.abc import Callable

Compiler = Callable[..., Callable]

_COMPILERS: dict[str, Compiler] = {}


def compiles(*names: str) -> Callable[[Compiler], Compiler]:
    """Register the decorated function as the compiler of the operations ``names``."""

    def register(function: Compiler) -> Compiler:
        for name in names:
            if name in _COMPILERS:
                raise AssertionError(f"two compilers for the operation {name!r}")
            _COMPILERS[name] = function
        return function

    return register


def compiler_for(name: str) -> Compiler | None:
    """The compiler of operation ``name``, or None when shapegen does not implement it."""
    return _COMPILERS.get(name)


def registered() -> frozenset[str]:
    """The names of every operation with a compiler."""
    return frozenset(_COMPILERS)


# The modules register their compilers when imported (at the end: they import `compiles`).
from shapegen.engine.cga_ops import (  # noqa: E402, F401
    appearance,
    assets,
    extrusion,
    polygons,
    roofs,
    scatter,
    scope_ops,
    split_area,
    topology,
)
