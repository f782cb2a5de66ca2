"""Rule inlining and Boolean 3D (op_inline, op_boolOp): ``inline[(append|unify|recompose)]
Rule | subdivision | { operations }`` and ``union | subtract | intersect { A | B }``.

The inlined operations are derived at once on a copy of the current shape, down to their
leaves; the leaves' geometries then replace the current shape's:

- one leaf: its shape is taken as it is (scope, geometry, attributes and look);
- several: their geometries are joined in one shape with the current shape's attributes and
  axes, the scope fitted to them: ``append`` (the default) puts the faces side by side as they
  are, ``recompose`` welds the vertices they share (shape recomposition), ``unify`` is their
  Boolean union.

A Boolean operation unifies each operand's leaves, then takes A's union, difference or
intersection with B; A gives the attributes and the scope's axes. Closed solids are combined by
manifold3d, faces lying in one plane by shapely, and other operands (an open mesh against a
solid, faces in different planes) by cutting each one's faces along the other's surface
(:mod:`shapegen.geometry.open_boolean`): an open operand is "assumed closed as long as
boundaries are not intersected": a plane's inside is the side it does not face ("everything
below the plane is regarded as inside"), another open surface's the points it winds round at
least half (as though its openings were capped); where its open boundary does cross the other
operand the reference defines no result, and the derivation warns. The pieces of one plane of
the result become polygons again (a piece with a hole stays triangles, as shapegen's faces
have no holes). Leaves deleted by ``NIL`` and edge or vertex shapes add no geometry.
"""

from __future__ import annotations

__all__ = ["derived_leaves", "joined_mesh"]

import numpy as np

from shapegen.engine.operations.cga.arguments import argument_word
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.auto_tags import boolean_tags
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.engine.shapes.tags import merged_tags, resolved_tags
from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.geometry.open_boolean import open_boolean
from shapegen.geometry.scope_frames import fitted_scope
from shapegen.grammar import ast
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL, COSINE_SLACK, ROUNDOFF_REL

_STRATEGIES = ("append", "unify", "recompose")
_BOOLEAN = ("union", "subtract", "intersect")


def derived_leaves(state, body, args, branch) -> list:
    """The leaf shape states of ``body`` derived on a copy of ``state``'s shape, as the
    interpreter derives a rule (depth first, in the order the successors are written)."""
    run = state.run
    made = state.children[0]
    child = run.child(state, state.shape, branch)
    # the inlined subtree is no successor of the shape ("collapsed and removed from the Model
    # Hierarchy"), which stays a leaf unless it has others; its draws are its own
    state.children[0] = made
    where = getattr(branch, "location", None)
    child.path = state.path + (
        "inline",
        made,
        getattr(where, "line", 0),
        getattr(where, "column", 0),
    )
    out: list = []
    if body(child, args, out) and child.is_leaf():
        out.append((child, None, ()))
    leaves, stack = [], list(reversed(out))
    while stack:
        shape_state, rule, values = stack.pop()
        if rule is None:
            leaves.append(shape_state)
            continue
        more: list = []
        if rule.body(shape_state, values, more) and shape_state.is_leaf():
            more.append((shape_state, None, ()))
        stack.extend(reversed(more))
    return leaves


def _world_meshes(program, node, leaves) -> list[Mesh]:
    meshes = []
    for leaf in leaves:
        if leaf.shape.kind not in (FACE, MASS):
            if leaf.shape.insert is not None:
                raise program.error(
                    node, f"{node.name}: shapegen's template primitives cannot be joined"
                )
            continue  # edges and vertices add no faces
        mesh = leaf.shape.world_mesh()
        if mesh.n_faces:
            meshes.append(mesh)
    return meshes


def joined_mesh(meshes: list[Mesh]) -> Mesh:
    """The faces of ``meshes`` side by side in one mesh (``append``)."""
    offsets = np.cumsum([0] + [m.n_vertices for m in meshes])
    faces = [tuple(int(i + offsets[k]) for i in f) for k, m in enumerate(meshes) for f in m.faces]
    return Mesh(np.vstack([m.vertices for m in meshes]), faces)


def _is_flat(mesh: Mesh) -> tuple[np.ndarray, float] | None:
    """The plane ``(unit normal, offset)`` all faces of ``mesh`` lie in, or None."""
    normal = polygon_normal(mesh.vertices[list(mesh.faces[0])]) if mesh.n_faces else None
    if normal is None or not np.linalg.norm(normal):
        return None
    normal = normal / np.linalg.norm(normal)
    heights = mesh.vertices @ normal
    slack = COINCIDENT_REL * max(1.0, mesh.size())
    if np.ptp(heights) > slack or any(
        float(polygon_normal(mesh.face_points(k)) @ normal) < 0 for k in range(mesh.n_faces)
    ):
        return None
    return normal, float(heights.mean())


