"""The catalogue of primitives: the built-in ones, then the plug-ins of the entry-point group
``shapegen.primitives``, loaded on first use; found by name."""

from __future__ import annotations

__all__ = ["available", "get", "insert"]


from shapegen.model import Block, Scope
from shapegen.plugins import find_registered, load_plugins
from shapegen.primitives import (  # noqa: F401  (each module registers its primitives)
    arch,
    box,
    bridge,
    buttress,
    column,
    dome,
    registry,
    vault,
    wall,
)
from shapegen.primitives.registry import Primitive


def get(name: str) -> Primitive:
    """The primitive registered as ``name``; the error suggests close names."""
    load_plugins("shapegen.primitives", "primitives")
    return find_registered(registry.REGISTRY, name, "primitive")


def available() -> list[str]:
    """Names of all registered primitives, sorted."""
    load_plugins("shapegen.primitives", "primitives")
    return sorted(registry.REGISTRY)


def insert(name: str, scope: Scope, **params) -> list[Block]:
    """Blocks of primitive ``name`` fitted to ``scope`` (world coordinates)."""
    return get(name)(scope, **params)
