"""CityEngine's component split: ``comp(f)``, ``comp(e)``, ``comp(v)``, ``comp(fe)``, ``comp(fv)``,
``comp(h)``.

The components of a shape's geometry (a box filling its scope when it has none) become new
shapes, with scopes as op_comp sets them:

- a face: x along its first edge, z along its normal, the scope its bounding box (sz = 0);
  indices in the geometry's face order (for an extruded lot: 0 bottom, 1 top, then the sides
  from the lot's first edge, as PyPRT gives);
- an edge (``e``): x along the edge, z along the mean of its faces' normals, size (length, 0, 0);
  edges are numbered around the faces in order, a shared edge counted once;
- a face edge (``fe``): every face's edges, x in the face's direction, z out of the face in its
  plane;
- a vertex (``v``): the origin at the vertex, z along the mean of its faces' normals, size 0;
- a face vertex (``fv``): every face's corners, x along the bisector of the face's edges coming
  in and leaving (along the edge on an edge's ends), y the face normal, z out of the face in its
  plane, size 0;
- a hole (``h``): every face's holes, face by face, each a face of its own turned to face as its
  face does (its ring reversed, so that its first edge is the hole's first edge turned round),
  its scope and pivot as a face's.

A face's holes are rings of edges and corners as its outline is: ``e``, ``fe``, ``v`` and ``fv``
count them as CityEngine's runtime does (:func:`_face_rings`: a flat face's outline, then its
holes; an extruded courtyard's outer rings, then the holes of its bottom and top, then its inner
walls), and a border edge is one of a single ring (tests/data/prt_comp_holes.json).

Selectors are exclusive from left to right. ``sel : A`` makes one shape per component,
``sel = A`` one shape of all of them. A selector is a name (``front``, ``world.up``,
``object.side``, ``vertical``, ``border``... see :data:`shapegen.geometry.queries.
FACE_SELECTORS`), an index, ``||``/``&&``/``!`` of those, or any boolean expression evaluated on
the component's shape (``geometry.area() > 1``).
"""

from __future__ import annotations

__all__ = [
    "COMPONENT_KINDS",
    "COMP_CAME_TO_NOTHING",
    "EDGE",
    "compile_comp",
    "comp_operation",
    "component_selector",
    "components_of",
    "connected_sets",
    "face_components",
    "holes_shape",
    "merged_shape",
    "selector_text",
    "selector_word",
]

from dataclasses import dataclass

import numpy as np

from shapegen.engine.operations.cga.comp_selectors import component_selector, selector_text
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.boxes import box_faces_of, extruded_backwards
from shapegen.engine.shapes.shape import FACE, MASS, Shape, face_scopes
from shapegen.engine.shapes.trim import comp_trim_planes
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.queries import border_faces
from shapegen.geometry.roof_edges import ROOF_EDGE_CLASSES, roof_edge_classes
from shapegen.geometry.scope_frames import (
    face_rotation,
    fills_rectangle,
    fitted_face_scopes,
    fitted_scope,
    rotation_keeping_x,
)
from shapegen.grammar import ast
from shapegen.model.scope import Scope
from shapegen.tolerances import COSINE_SLACK, ZERO_LENGTH, is_zero

EDGE = "edge"
COMP_CAME_TO_NOTHING = "comp came to nothing"
"""``ShapeState.deleted`` of a component whose comp chose nothing, or whose chosen components
all came to nothing: it leaves no leaf, and its own comp counts it as nothing (``comp_op``)."""
VERTEX = "vertex"
COMPONENT_KINDS = ("f", "e", "v", "fe", "fv", "g", "m", "h")
_ROOF_EDGES = ROOF_EDGE_CLASSES
_HOLE_SELECTORS_IGNORED = (  # PyPRT's words
    "comp(): comp(h) does not support border and inside selectors; ignoring selector."
)