def _plane_frame(normal: np.ndarray) -> np.ndarray:
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(helper, normal)
    u /= np.linalg.norm(u)
    return np.column_stack([u, np.cross(normal, u), normal])


def _flat_boolean(kind: str, a: Mesh, b: Mesh, plane) -> Mesh | None:
    """A 2D Boolean of two meshes in one plane (shapely), as polygons of that plane."""
    import shapely
    from shapely.geometry import Polygon

    normal, offset = plane
    frame = _plane_frame(normal)

    def region(mesh):
        flat = mesh.vertices @ frame[:, :2]
        polygons = [Polygon(flat[list(f)]).buffer(0) for f in mesh.faces]
        return shapely.unary_union(polygons)

    first, second = region(a), region(b)
    result = {"union": first.union, "subtract": first.difference, "intersect": first.intersection}[
        kind
    ](second)
    faces, points = [], []
    for polygon in getattr(result, "geoms", [result]):
        if polygon.is_empty or polygon.geom_type != "Polygon":
            continue
        pieces = [polygon] if not polygon.interiors else _triangles(polygon)
        for piece in pieces:
            ring = np.asarray(piece.exterior.coords)[:-1]
            if shapely.Polygon(ring).exterior.is_ccw is False:
                ring = ring[::-1]
            start = len(points)
            points.extend(ring @ frame[:, :2].T + normal * offset)
            faces.append(tuple(range(start, start + len(ring))))
    return Mesh(np.array(points), faces) if faces else None


def _triangles(polygon):
    import shapely

    return [
        t
        for t in shapely.delaunay_triangles(polygon).geoms
        if t.within(polygon.buffer(COINCIDENT_M))
    ]


def _solid_boolean(kind: str, meshes: list[Mesh]) -> Mesh | None:
    """A Boolean of closed solids (manifold3d): the union of all, or the first minus / and the
    union of the rest; coplanar triangles joined back into polygons."""
    from manifold3d import Manifold
    from manifold3d import Mesh as Triangles

    center = np.vstack([m.vertices for m in meshes]).mean(axis=0)

    def solid(mesh: Mesh):
        triangles = [(f[0], f[k], f[k + 1]) for f in mesh.faces for k in range(1, len(f) - 1)]
        return Manifold(
            Triangles(
                vert_properties=np.asarray(mesh.vertices - center, np.float32),
                tri_verts=np.asarray(triangles, np.uint32),
            )
        )

    solids = [solid(m) for m in meshes]
    result = solids[0]
    if kind == "union":
        for other in solids[1:]:
            result = result + other
    else:
        rest = solids[1]
        for other in solids[2:]:
            rest = rest + other
        result = result - rest if kind == "subtract" else result ^ rest
    out = result.to_mesh()
    points = np.asarray(out.vert_properties, float)[:, :3] + center
    triangles = np.asarray(out.tri_verts, dtype=np.int64)
    if len(triangles) == 0:
        return None
    return _polygons(points, triangles)


