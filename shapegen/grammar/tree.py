"""The machinery every AST node shares: the frozen-dataclass decorator, the tree walk and the
rebuild of a tree with some nodes changed.

:func:`node` registers which fields of a node class may hold other nodes, so that
:func:`children` and :func:`walk` descend into any tree without spelling out its shape.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterator
from dataclasses import dataclass, field, fields

from shapegen.errors import SourceLocation

__all__ = ["NOWHERE", "children", "location_field", "node", "rebuilt", "walk"]

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


def rebuilt(tree, change, params: frozenset[str] = frozenset()):
    """``tree`` rebuilt bottom-up with ``change(node, params)`` applied to every node (a dict of
    fields to replace, or None); unchanged subtrees are kept as they are."""
    if isinstance(tree, tuple):
        items = tuple(rebuilt(item, change, params) for item in tree)
        return tree if all(a is b for a, b in zip(items, tree, strict=True)) else items
    if not dataclasses.is_dataclass(tree) or isinstance(tree, type):
        return tree
    changes = {}
    for member in dataclasses.fields(tree):
        if member.name == "location":
            continue
        value = getattr(tree, member.name)
        if isinstance(value, tuple) or dataclasses.is_dataclass(value):
            new = rebuilt(value, change, params)
            if new is not value:
                changes[member.name] = new
    if changes:
        tree = dataclasses.replace(tree, **changes)
    replaced = change(tree, params)
    if replaced is None:
        return tree
    if isinstance(replaced, dict):
        return dataclasses.replace(tree, **replaced)
    return replaced
