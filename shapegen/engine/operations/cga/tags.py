"""Geometry tagging (cga_componentTags): ``tag(name[, auto|faces|edges|vertices])``,
``deleteTags([tagQuery[, all|faces|edges|vertices]])`` and ``setTagsFromEdgeAttrs()``.

The tags are the shape's :class:`~shapegen.engine.shapes.tags.ComponentTags`; ``isTagged()``
in the selectors of comp and modify, ``geometry.tags`` and ``geometry.hasTags`` read them.
``setTagsFromEdgeAttrs`` reads the initial shape's edge attributes, which shapegen's lots do not
have: it tags nothing, with a warning.
"""

from __future__ import annotations

__all__ = ["compile_tags", "shape_tags"]

from shapegen.engine.operations.cga.arguments import argument_word, plain_arguments
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.tags import ComponentTags, resolved_tags, valid_tag
from shapegen.grammar import ast

_COMPONENTS = {
    "tag": ("auto", "faces", "edges", "vertices"),
    "deleteTags": ("all", "faces", "edges", "vertices"),
}
_COUNTS = {"tag": (1, 2), "deleteTags": (0, 2), "setTagsFromEdgeAttrs": (0, 0)}


def shape_tags(shape) -> ComponentTags:
    """The component tags of ``shape``, empty when it has none."""
    tags = resolved_tags(shape)
    return tags if tags is not None else ComponentTags.empty(shape.mesh().n_faces)


@operation(
    "tag",
    "deleteTags",
    "setTagsFromEdgeAttrs",
    partial={
        "setTagsFromEdgeAttrs": "tags nothing, with a warning: shapegen's lots have no edge "
        "attributes"
    },
)
def compile_tags(program, node: ast.Operation, params):
    low, high = _COUNTS[node.name]
    arguments = plain_arguments(program, node, range(low, high + 1))
    values = []
    if arguments:  # the name or query: a string expression
        values.append(program.expressions.compile(arguments[0], params))
    components = _COMPONENTS.get(node.name, ("",))[0]
    if len(arguments) == 2:
        components = argument_word(arguments[1])
        choices = _COMPONENTS[node.name]
        if components not in choices:
            raise program.error(
                node,
                f"{node.name}()'s components are one of {', '.join(choices)}; "
                f"got {components or 'a value'}",
            )
    error = program.error
    name = node.name

    def strings(state, args) -> list[str]:
        out = []
        for value in values:
            text = value(args, state)
            if type(text) is not str:
                raise error(node, f"{name}() takes a string")
            out.append(text)
        return out

    def tag(state, args, out):
        (text,) = strings(state, args)
        text = valid_tag(text)
        if not text:
            warn_at(state, node, "tag(): an empty tag name tags nothing")
            return True
        if not state.run.tags:  # the file never reads a tag (Program.reads_tags)
            return True
        shape = state.shape
        state.shape = shape.with_tags(shape_tags(shape).tagged(shape.mesh(), text, components))
        return True

    def delete_tags(state, args, out):
        given = strings(state, args)
        shape = state.shape
        tags = resolved_tags(shape)
        if tags is None:
            return True
        state.shape = shape.with_tags(tags.deleted(given[0] if given else None, components))
        return True

    def from_edge_attributes(state, args, out):
        warn_at(
            state,
            node,
            "setTagsFromEdgeAttrs(): shapegen's lots have no edge attributes, so it tags nothing",
        )
        return True

    return {"tag": tag, "deleteTags": delete_tags}.get(name, from_edge_attributes)