def _polygons(points: np.ndarray, triangles: np.ndarray) -> Mesh:
    """Triangles of one plane joined into polygons (holes keep their triangles). A polygon's
    corners are the triangles' own vertices, and a corner on a straight stretch of its ring is
    dropped only when no triangle of another plane uses it: a closed solid stays closed (no
    vertex of a neighbouring face left in the middle of an edge)."""
    import shapely
    from shapely.geometry import Polygon

    triangles = _welded(points, triangles)
    normals = np.cross(points[triangles[:, 1]] - points[triangles[:, 0]],
                       points[triangles[:, 2]] - points[triangles[:, 0]])  # fmt: skip
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > ROUNDOFF_REL
    triangles, normals = triangles[keep], normals[keep] / lengths[keep, None]
    scale = max(1.0, float(np.abs(points).max()))
    keys = np.round(
        np.column_stack([normals, np.einsum("ij,ij->i", normals, points[triangles[:, 0]]) / scale]),
        6,
    )
    groups = [triangles[np.all(keys == key, axis=1)] for key in np.unique(keys, axis=0)]
    planes_at = np.zeros(len(points), dtype=np.int64)  # how many planes use each vertex
    for group in groups:
        planes_at[np.unique(group)] += 1
    faces: list[tuple[int, ...]] = []
    for group in groups:
        normal = normals[np.all(triangles == group[0], axis=1)][0]
        frame = _plane_frame(normal)
        flat = points @ frame[:, :2]
        merged = shapely.unary_union([Polygon(flat[t]) for t in group])
        polygons = list(getattr(merged, "geoms", [merged]))
        if any(p.geom_type != "Polygon" or p.interiors for p in polygons):
            faces.extend(tuple(int(i) for i in t) for t in group)
            continue
        used = np.unique(group)
        for polygon in polygons:
            ring = np.asarray(polygon.exterior.coords)[:-1]
            if not shapely.Polygon(ring).exterior.is_ccw:
                ring = ring[::-1]
            # each corner back to the vertex it was made from (the nearest of the plane's)
            nearest = np.argmin(
                np.linalg.norm(ring[:, None, :] - flat[used][None, :, :], axis=2), axis=1
            )
            corners = [int(i) for i in used[nearest]]
            corners = [c for k, c in enumerate(corners) if c != corners[k - 1]]
            faces.append(_without_idle_corners(corners, flat, planes_at))
    return Mesh(points, [f for f in faces if len(f) >= 3]).cleaned()


