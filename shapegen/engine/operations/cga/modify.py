"""``modify(component[, zUp|noAlign]) { selector operator operations | ... }`` (op_modify,
cga_shapeRecomposition): the selected components are derived as ``comp`` would make them, and
what they become is put back into the shape's geometry, which stays one shape with no successor.

Recomposition as shapegen does it:

- a component whose derivation ends in one shape with its components (moved, turned, scaled:
  ``t``, ``r``, ``s``, ``center``) moves its vertices; the moves of a vertex shared by several
  components are summed ("shared vertices are merged by summing their individual offsets from
  the original vertex position"), so the faces around follow;
- a face component deleted (``NIL``) leaves a hole; a face component made into other shapes
  (split, extruded...) is replaced by their faces, appended without joining them to the rest (as
  CityEngine appends what its connectivity tracking does not follow);
- an edge component made into several edges (``split(x)`` of the edge, its parts moved or
  scaled or not) is replaced in the faces around it by the chain of its parts' end points, in
  the order the parts were made, as the reference's Chaikin corner cutting and corrugated
  facade examples build their outlines: consecutive parts are joined where they meet, a moved
  part by new edges from its neighbours' ends to its own; each part's tags go on its edge;
- a vertex component made into several shapes, or an edge made into other than edges, keeps
  its place, with a warning;
- the tags the component's shape was given (``tag()``) are put on the component.

The shape keeps its scope's axes; the scope is fitted to the new geometry, as after ``inline``.
``comp.index``, ``comp.total`` and ``comp.sel`` are set as comp sets them.
"""

from __future__ import annotations

__all__ = ["compile_modify"]

import numpy as np

from shapegen.engine.operations.cga.inline import _shape_of, derived_leaves
from shapegen.engine.operations.cga.topology import (
    COMPONENT_KINDS,
    EDGE,
    _unaligned,
    component_selector,
    components_of,
    merged_shape,
    selector_text,
    selector_word,
)
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.shape import FACE, MASS
from shapegen.engine.shapes.tags import ComponentTags, merged_tags, resolved_tags
from shapegen.geometry.mesh import Mesh
from shapegen.grammar import ast
from shapegen.tolerances import COINCIDENT_M

_KINDS = COMPONENT_KINDS


@operation(
    "modify",
    partial="moves, scales and turns of components are recomposed; a face made into other "
    "shapes is appended, an edge split in parts is replaced by their chain; a vertex made into "
    "several shapes keeps its place (a warning)",
)
def compile_modify(program, node: ast.Operation, params):
    if not node.arguments or len(node.arguments) > 2:
        raise program.error(node, "modify() takes (component) or (component, zUp|noAlign)")
    kind = selector_word(node.arguments[0].value)
    if kind not in _KINDS:
        raise program.error(node, f"modify({kind}): the component is one of {', '.join(_KINDS)}")
    align = True
    if len(node.arguments) == 2:
        mode = selector_word(node.arguments[1].value)
        if mode not in ("zUp", "noAlign"):
            raise program.error(node, f"modify's alignment is zUp or noAlign, got {mode!r}")
        align = mode == "zUp"
    split_kind = "f" if kind in ("g", "m") else kind  # faces, as far as recomposing goes
    branches = []
    for branch in node.branches:
        if branch.connected:
            raise program.error(
                branch, "modify's '=:' operator is not supported by shapegen; use ':' or '='"
            )
        branches.append(
            (
                component_selector(program, branch.key, params, kind, branch),
                branch.merge,
                program.body(branch.body, params),
                branch,
                selector_text(branch.key),
            )
        )

    def modify_op(state, args, out):
        shape = state.shape
        if shape.kind not in (FACE, MASS, EDGE):
            raise program.operation_error(node, "modify() cannot take apart an inserted primitive")
        rotation = getattr(state.run, "object_rotation", None)
        components = components_of(shape, kind, rotation)
        mesh = shape.mesh()
        world = shape.scope.to_world(mesh.vertices)
        offsets = np.zeros_like(world)
        removed: set[int] = set()
        appended: list[tuple[Mesh, object]] = []
        # "chains": an edge (a, b) split in parts -> (their end points, world; tags per part)
        added: dict = {"faces": {}, "edges": {}, "vertices": {}, "chains": {}}
        taken = [False] * len(components)
        for select, merge, body, branch, text in branches:
            chosen = []
            for k, component in enumerate(components):
                if not taken[k] and select(component, state, args):
                    taken[k] = True
                    chosen.append(component)
            if not chosen:
                continue
            if merge and kind == "f" and len(chosen) > 1:
                pieces = [(merged_shape(shape, chosen), chosen)]
            else:
                pieces = [(c.shape, [c]) for c in chosen]
            if not align:  # noAlign: the components keep the shape's axes (op_comp)
                pieces = [(_unaligned(piece, shape.scope), members) for piece, members in pieces]
            for index, (piece, members) in enumerate(pieces):
                leaves = _derived(state, piece, body, args, branch, index, len(pieces), text)
                _recompose(
                    state, node, split_kind, piece, members, leaves, world, offsets, removed,
                    appended, added,
                )  # fmt: skip
        state.shape = _recomposed(shape, world + offsets, mesh, removed, appended, added)
        return True

    def _derived(state, piece, body, args, branch, index, total, text):
        def with_comp(child, args, out):
            child.comp_index, child.comp_total, child.comp_sel = index, total, text
            if not align:
                child.pivot = state.pivot
            return body(child, args, out)

        saved = state.shape
        state.shape = piece
        try:
            return derived_leaves(state, with_comp, args, branch)
        finally:
            state.shape = saved

    return modify_op