@dataclass
class Component:
    """One component: its index, its normals (scope, world and object frames), whether it is on
    the border, and the shape it becomes."""

    index: int
    normal: np.ndarray
    world: np.ndarray
    object: np.ndarray
    border: bool
    shape: Shape
    mesh_faces: tuple[int, ...] = ()
    roof: str = ""  # comp(e): eave, hip, valley, ridge or "" (shapegen.geometry.roof_edges)
    first: np.ndarray | None = None  # the pivot's origin (op_comp): the first vertex, world
    vertices: tuple[int, ...] = ()  # its vertices in the shape's mesh (isTagged reads them)


def face_components(shape: Shape, object_rotation: np.ndarray | None) -> list[Component]:
    """The faces of ``shape`` as components, in its geometry's order."""
    scope = shape.scope
    box = box_faces_of(shape)
    if box is not None:  # a box or a rectangle: each face's scope from a table
        shapes = [Shape(s, FACE, 2) for s in box.face_scopes(scope)]
        firsts = [s.scope.o for s in shapes]  # origins: each face's first corner
        normals, borders, faces = box.normals, [box.border] * len(shapes), box.faces
    elif shape.geometry is None and shape.kind == MASS:
        mesh = Mesh.box(scope.size)
        scopes = [s for _, s in face_scopes(scope)]
        shapes, normals, borders = [Shape(s, FACE, 2) for s in scopes], mesh.face_normals(), [0] * 6
        firsts, faces = [s.origin for s in scopes], mesh.faces
    else:
        mesh = shape.mesh()
        shapes, firsts = _face_shapes(mesh, scope)
        normals, borders, faces = mesh.face_normals(), border_faces(mesh), mesh.faces
    worlds = normals @ scope.rotation.T
    objects = worlds if object_rotation is None else worlds @ object_rotation
    if extruded_backwards(shape):  # CityEngine's scope.sy < 0: top and bottom change places
        normals = normals * np.array([1.0, -1.0, 1.0])
    return [
        Component(
            k,
            normals[k],
            worlds[k],
            objects[k],
            bool(borders[k]),
            shapes[k],
            (k,),
            first=firsts[k],
            vertices=tuple(faces[k]),
        )
        for k in range(len(shapes))
    ]


def _face_shapes(mesh: Mesh, scope: Scope) -> tuple[list[Shape], list]:
    """The faces of ``mesh`` (in ``scope``) as face shapes, and each one's first corner
    (world): the faces of one corner count framed and fitted together, as a batch."""
    world_vertices = scope.to_world(mesh.vertices)
    world_normals = mesh.face_normals() @ scope.rotation.T
    faces = mesh.faces
    by_count: dict[int, list[int]] = {}
    for k, face in enumerate(faces):
        by_count.setdefault(len(face), []).append(k)
    shapes, firsts = [None] * len(faces), [None] * len(faces)
    for members in by_count.values():
        points = world_vertices[np.array([faces[k] for k in members])]
        origins, rotations, sizes, local = fitted_face_scopes(points, world_normals[members])
        fills = fills_rectangle(local, sizes)
        for row, k in enumerate(members):
            face_scope = Scope.of_arrays(origins[row], rotations[row], sizes[row])
            if mesh.holes and mesh.holes[k]:  # the face keeps its holes (op_comp)
                holed = _holed_face(mesh, k, world_vertices, face_scope)
                shapes[k] = Shape.with_geometry(face_scope, holed, FACE, 2)
            elif fills[row]:  # the rectangle filling its scope from its origin: the fast path
                shapes[k] = Shape(face_scope, FACE, 2)
            else:
                shapes[k] = Shape.with_geometry(face_scope, Mesh.polygon(local[row]), FACE, 2)
            firsts[k] = points[row, 0]
    return shapes, firsts


def _holed_face(mesh: Mesh, k: int, world: np.ndarray, scope: Scope) -> Mesh:
    """Face ``k`` of ``mesh`` (its vertices ``world``) with its holes, in its ``scope``."""
    face = Mesh.of_valid_faces(world, mesh.faces, holes=mesh.holes).subset([k])
    return face.moved_to(scope.to_local(face.vertices))