def _welded(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """``triangles`` with the points that coincide (within round-off of the solid's size)
    replaced by one of them, so that faces meeting there share it."""
    if len(points) == 0:
        return triangles
    scale = COINCIDENT_REL * max(1.0, float(np.ptp(points, axis=0).max()))
    keys = np.round(points / scale).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    return first[inverse.reshape(-1)][triangles]


def _without_idle_corners(corners: list[int], flat: np.ndarray, planes_at) -> tuple[int, ...]:
    """The ring ``corners`` without the corners on a straight stretch that no other plane
    uses (a triangulation's inner vertex on the polygon's edge)."""
    kept = list(corners)
    changed = True
    while changed and len(kept) > 3:
        changed = False
        for k in range(len(kept)):
            before, here, after = flat[kept[k - 1]], flat[kept[k]], flat[kept[(k + 1) % len(kept)]]
            span = np.linalg.norm(after - before)
            (ax, ay), (bx, by) = here - before, after - before
            bend = abs(float(ax * by - ay * bx))
            if planes_at[kept[k]] <= 1 and bend <= COINCIDENT_REL * max(span, 1.0) * span:
                del kept[k]
                changed = True
                break
    return tuple(kept)


def _combined(program, node, strategy: str, meshes: list[Mesh], state) -> Mesh:
    if strategy == "append":
        return joined_mesh(meshes)
    if strategy == "recompose":
        return joined_mesh(meshes).cleaned()
    return _boolean(program, node, "union", meshes, state)


_EMPTY = Mesh(np.empty((0, 3)), ())


def _boolean(program, node, kind: str, meshes: list[Mesh], state) -> Mesh:
    """``kind`` of ``meshes`` (the union of all, or the first and the second): closed solids
    by manifold3d, faces in one plane in 2D, anything else by cutting each operand's faces
    along the other (:mod:`shapegen.geometry.open_boolean`), two at a time."""
    if len(meshes) == 1 and kind == "union":
        return meshes[0]
    if all(m.is_closed for m in meshes):
        result = _solid_boolean(kind, meshes)
        return result if result is not None else _EMPTY
    result = meshes[0]
    for other in meshes[1:]:
        if result.n_faces == 0:
            if kind != "union":
                return _EMPTY
            result = other
            continue
        result = _pair(program, node, kind, result, other, state)
    return result


def _pair(program, node, kind: str, a: Mesh, b: Mesh, state) -> Mesh:
    if a.is_closed and b.is_closed:
        result = _solid_boolean(kind, [a, b])
        return result if result is not None else _EMPTY
    plane_a, plane_b = _is_flat(a), _is_flat(b)
    if (
        plane_a is not None
        and plane_b is not None
        and np.allclose(plane_a[0], plane_b[0], atol=COSINE_SLACK)
        and abs(plane_a[1] - plane_b[1]) <= COINCIDENT_REL * max(1.0, abs(plane_a[1]))
    ):
        result = _flat_boolean(kind, a, b, plane_a)
        return result if result is not None else _EMPTY
    points, triangles, crossed = open_boolean(kind, a, b)
    if crossed:
        warn_at(
            state,
            node,
            f"{node.name}: the open boundary of an operand crosses the other operand, where "
            "op_boolOp defines no result (open operands are assumed closed only while their "
            "boundaries are not intersected); shapegen takes a plane's inside as the side it "
            "does not face, carried on past its outline, and another open surface's as the "
            "points it winds round at least half",
        )
    return _polygons(points, triangles) if len(triangles) else _EMPTY


def _leaf_tags(leaves, mesh: Mesh):
    """The tags of the leaves of an operand, on its unified world ``mesh``; None for none."""
    tagged = [(leaf.shape, resolved_tags(leaf.shape)) for leaf in leaves]
    if all(tags is None for _, tags in tagged):
        return None
    return merged_tags([(s.world_mesh(), t) for s, t in tagged if t is not None], mesh)


def _shape_of(mesh: Mesh, rotation: np.ndarray) -> Shape:
    if mesh.n_faces == 0:
        return Shape.with_geometry(fitted_scope(np.zeros((1, 3)), rotation)[0], mesh, MASS)
    scope, local = fitted_scope(mesh.vertices, rotation)
    flat = [k for k in range(3) if scope.size[k] <= 0]
    kind = FACE if _is_flat(mesh) is not None else MASS
    return Shape.with_geometry(scope, Mesh(local, mesh.faces), kind, flat[0] if flat else 2)


@operation(
    "inline",
    *_BOOLEAN,
    partial="an open operand whose open boundary crosses the other (no result in the "
    "reference) is still read as a plane's half-space or by its winding number, with a warning",
)
def compile_inline(program, node: ast.Operation, params):
    if node.name == "inline":
        if len(node.arguments) > 1 or len(node.branches) != 1:
            raise program.error(node, "inline takes a rule, a subdivision or { operations }")
        strategy = "append"
        if node.arguments:
            strategy = argument_word(node.arguments[0].value)
            if strategy not in _STRATEGIES:
                raise program.error(
                    node, f"inline's merge strategy is one of {', '.join(_STRATEGIES)}"
                )
    elif node.arguments or len(node.branches) != 2:
        raise program.error(node, f"{node.name} takes {{ operations A | operations B }}")
    bodies = [(program.body(b.body, params), b) for b in node.branches]

    def inline(state, args, out):
        ((body, branch),) = bodies
        leaves = derived_leaves(state, body, args, branch)
        if len(leaves) == 1:  # "In case it results in a single shape, it is taken as is"
            (leaf,) = leaves
            state.shape, state.attrs, state.appearance = leaf.shape, leaf.attrs, leaf.appearance
            return True
        meshes = _world_meshes(program, node, leaves)
        if not meshes:
            state.deleted = True  # nothing was made: the shape is gone, as after NIL
            return True
        mesh = _combined(program, node, strategy, meshes, state)
        state.shape = _shape_of(mesh, state.shape.scope.rotation)
        tagged = [(leaf.shape, resolved_tags(leaf.shape)) for leaf in leaves]
        if any(tags is not None for _, tags in tagged):  # op_inline: the leaves' tags kept
            world = [(shape.world_mesh(), tags) for shape, tags in tagged if tags is not None]
            state.shape = state.shape.with_tags(merged_tags(world, state.shape.world_mesh()))
        return True

    def boolean(state, args, out):
        operands = []
        for body, branch in bodies:
            leaves = derived_leaves(state, body, args, branch)
            meshes = _world_meshes(program, node, leaves)
            operands.append(
                (leaves, _boolean(program, node, "union", meshes, state) if meshes else None)
            )
        (a_leaves, a), (_, b) = operands
        if a is None:
            state.deleted = True
            return True
        result = a if b is None and node.name != "intersect" else (
            _boolean(program, node, node.name, [a, b], state) if b is not None else None
        )  # fmt: skip
        if result is None or result.n_faces == 0:
            state.deleted = True
            return True
        first = a_leaves[0]  # "The first operand A determines the resulting shape and attributes"
        state.attrs, state.appearance = first.attrs, first.appearance
        shape = _shape_of(result, first.shape.scope.rotation)
        operands = [
            (mesh, _leaf_tags(leaves, mesh)) for (leaves, mesh) in operands if mesh is not None
        ]
        if len(operands) == 1:
            operands.append((Mesh(np.empty((0, 3)), ()), None))
        state.shape = shape
        if state.run.tags:
            state.shape = shape.with_tags(boolean_tags(shape.world_mesh(), operands))
        return True

    return inline if node.name == "inline" else boolean
