"""Template primitives: convex-block assemblies fitted to a scope (arch, vault, dome, wall...)."""

from shapegen.primitives.registry import (
    Choice,
    Primitive,
    available,
    get,
    insert,
    primitive,
    require,
)

__all__ = ["Choice", "Primitive", "available", "get", "insert", "primitive", "require"]