def _face_rings(mesh: Mesh) -> list[tuple[int, tuple]]:
    """Every face's rings in the order CityEngine counts their edges and corners: ``(face,
    ring)``. The outlines come in face order, and the holes (wound against their faces; face by
    face, each face's in order) all come just before the first face whose outline runs along one
    of them (an extruded courtyard's inner walls: the bottom's holes, the top's, then the walls),
    or after the last face (tests/data/prt_comp_holes.json, CityEngine's runtime)."""
    if not mesh.holes:
        return list(enumerate(mesh.faces))
    holes = [(f, ring) for f, rings in enumerate(mesh.holes) for ring in rings or ()]
    hole_edges = {
        frozenset(pair) for _, ring in holes for pair in zip(ring, ring[1:] + ring[:1], strict=True)
    }
    out = []
    for f, face in enumerate(mesh.faces):
        if holes and any(
            frozenset(pair) in hole_edges for pair in zip(face, face[1:] + face[:1], strict=True)
        ):
            out += holes
            holes = []
        out.append((f, face))
    return out + holes


def holes_shape(shape: Shape) -> Shape:
    """The holes of ``shape``'s faces as the faces of one shape in its scope (what ``comp(h)``
    takes apart): each hole's ring reversed, so that it faces as its face does and its first
    edge is the hole's first edge turned round (``b, a, ...``), as CityEngine's runtime gives
    them; no faces when there are no holes."""
    mesh = shape.geometry
    holes = mesh.holes if mesh is not None else ()
    rings = [ring for rings in holes for ring in rings or ()]
    faces = tuple(tuple(ring[1::-1]) + tuple(ring[:1:-1]) for ring in rings)
    if not faces:
        return Shape.with_geometry(shape.scope, Mesh(np.empty((0, 3)), ()), FACE, 2)
    faced = Mesh(mesh.vertices, faces).subset(range(len(faces)))  # only the holes' corners
    return Shape.with_geometry(shape.scope, faced, FACE, 2)


def _edge_components(shape: Shape, object_rotation, per_face: bool) -> list[Component]:
    scope = shape.scope
    mesh = shape.mesh()
    world_vertices = scope.to_world(mesh.vertices)
    face_normals = mesh.face_normals() @ scope.rotation.T
    rings = _face_rings(mesh)
    # a roof's sheets share no edge: an edge where two meet is an edge of each (CityEngine's
    # runtime lists it once for each sheet)
    sheet = mesh.sheets or (0,) * mesh.n_faces
    edge_faces: dict[tuple[int, int, object], list[int]] = {}
    for f, face in rings:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            edge_faces.setdefault((min(a, b), max(a, b), sheet[f]), []).append(f)
    out = []
    if per_face:
        pairs = [
            (a, b, f, sheet[f])
            for f, face in rings
            for a, b in zip(face, face[1:] + face[:1], strict=True)
            if a != b
        ]
        roofs = [("", False)] * len(pairs)
    else:
        pairs = [(a, b, None, s) for a, b, s in _ordered_edges(rings, sheet)]
        # in scope coordinates: op_comp's selectors read the shape's own axes, y up
        edges = [(a, b) for a, b, _, _ in pairs]
        roofs = roof_edge_classes(
            mesh.vertices,
            mesh.faces,
            edges,
            mesh.holes,
            mesh.sheets,
            [s for *_, s in pairs] if mesh.sheets else None,
        )
    for k, ((a, b, f, s), (roof, turn)) in enumerate(zip(pairs, roofs, strict=True)):
        if turn:  # hips, valleys and ridges run up the scope's y; eaves as their face runs
            a, b = b, a
        start, end = world_vertices[a], world_vertices[b]
        faces = edge_faces[(min(a, b), max(a, b), s)]
        if f is None:
            z = face_normals[faces].sum(axis=0)
        else:
            z = np.cross(end - start, face_normals[f])  # out of the face, in its plane (op_comp)
        x = end - start
        length = float(np.linalg.norm(x))
        if length == 0:
            continue
        rotation = _frame(x / length, z)
        edge_scope = Scope(start, rotation, np.array([length, 0.0, 0.0]))
        geometry = Mesh([(0, 0, 0), (length, 0, 0)], [(0, 1)])
        normal_world = rotation[:, 2]
        out.append(
            Component(
                k,
                scope.rotation.T @ normal_world,
                normal_world,
                normal_world if object_rotation is None else object_rotation.T @ normal_world,
                len(faces) == 1,
                Shape.with_geometry(edge_scope, geometry, EDGE, 2),
                tuple(faces),
                roof,
                start,
                (a, b),
            )
        )
    return out


