"""Template primitives: convex-block assemblies fitted to a scope (arch, vault, dome, wall...)."""

from shapegen.primitives.library import available, get, insert
from shapegen.primitives.registry import Choice, Primitive, primitive, require

__all__ = ["Choice", "Primitive", "available", "get", "insert", "primitive", "require"]
