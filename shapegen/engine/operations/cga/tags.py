"""Geometry tagging (cga_componentTags): ``tag(name[, auto|faces|edges|vertices])``,
``deleteTags([tagQuery[, all|faces|edges|vertices]])`` and ``setTagsFromEdgeAttrs()``.

Tags label components of the geometry; only ``isTagged()`` in a selector, ``geometry.tags`` and
``geometry.hasTags`` read them, and shapegen evaluates none of these (a rule file that uses them
is refused when it loads). So a tag can change nothing shapegen derives: the operations are
accepted, their arguments checked, and each is a warning of the derivation saying it is
ignored. ``setTagsFromEdgeAttrs`` would read the initial shape's edge attributes, which
shapegen's lots do not have.
"""

from __future__ import annotations

__all__ = ["compile_tags"]

from shapegen.engine.operations.cga import compiles, warn_at
from shapegen.engine.operations.cga.arguments import argument_word, plain_arguments
from shapegen.grammar import ast

_COMPONENTS = {
    "tag": ("auto", "faces", "edges", "vertices"),
    "deleteTags": ("all", "faces", "edges", "vertices"),
}
_COUNTS = {"tag": (1, 2), "deleteTags": (0, 2), "setTagsFromEdgeAttrs": (0, 0)}
_IGNORED = (
    "shapegen keeps no component tags (nothing it evaluates reads them: isTagged, "
    "geometry.tags and geometry.hasTags are not supported), so it is ignored"
)


@compiles(
    "tag",
    "deleteTags",
    "setTagsFromEdgeAttrs",
    partial="accepted and ignored with a warning: shapegen keeps no component tags",
)
def compile_tags(program, node: ast.Operation, params):
    low, high = _COUNTS[node.name]
    arguments = plain_arguments(program, node, range(low, high + 1))
    values = []
    if arguments:  # the name or query: a string expression
        values.append(program.expressions.compile(arguments[0], params))
    if len(arguments) == 2:
        word = argument_word(arguments[1])
        choices = _COMPONENTS[node.name]
        if word not in choices:
            raise program.error(
                node,
                f"{node.name}()'s components are one of {', '.join(choices)}; "
                f"got {word or 'a value'}",
            )
    error = program.error

    def ignored(state, args, out):
        for value in values:
            if type(value(args, state)) is not str:
                raise error(node, f"{node.name}() takes a string")
        warn_at(state, node, f"{node.name}(): {_IGNORED}")
        return True

    return ignored