def _recompose(state, node, kind, piece, members, leaves, world, offsets, removed, appended, added):
    """Put what the component ``piece`` (of ``members``) became back: see the module."""
    kept = [leaf for leaf in leaves if not leaf.deleted]
    before = piece.world_mesh()
    vertices = [v for member in members for v in member.vertices]
    if len(kept) == 1 and _same_components(piece, kept[0].shape):
        after = kept[0].shape.world_mesh()
        mine = np.unique(np.array(vertices, dtype=int))
        for j, point in enumerate(before.vertices):  # each piece corner is one of the members'
            nearest = mine[int(np.argmin(np.linalg.norm(world[mine] - point, axis=1)))]
            offsets[nearest] += after.vertices[j] - point
        tags = resolved_tags(kept[0].shape)
        if tags is not None:
            names = tags.listed("all")
            key = {"f": "faces", "e": "edges", "fe": "edges"}.get(kind, "vertices")
            for member in members:
                where = member.mesh_faces if key == "faces" else (tuple(sorted(member.vertices)),)
                if key == "vertices":
                    where = member.vertices
                for item in where:
                    added[key].setdefault(item, []).extend(names)
        return
    if kind == "f":
        for member in members:
            removed.update(member.mesh_faces)
        for leaf in kept:
            if leaf.shape.kind in (FACE, MASS) and leaf.shape.insert is None:
                mesh = leaf.shape.world_mesh()
                if mesh.n_faces:
                    appended.append((mesh, resolved_tags(leaf.shape)))
        return
    if kind in ("e", "fe") and kept and all(leaf.shape.kind == EDGE for leaf in kept):
        (member,) = members
        _chain(member.vertices, kept, world, added["chains"])
        return
    if kept:
        warn_at(
            state,
            node,
            f"modify({kind}): a component made into {len(kept)} shapes (or other components) "
            "keeps its place: shapegen does not recompose it into the faces around it",
        )


def _chain(ends, leaves, world, chains) -> None:
    """Record the edge ``ends`` (a, b) replaced by the segments of ``leaves`` in order: the
    points between a and b (coincident ones once) and, for each part, the tags it was given
    with the positions of its two ends in the chain (0 is a, len + 1 is b)."""
    a, b = ends
    points: list[np.ndarray] = []
    parts = []
    slack = COINCIDENT_M

    def place(point) -> int:
        if float(np.linalg.norm(point - world[a])) <= slack and not points:
            return 0
        if points and float(np.linalg.norm(point - points[-1])) <= slack:
            return len(points)
        points.append(np.asarray(point, float))
        return len(points)

    for leaf in leaves:
        mesh = leaf.shape.world_mesh()
        tags = resolved_tags(leaf.shape)
        names = tuple(tags.listed("all")) if tags is not None else ()
        for i, j in mesh.faces:
            parts.append((place(mesh.vertices[i]), place(mesh.vertices[j]), names))
    if points and float(np.linalg.norm(points[-1] - world[b])) <= slack:
        points.pop()  # the last part ends at b
        parts = [(i, min(j, len(points) + 1), n) for i, j, n in parts]
    chains[(a, b)] = (points, parts)