def _ordered_edges(rings, sheet) -> list[tuple[int, int, object]]:
    """Edges in CityEngine's order: around the first ring of :func:`_face_rings`, then the next,
    shared ones once in each sheet (``sheet``: per face, :attr:`Mesh.sheets`); each in the
    direction of the ring that met it first, with the sheet it is listed for."""
    seen = set()
    out = []
    for f, face in rings:
        for a, b in zip(face, face[1:] + face[:1], strict=True):
            key = (min(a, b), max(a, b), sheet[f])
            if a != b and key not in seen:
                seen.add(key)
                out.append((a, b, sheet[f]))
    return out


def _vertex_components(shape: Shape, object_rotation) -> list[Component]:
    scope = shape.scope
    mesh = shape.mesh()
    world_vertices = scope.to_world(mesh.vertices)
    face_normals = mesh.face_normals() @ scope.rotation.T
    # a roof's sheets share no corner: a corner where sheets meet is one of each (CityEngine's
    # runtime lists it once for each sheet, the sheets in face order)
    sheet = mesh.sheets or (0,) * mesh.n_faces
    touching: dict[tuple[int, object], list[int]] = {}
    uses: dict[tuple[frozenset, object], int] = {}
    for f, face in _face_rings(mesh):
        for i in face:
            touching.setdefault((i, sheet[f]), []).append(f)
        for pair in zip(face, face[1:] + face[:1], strict=True):
            key = (frozenset(pair), sheet[f])
            uses[key] = uses.get(key, 0) + 1
    # op_comp: "border vertices are start or end point of one or more border edges", an edge
    # of one face (a hole's ring is an edge of its face, so an extruded courtyard has none)
    on_border = {(i, s) for (edge, s), count in uses.items() if count == 1 for i in edge}
    if mesh.sheets:
        order = list(dict.fromkeys(mesh.sheets))
        listed = sorted(touching, key=lambda key: (order.index(key[1]), key[0]))
    else:
        listed = [(k, 0) for k in range(mesh.n_vertices)]
    out = []
    for index, (k, s) in enumerate(listed):
        faces = touching.get((k, s), [])
        z = face_normals[faces].sum(axis=0) if faces else scope.rotation[:, 1]
        rotation = _vertex_frame(scope.rotation[:, 0], z)
        normal_world = rotation[:, 2]
        vertex_scope = Scope(world_vertices[k], rotation, np.zeros(3))
        out.append(
            Component(
                index,
                scope.rotation.T @ normal_world,
                normal_world,
                normal_world if object_rotation is None else object_rotation.T @ normal_world,
                (k, s) in on_border,
                Shape.with_geometry(vertex_scope, Mesh([(0, 0, 0)], ()), VERTEX, 2),
                tuple(faces),
                first=world_vertices[k],
                vertices=(k,),
            )
        )
    return out


