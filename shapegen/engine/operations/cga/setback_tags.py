"""The auto-tags of the setback operations' edges (op_setback, "Component tags")."""

from __future__ import annotations

__all__ = ["SetbackLines", "edge_component", "tag_selector"]

import numpy as np

from shapegen.grammar import ast
from shapegen.tolerances import TAG_MATCH_REL


class SetbackLines:
    """The edges of the faces a setback cuts and the lines it sets them back to (world
    coordinates), to give its pieces' edges their auto-tags (op_setback, "Component tags"):
    on a piece of an edge's strip, ``setback.front`` the original selected edge,
    ``setback.back`` the new setback edge, ``setback.side`` the others; on the remainder,
    ``setback.back`` the setback edges, ``setback.remainder`` the original edges the setback
    did not cut and ``setback.side`` the others (the reference's picture shows the rest of a cut
    original edge as a side edge). Earlier ``setback.*`` tags are replaced; the others are kept
    as the pieces' components keep them."""

    def __init__(self):
        self.edges: list[tuple[np.ndarray, np.ndarray, bool]] = []  # start, end, set back
        self.moved: list[tuple[np.ndarray, np.ndarray]] = []  # a point and the direction

    def add(self, scope, frame, polygon: np.ndarray, distances) -> None:
        """The face ``polygon`` (2D, in the plane of ``frame``, a
        :class:`~shapegen.engine.operations.cga.polygons.FaceFrame`) set back by ``distances``
        (m, one per edge)."""
        n = len(polygon)
        world = scope.to_world(frame.lift(polygon))
        for k in range(n):
            start, end = world[k], world[(k + 1) % n]
            self.edges.append((start, end, bool(distances[k] > 0)))
            if distances[k] > 0:
                a, b = polygon[k], polygon[(k + 1) % n]
                direction = b - a
                inward = np.array([-direction[1], direction[0]]) / np.linalg.norm(direction)
                moved = scope.to_world(frame.lift(np.array([a, b]) + distances[k] * inward))
                self.moved.append((moved[0], moved[1] - moved[0]))

    def rule(self, remainder: bool):
        """The tags of a piece (a remainder one or a strip), made from the parent shape."""

        def tags(parent, shape):
            from shapegen.engine.shapes.tags import ComponentTags, carried_tags

            kept = carried_tags(parent, shape)
            if kept is not None:
                kept = kept.without_prefix("setback")
            mesh = shape.world_mesh()
            slack = TAG_MATCH_REL * max(1.0, float(mesh.size()))
            edges = dict(kept.edges) if kept is not None else {}
            for a, b in mesh.edges:
                p, q = mesh.vertices[a], mesh.vertices[b]
                edges[(a, b)] = (*edges.get((a, b), ()), self._class(p, q, remainder, slack))
            faces = kept.faces if kept is not None else ((),) * mesh.n_faces
            return ComponentTags(faces, edges, dict(kept.vertices) if kept is not None else {})

        return tags

    def _class(self, p, q, remainder: bool, slack: float) -> str:
        for start, end, moved in self.edges:
            if _on_line(p, start, end - start, slack) and _on_line(q, start, end - start, slack):
                if not remainder:
                    return "setback.front" if moved else "setback.side"
                # an original edge the setback did not cut (the picture of op_setback)
                near = [float(np.linalg.norm(a - b)) <= slack for a in (p, q) for b in (start, end)]
                whole = (near[0] and near[3]) or (near[1] and near[2])
                return "setback.remainder" if whole else "setback.side"
        for point, direction in self.moved:
            if _on_line(p, point, direction, slack) and _on_line(q, point, direction, slack):
                return "setback.back"
        return "setback.side"


def _on_line(p, point, direction, slack: float) -> bool:
    length = float(np.linalg.norm(direction))
    if length == 0:
        return False
    offset = p - point
    return float(np.linalg.norm(offset - (offset @ direction) / length**2 * direction)) <= slack


def _tag_words(key) -> bool:
    """Whether ``key`` is made of isTagged() calls, selector names and edge indices joined by
    ``&&``, ``||`` and ``!``, with at least one isTagged()."""

    def plain(node) -> bool:
        if isinstance(node, ast.Call):
            return node.name == "isTagged"
        if isinstance(node, (ast.Name, ast.ShapeAttribute, ast.Number)):
            return True
        if isinstance(node, ast.Binary) and node.op in ("&&", "||"):
            return plain(node.left) and plain(node.right)
        if isinstance(node, ast.Unary) and node.op == "!":
            return plain(node.operand)
        return False

    def tagged(node) -> bool:
        if isinstance(node, ast.Call):
            return True
        if isinstance(node, ast.Binary):
            return tagged(node.left) or tagged(node.right)
        return isinstance(node, ast.Unary) and tagged(node.operand)

    return plain(key) and tagged(key)


def tag_selector(program, key, params):
    """A setback selector written with isTagged() (op_setback: "isTagged(tagQuery): Selects
    tagged edges ... Edges can also be selected based on the tags of adjacent faces"), as
    comp(e) reads it: ``selector(component, state, args) -> bool``; None for other forms."""
    if not _tag_words(key):
        return None
    from shapegen.engine.operations.cga.comp_selectors import component_selector

    return component_selector(program, key, params, "e")


def edge_component(shape, frame, polygon, k: int, normals):
    """Edge ``k`` of the face ``polygon`` (in the plane of ``frame``) of ``shape`` as a comp(e)
    component: its mesh vertices found by position, the faces along it, its normals (scope,
    world, object), on the border."""
    from shapegen.engine.operations.cga.topology import Component

    mesh = shape.mesh()
    ends = frame.lift(np.array([polygon[k], polygon[(k + 1) % len(polygon)]]))
    a, b = (int(np.argmin(np.linalg.norm(mesh.vertices - p, axis=1))) for p in ends)
    faces = tuple(f for f, face in enumerate(mesh.faces) if a in face and b in face)
    scope_normal, world, obj = normals
    return Component(k, scope_normal, world, obj, True, shape, faces, vertices=(a, b))
