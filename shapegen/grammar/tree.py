"""The machinery every AST node shares: the frozen-dataclass decorator and the tree walk.

:func:`node` registers which fields of a node class may hold other nodes, so that
:func:`children` and :func:`walk` descend into any tree without spelling out its shape.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, fields

from shapegen.errors import SourceLocation

__all__ = ["NOWHERE", "children", "location_field", "node", "walk"]

#: Placeholder location for nodes built by hand (tests, programmatic grammars).
NOWHERE = SourceLocation("<unknown>", 0, 0)


def location_field():
    """The ``location`` field of a node: keyword-only, excluded from equality and repr."""
    return field(default=NOWHERE, compare=False, repr=False, kw_only=True)


# Per node class, the names of the fields that may hold nodes (not its location).
_NODE_FIELDS: dict[type, tuple[str, ...]] = {}


def node(cls: type) -> type:
    """Make ``cls`` a frozen dataclass and an AST node that :func:`walk` descends into."""
    cls = dataclass(frozen=True)(cls)
    _NODE_FIELDS[cls] = tuple(f.name for f in fields(cls) if f.name != "location")
    return cls


def children(tree: object) -> Iterator[object]:
    """The nodes directly below ``tree``, in field order (tuples item by item)."""
    for name in _NODE_FIELDS.get(type(tree), ()):
        value = getattr(tree, name)
        if type(value) in _NODE_FIELDS:
            yield value
        elif isinstance(value, tuple):
            yield from (item for item in value if type(item) in _NODE_FIELDS)


def walk(tree: object) -> Iterator[object]:
    """``tree`` and every node below it, depth first, each node's children in field order.

    Field order is source order, except that a definition's annotations come after its value or
    body. Iterative, so a deeply nested expression (``1 + 1 + ... + 1``) does not reach Python's
    recursion limit.
    """
    stack = [tree]
    while stack:
        current = stack.pop()
        yield current
        stack.extend(reversed(tuple(children(current))))
