"""A definition's ``with ( ... )`` local variables (with.html), as the compiled code sees them:
appended to the arguments of the call that reaches the definition."""

from __future__ import annotations

__all__ = ["local_scope", "with_locals"]


def local_scope(compiler, definition, params: dict[str, int]):
    """``params`` with the definition's ``with`` variables after them, and a closure
    ``extend(args, state)`` that appends their values to ``args`` (None without any):
    with.html, each is evaluated once when the definition is called, and may read the
    parameters and the variables before it."""
    if not definition.local_variables:
        return params, None
    scope = dict(params)
    compiled = []
    for index, variable in enumerate(definition.local_variables, start=len(params)):
        compiled.append(compiler.compile(variable.value, scope))
        scope[variable.name] = index

    def extend(args, state):
        values = list(args)
        for value in compiled:
            values.append(value(tuple(values), state))
        return tuple(values)

    return scope, extend


def with_locals(body, extend):
    """``body(args, state)`` with the local variables appended to ``args`` first."""
    return lambda args, state: body(extend(args, state), state)