def _face_vertex_components(shape: Shape, object_rotation) -> list[Component]:
    """comp(fv): every corner of every face; x along :func:`_corner_tangent`, y the face normal,
    z = x cross y (out of the face, in its plane), size 0."""
    scope = shape.scope
    mesh = shape.mesh()
    world_vertices = scope.to_world(mesh.vertices)
    normals = mesh.face_normals() @ scope.rotation.T
    borders = border_faces(mesh)
    out = []
    for f, face in _face_rings(mesh):
        for j, i in enumerate(face):
            tangent = _corner_tangent(
                world_vertices[face[j - 1]],
                world_vertices[i],
                world_vertices[face[(j + 1) % len(face)]],
            )
            rotation = rotation_keeping_x(tangent, normals[f]) if tangent.any() else None
            if rotation is None or not normals[f].any():
                continue
            out.append(
                Component(
                    len(out),
                    scope.rotation.T @ rotation[:, 2],
                    rotation[:, 2],
                    rotation[:, 2]
                    if object_rotation is None
                    else object_rotation.T @ rotation[:, 2],
                    borders[f],
                    Shape.with_geometry(
                        Scope(world_vertices[i], rotation, np.zeros(3)),
                        Mesh([(0, 0, 0)], ()),
                        VERTEX,
                        2,
                    ),
                    (f,),
                    first=world_vertices[i],
                    vertices=(i,),
                )
            )
    return out


def _corner_tangent(before: np.ndarray, corner: np.ndarray, after: np.ndarray) -> np.ndarray:
    """A face corner's x (comp(fv)): the bisector of the directions of the edge coming in and of
    the edge leaving, as CityEngine's runtime gives it (tests/data/prt_comp_holes.json: a
    square's corners at 45 degrees), or the edge leaving where the two cancel (an edge's two
    ends: op_comp, "if applied on an edge component the tangent/x-axis point along the edge")."""
    leaving, coming = after - corner, corner - before
    out_length, in_length = float(np.linalg.norm(leaving)), float(np.linalg.norm(coming))
    if out_length == 0 or in_length == 0:
        return leaving
    bisector = leaving / out_length + coming / in_length
    return bisector if np.linalg.norm(bisector) > COSINE_SLACK else leaving  # opposite: cancel


