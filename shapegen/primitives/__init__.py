"""Template primitives: convex-block assemblies fitted to a scope (arch, vault, dome, wall...)."""

from shapegen.primitives.registry import Choice, Primitive, available, get, insert, primitive

__all__ = ["Choice", "Primitive", "available", "get", "insert", "primitive"]
