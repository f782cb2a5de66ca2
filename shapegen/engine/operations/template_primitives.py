"""shapegen's template primitives in ``i("name", key=value)`` (``box``, ``arch``, ``column``...,
the registry of :mod:`shapegen.primitives`): which names they are, the check of a call with a
literal name when the rule loads, and the parameters of one when it is derived."""

from __future__ import annotations

__all__ = ["check_primitive_call", "is_template", "resolve_primitive"]

import difflib
from collections.abc import Callable

from shapegen.errors import OptionError
from shapegen.grammar import ast


def is_template(name: str) -> bool:
    """True when ``name`` is one of shapegen's template primitives (``box``, ``arch``...)."""
    from shapegen.primitives import get

    try:
        get(name)
    except OptionError:
        return name == "box"
    return True


def check_primitive_call(node: ast.Insert, error: Callable) -> None:
    """At load time: ``i("name", key=...)`` with a literal name must name a registered
    primitive and only its parameters (values are checked when the shape is derived)."""
    from shapegen.primitives import get

    name = node.primitive.value
    if name == "box" and not node.parameters:
        return
    try:
        primitive = get(name)
    except OptionError as exc:
        raise error(node, str(exc)) from None
    for keyword in node.parameters:
        if keyword.name not in primitive.parameters:
            known = ", ".join(sorted(primitive.parameters)) or "none"
            close = difflib.get_close_matches(keyword.name, list(primitive.parameters), n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise error(
                keyword if getattr(keyword, "location", None) else node,
                f"primitive {name!r} has no parameter {keyword.name!r}{hint}; "
                f"its parameters: {known}",
            )


def resolve_primitive(name: str, values: dict) -> dict:
    from shapegen.primitives import get

    return get(name).resolve(values)