def _vertex_frame(scope_x: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """A vertex's axes as CityEngine's runtime sets them (measured with PyPRT on flat and
    extruded lots whose first edges run along x and along z, tests/data/prt_comp_holes.json):
    z the vertex normal (the sum of its faces' normals), x square to it and to the shape's scope
    x (z cross scope x), y = z cross x. A normal along the scope's x keeps :func:`_frame`'s."""
    length = float(np.linalg.norm(normal))
    if length == 0:
        return _frame(scope_x, normal)
    z = normal / length
    x = np.cross(z, scope_x)
    across = float(np.linalg.norm(x))
    if is_zero(across, ZERO_LENGTH):
        return _frame(scope_x, z)
    x = x / across
    return np.column_stack([x, np.cross(z, x), z])


def _frame(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Columns x, y, z with x along ``x`` and z as close to ``z`` as possible."""
    length = float(np.linalg.norm(z))
    if length == 0:
        z = np.array([0.0, 1.0, 0.0])
    frame = rotation_keeping_x(np.asarray(x, float), np.asarray(z, float))  # x, y := z
    # rotation_keeping_x puts the second argument on y; turn it so it is on z instead
    return np.column_stack([frame[:, 0], -frame[:, 2], frame[:, 1]])


def merged_shape(shape: Shape, chosen: list[Component]) -> Shape:
    """All ``chosen`` faces as one shape, in the frame of the first."""
    faces = [f for c in chosen for f in c.mesh_faces]
    box = box_faces_of(shape)
    if box is not None:  # a box or a rectangle: in closed form
        return Shape.with_geometry(*box.merged(shape.scope, faces), FACE, 2)
    mesh = shape.mesh()
    subset = mesh.subset(faces)
    world = shape.scope.to_world(subset.vertices)
    first = shape.scope.to_world(mesh.face_points(faces[0]))
    rotation = face_rotation(first, shape.scope.rotation @ mesh.lone_face_normal(faces[0]))
    scope, local = fitted_scope(world, rotation)
    return Shape.with_geometry(
        scope, Mesh.of_valid_faces(local, subset.faces, holes=subset.holes), FACE, 2
    )


# ---------------------------------------------------------------------------- the operation
def comp_operation(program, node, kind: str, branches, params, align: bool = True):
    """The closure of ``comp(kind) { ... }``; ``branches`` are ``(key, merge, body, node)``."""
    if kind not in COMPONENT_KINDS:
        raise program.error(
            node,
            f"comp({kind}) is not supported by shapegen; it splits into f, e, v, fe, fv, g, m or h",
        )
    compiled = [
        (
            component_selector(program, key, params, kind, branch),
            merge,
            body,
            branch,
            selector_text(key),
        )
        for key, merge, body, branch in branches
    ]
    error = program.error
    trims = program.cga_dialect
    # op_comp: border and inside "do not work on holes": PyPRT's comp(h) takes no hole with them
    # and warns once for the split, holes or not (tests/data/prt_comp_holes.json)
    ignored = kind == "h" and any(text in ("border", "inside") for *_, text in compiled)

    def comp_op(state, args, out):
        shape = state.shape
        if shape.kind not in (FACE, MASS, EDGE):
            raise error(node, f"comp({kind}) cannot take apart an inserted primitive")
        if ignored:
            warn_at(state, node, _HOLE_SELECTORS_IGNORED)
        components = components_of(shape, kind, getattr(state.run, "object_rotation", None))
        source = holes_shape(shape) if kind == "h" else shape  # whose faces are merged
        taken = [False] * len(components)
        run = state.run
        planes = None
        if trims and kind == "f":
            planes = comp_trim_planes(shape, [c.shape for c in components])
        before = state.children[0]
        made = came_to_nothing = 0
        for select, merge, body, branch, text in compiled:
            chosen = []
            for k, component in enumerate(components):
                if not taken[k] and select(component, state, args):
                    taken[k] = True
                    chosen.append(component)
            if not chosen:
                continue
            groups = [chosen]
            if getattr(branch, "connected", False):  # =: a shape per connected set
                groups = connected_sets(shape.mesh(), chosen)
            if merge and kind in ("f", "h"):
                shapes = [merged_shape(source, group) for group in groups]
                firsts = [group[0].first for group in groups]
            else:
                shapes = [c.shape for c in chosen]
                firsts = [c.first for c in chosen]
            # op_comp: the pivot at the (first) component's first vertex, along its scope
            if not align:
                shapes = [_unaligned(s, shape.scope) for s in shapes]
            total = len(shapes)
            for index, piece in enumerate(shapes):
                child = run.child(state, piece, branch)
                child.comp_index = index
                child.comp_total = total
                child.comp_sel = text
                if align and firsts[index] is not None:  # noAlign keeps the pivot
                    child.pivot = (firsts[index], piece.scope)  # read: frames.pivot_frame
                if planes is not None:  # op_comp: only the ':' operator makes trim planes
                    child.trim_planes = () if merge else planes[chosen[index].index]
                made += 1
                if body(child, args, out) and child.is_leaf():
                    out.append((child, None, ()))
                came_to_nothing += child.deleted is COMP_CAME_TO_NOTHING
        if came_to_nothing == made:
            # nothing chosen, or every chosen component came to nothing: as CityEngine's
            # runtime does (PyPRT 1.12, envelope2002's rules rewritten in their compiled
            # form), a component made by a comp or a split vanishes and tells its own comp so,
            # and a shape a rule made goes on as it was (envelope2002's narrow floors stay
            # whole when comp(f){bottom: offset(-1) comp(f){inside: ...}} finds no inside, and
            # so does a comp(f){border: ...} of a closed box; the ground floor plan's
            # offset(-2), whose inside vanishes too, leaves no border)
            if state.piece:
                if state.children[0] == before:
                    state.deleted = COMP_CAME_TO_NOTHING
                else:
                    state.deleted = True
            else:
                state.children[0] = before
        return True

    return comp_op


def components_of(shape: Shape, kind: str, object_rotation) -> list[Component]:
    """The components of ``shape`` of one ``kind`` (f, e, fe, fv, v, h, g or m), in CityEngine's
    order."""
    if kind == "f":
        return face_components(shape, object_rotation)
    if kind == "h":
        return face_components(holes_shape(shape), object_rotation)
    if kind in ("e", "fe"):
        return _edge_components(shape, object_rotation, kind == "fe")
    if kind == "fv":
        return _face_vertex_components(shape, object_rotation)
    if kind in ("g", "m"):
        return _whole_components(shape, object_rotation)
    return _vertex_components(shape, object_rotation)


def _whole_components(shape: Shape, object_rotation) -> list[Component]:
    """comp(g) and comp(m): shapegen's geometry is one group of one material, so there is one
    component, the whole shape. It meets a selector when one of its faces does (op_comp: "Group
    and material components satisfy a specific selection keyword if at least one geometric
    component (usually a face) satifies it"); shapegen takes the first face's normal."""
    faces = face_components(shape, object_rotation)
    if not faces:
        return []
    first = faces[0]
    mesh = shape.mesh()
    return [
        Component(
            0,
            first.normal,
            first.world,
            first.object,
            any(f.border for f in faces),
            shape.copy(),
            tuple(range(mesh.n_faces)),
            first=first.first,
            vertices=tuple(range(mesh.n_vertices)),
        )
    ]


def _unaligned(piece: Shape, parent: Scope) -> Shape:
    """``noAlign``: the component in the parent's scope axes, the scope fitted to it."""
    world = piece.scope.to_world(piece.mesh().vertices)
    scope, local = fitted_scope(world, parent.rotation)
    return Shape.with_geometry(scope, piece.mesh().moved_to(local), piece.kind, piece.normal_axis)


@operation(
    "comp",
    nodes=(ast.Comp, ast.Operation),
    partial="refused: =: on edges, vertices and holes; g and m give one component, the whole "
    "geometry (shapegen's meshes have one group and one material)",
)
def compile_comp(program, node: ast.Comp | ast.Operation, params):
    """``comp(f|e|v|fe|fv|h [, zUp|noAlign]) { selector : body | ... }``: the parser's
    :class:`~shapegen.grammar.ast.Comp` (``comp(f) { ... }``) or a generic operation (with an
    alignment)."""
    if type(node) is ast.Comp:
        kind, align = node.kind, True
        keys = [branch.selector for branch in node.branches]
    elif not node.arguments:
        raise program.error(node, "comp() needs the kind of component: comp(f), comp(e)...")
    else:
        kind = selector_word(node.arguments[0].value)
        align = True
        if len(node.arguments) > 1:
            mode = selector_word(node.arguments[1].value)
            if mode not in ("zUp", "noAlign"):
                raise program.error(node, f"comp's alignment is zUp or noAlign, got {mode!r}")
            align = mode == "zUp"
        keys = [branch.key for branch in node.branches]
    for branch in node.branches:
        if branch.connected and kind != "f":
            raise program.error(
                branch,
                f"comp's '=:' operator (a shape per connected set of components) is supported "
                f"by shapegen for faces, not comp({kind})",
            )
    branches = [
        (key, branch.merge, program.body(branch.body, params), branch)
        for key, branch in zip(keys, node.branches, strict=True)
    ]
    return comp_operation(program, node, kind, branches, params, align)


def connected_sets(mesh: Mesh, chosen: list[Component]) -> list[list[Component]]:
    """The face components ``chosen`` in sets connected by shared edges (op_comp's ``=:``: "Two
    components are connected if their faces share an edge"), each in the order chosen, the sets
    in the order of their first component."""
    parent = list(range(len(chosen)))

    def root(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    seen: dict[tuple[int, int], int] = {}
    for k, component in enumerate(chosen):
        for f in component.mesh_faces:
            face = mesh.faces[f]
            for a, b in zip(face, face[1:] + face[:1], strict=True):
                key = (a, b) if a < b else (b, a)
                if key in seen:
                    parent[root(k)] = root(seen[key])
                else:
                    seen[key] = k
    sets: dict[int, list[Component]] = {}
    for k, component in enumerate(chosen):
        sets.setdefault(root(k), []).append(component)
    return list(sets.values())


def selector_word(expression) -> str:
    if isinstance(expression, ast.Name):
        return expression.name
    if isinstance(expression, ast.String):
        return expression.value
    return type(expression).__name__