def _same_components(piece, made) -> bool:
    """Whether ``made`` has the components of ``piece`` (moved, turned or scaled)."""
    if piece.kind != made.kind or made.insert is not None:
        return False
    a, b = piece.mesh(), made.mesh()
    return a.n_vertices == b.n_vertices and a.faces == b.faces


def _recomposed(shape, vertices, mesh, removed, appended, added):
    """The shape of the moved ``vertices`` (world) with ``mesh``'s faces but the ``removed``
    ones, then the ``appended`` world meshes' faces; tags kept by index."""
    faces = [f for k, f in enumerate(mesh.faces) if k not in removed]
    kept_index = [k for k in range(mesh.n_faces) if k not in removed]
    points = [vertices]
    count = len(vertices)
    chain_edges: dict[tuple[int, int], tuple] = {}
    if added["chains"]:
        faces, count, chain_edges = _with_chains(faces, added["chains"], points, count)
    for extra, _ in appended:
        faces += [tuple(i + count for i in f) for f in extra.faces]
        points.append(extra.vertices)
        count += extra.n_vertices
    world = Mesh(np.vstack(points), faces)
    made = _shape_of(world, shape.scope.rotation)
    if made.kind == FACE and shape.kind == MASS and not removed and not appended:
        made.kind = MASS
    old = resolved_tags(shape)
    if (
        old is None
        and not chain_edges
        and not any(added[k] for k in ("faces", "edges", "vertices"))
        and all(t is None for _, t in appended)
    ):
        return made
    old = old or ComponentTags.empty(mesh.n_faces)
    face_tags = [
        tuple(dict.fromkeys((*old.face(k), *added["faces"].get(k, ())))) for k in kept_index
    ]
    edges = dict(old.edges)
    for key, names in chain_edges.items():
        edges[key] = tuple(dict.fromkeys((*edges.get(key, ()), *names)))
    for key, names in added["edges"].items():
        edges[key] = tuple(dict.fromkeys((*edges.get(key, ()), *names)))
    vertex_tags = dict(old.vertices)
    for key, names in added["vertices"].items():
        vertex_tags[key] = tuple(dict.fromkeys((*vertex_tags.get(key, ()), *names)))
    if appended:
        more = merged_tags(list(appended), world)
        face_tags += list(more.faces[len(face_tags) :])
    return made.with_tags(ComponentTags(tuple(face_tags), edges, vertex_tags))


def _with_chains(faces, chains, points, count):
    """``faces`` with each chained edge replaced by its chain's points (appended to ``points``,
    numbered from ``count``, shared by the faces on both sides), the new count, and the tags of
    the chains' edges keyed by their sorted vertex pairs."""
    numbers = {}
    tags: dict[tuple[int, int], tuple] = {}
    for (a, b), (chain, parts) in chains.items():
        if not chain:
            continue
        numbers[(a, b)] = list(range(count, count + len(chain)))
        points.append(np.array(chain))
        nodes = [a, *numbers[(a, b)], b]
        for i, j, names in parts:
            if names and i != j:
                u, v = nodes[i], nodes[j]
                key = (u, v) if u < v else (v, u)
                tags[key] = tuple(dict.fromkeys((*tags.get(key, ()), *names)))
        count += len(chain)
    out = []
    for face in faces:
        ring = []
        for k, u in enumerate(face):
            v = face[(k + 1) % len(face)]
            ring.append(u)
            if (u, v) in numbers:
                ring += numbers[(u, v)]
            elif (v, u) in numbers:
                ring += numbers[(v, u)][::-1]
        out.append(tuple(ring))
    return out, count, tags
