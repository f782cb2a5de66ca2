"""CityEngine's polygon operations on faces, innerRectangle and footprint, and what they share
with the setbacks (:mod:`.setbacks`) and offset (:mod:`.offset`): faces laid in their planes,
shapes made of flat faces, branches of edge selectors.

Each acts on every face of a flat shape (the lot, a ``comp(f)`` face, an earlier result; offset
also on a 3D shape's faces): the face is laid in its own plane (x along the scope's in-plane
axis, counter-clockwise seen from its normal), the 2D work is done by
:mod:`shapegen.geometry.polygon2d`, and the pieces come back as shapes whose scope keeps the
orientation and fits the new geometry ("the scope's size is adapted to the new geometry").
Edge selectors are ``comp(f)``'s (:func:`shapegen.geometry.queries.face_matches`) applied to
each edge's outward normal in the face's plane: ``front`` +z, ``back`` -z, ``right`` +x,
``left`` -x, ``side``, ``world.*``...; a number selects that edge (modulo the count).

``offset(d)`` without a selector keeps both the inside and the border faces in one shape, with
the vertices they share welded, so ``comp(f) { inside : ... | border : ... }`` tells them apart
by adjacency (border faces have an edge no other face has).
"""

from __future__ import annotations

__all__ = [
    "FaceFrame",
    "face_frames",
    "edge_normals",
    "edge_object_quadrants",
    "edge_quadrants",
    "emit_pieces",
    "face_holes",
    "flat_faces",
    "flat_shape",
    "selector_branches",
]

from dataclasses import dataclass

import numpy as np

from shapegen.engine.operations.cga.arguments import plain_arguments, selector_name
from shapegen.engine.operations.cga.setback_tags import (
    tag_selector,
)
from shapegen.engine.operations.registry import operation
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.engine.shapes.tags import Pending
from shapegen.errors import GeometryError
from shapegen.geometry import polygon2d
from shapegen.geometry.inner_rectangle import inner_rectangle
from shapegen.geometry.mesh import Mesh, polygon_normal
from shapegen.geometry.queries import FACE_SELECTORS
from shapegen.geometry.scope_frames import quadrant
from shapegen.grammar import ast
from shapegen.limits import check_clock
from shapegen.model.scope import Scope
from shapegen.tolerances import COINCIDENT_M, COINCIDENT_REL, ROUNDOFF_REL

# Edge selectors are comp(f)'s, applied to each edge's outward normal in the face's plane
# (op_setback: "classifying their directions into the corresponding scope quadrants").
_EDGE_SELECTORS = frozenset(FACE_SELECTORS) - {"border", "inside"}


@dataclass(frozen=True)
class FaceFrame:
    """A face's plane in its shape's scope coordinates: ``point = u a + v b + (h0 + h) n``."""

    a: np.ndarray
    b: np.ndarray
    n: np.ndarray
    h0: float

    def lift(self, points2d: np.ndarray, height=0.0) -> np.ndarray:
        """``(k, 2)`` plane points (and heights along n, m) to ``(k, 3)`` scope coordinates."""
        p = np.asarray(points2d, float)
        h = self.h0 + np.broadcast_to(np.asarray(height, float), (len(p),))
        return np.outer(p[:, 0], self.a) + np.outer(p[:, 1], self.b) + np.outer(h, self.n)


def face_frames(shape: Shape) -> list[tuple[FaceFrame, np.ndarray]]:
    """Each face of a flat shape as its frame and its counter-clockwise ``(k, 2)`` polygon."""
    mesh = shape.mesh()
    axis = shape.normal_axis
    guess = np.eye(3)[1 if axis == 0 else 0]  # the scope axis that runs along the face
    out = []
    for k in range(mesh.n_faces):
        check_clock()
        points = mesh.face_points(k)
        normal = polygon_normal(points)
        length = float(np.linalg.norm(normal))
        if length <= 0:
            continue
        n = normal / length
        a = guess - n * float(guess @ n)
        if np.linalg.norm(a) < COINCIDENT_M:
            a = points[1] - points[0]
            a = a - n * float(a @ n)
        a = a / np.linalg.norm(a)
        b = np.cross(n, a)
        polygon = polygon2d.counter_clockwise(np.column_stack([points @ a, points @ b]))
        if len(polygon) >= 3:
            out.append((FaceFrame(a, b, n, float(points[0] @ n)), polygon))
    return out


def edge_normals(frame: FaceFrame, polygon: np.ndarray) -> np.ndarray:
    """``(n, 3)`` outward unit normals of the edges in the face's plane, scope coordinates."""
    m = polygon2d.edge_normals(polygon)
    return np.outer(m[:, 0], frame.a) + np.outer(m[:, 1], frame.b)


def edge_quadrants(frame: FaceFrame, polygon: np.ndarray) -> list[str]:
    """``front back left right top bottom`` of each edge's outward normal in scope axes."""
    return [quadrant(n) for n in edge_normals(frame, polygon)]


def edge_object_quadrants(shape: Shape, object_rotation, frame, polygon) -> list[str]:
    """``front back left right top bottom`` of each edge's outward normal in the object's axes
    (``object_rotation``, the start shape's; the world's when None): the ``object.*``
    selectors' classes, which ``street.*`` falls back to on a lot without street widths."""
    world = edge_normals(frame, polygon) @ shape.scope.rotation.T
    objects = world if object_rotation is None else world @ object_rotation
    return [quadrant(n) for n in objects]


def face_holes(shape: Shape) -> list[list[np.ndarray]]:
    """The holes of each face of :func:`face_frames` (in its order), each clockwise ``(k, 2)``
    in the face's plane; empty lists for a shape without holes."""
    mesh = shape.mesh()
    frames = face_frames(shape)
    if not mesh.holes:
        return [[] for _ in frames]
    out = []
    for k in range(mesh.n_faces):
        if float(np.linalg.norm(polygon_normal(mesh.face_points(k)))) <= 0:
            continue  # as face_frames skips it
        frame = frames[len(out)][0]
        rings = []
        for ring in mesh.holes[k]:
            points = mesh.vertices[list(ring)]
            flat = np.column_stack([points @ frame.a, points @ frame.b])
            rings.append(flat if polygon2d.signed_area(flat) < 0 else flat[::-1])
        out.append(rings)
    return out


def _welded(points: np.ndarray, counts: list[int]):
    """One vertex per distinct point (within round-off of the size), so that faces sharing an
    edge share its vertices: ``comp(f)``'s ``inside`` / ``border`` read that adjacency."""
    eps = COINCIDENT_REL * max(1.0, float(np.ptp(points, axis=0).max()))
    keys = np.round(points / eps).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep the vertices in the order they first appear
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    index = rank[inverse.reshape(-1)]
    faces, start = [], 0
    for count in counts:
        face: list[int] = []
        for k in index[start : start + count]:
            if not face or face[-1] != k:
                face.append(int(k))
        if len(face) > 1 and face[0] == face[-1]:
            face.pop()
        faces.append(tuple(face))
        start += count
    return points[np.sort(first)], faces


def flat_shape(parent: Shape, faces: list[np.ndarray], kind: str = FACE, holes=None) -> Shape:
    """A flat shape made of ``faces`` (``(k, 3)`` in ``parent``'s scope coordinates): the
    parent's orientation, the scope fitted to the faces. ``holes``: for each face, its hole
    rings ``(k, 3)`` (or None for none)."""
    if not any(len(face) for face in faces):
        raise GeometryError("it makes no face")
    if holes is not None and any(holes):
        return _flat_shape_with_holes(parent, faces, kind, holes)
    points = np.concatenate(faces)
    low, high = points.min(axis=0), points.max(axis=0)
    size = high - low
    size[size < ROUNDOFF_REL * max(1.0, float(np.abs(points).max()))] = 0.0
    scope = Scope(parent.scope.to_world(low), parent.scope.rotation, size)
    vertices, indexed = _welded(points - low, [len(f) for f in faces])
    if any(len(face) < 2 for face in indexed):  # welded into a point (a 1e-320 m face)
        raise GeometryError("a face it makes has no extent (its corners are one point)")
    return Shape(scope, kind, parent.normal_axis, None, Mesh(vertices, indexed))


def _flat_shape_with_holes(parent: Shape, faces, kind: str, holes) -> Shape:
    """:func:`flat_shape` of faces with holes: the rings welded together, the holes' after
    the faces'."""
    rings = list(faces) + [ring for face_holes in holes for ring in face_holes]
    points = np.concatenate(rings)
    low, high = points.min(axis=0), points.max(axis=0)
    size = high - low
    size[size < ROUNDOFF_REL * max(1.0, float(np.abs(points).max()))] = 0.0
    scope = Scope(parent.scope.to_world(low), parent.scope.rotation, size)
    vertices, indexed = _welded(points - low, [len(r) for r in rings])
    if any(len(ring) < 3 for ring in indexed):
        raise GeometryError("a face it makes has no extent (its corners are in a line)")
    out_faces, rest = indexed[: len(faces)], iter(indexed[len(faces) :])
    out_holes = [tuple(next(rest) for _ in face_holes) for face_holes in holes]
    return Shape(scope, kind, parent.normal_axis, None, Mesh(vertices, out_faces, out_holes))


def flat_faces(state, node, program, what: str) -> list[tuple[FaceFrame, np.ndarray]]:
    """The faces of ``state``'s shape (see :func:`face_frames`), which must be flat."""
    shape = state.shape
    if shape.kind in ("edge", "vertex"):  # CityEngine: a CGA error, the shape carries on
        raise program.operation_error(
            node, f"{what}: the shape has no faces (an edge or a vertex of comp())"
        )
    if shape.kind == MASS and program.cga_dialect:
        # each face of the geometry, in its own plane: op_envelope builds "above each face of
        # the current shape's geometry", op_setback and op_innerRectangle apply "to shapes
        # with more than one face", op_taper takes the first
        return face_frames(shape)
    if shape.kind != FACE:
        raise program.error(node, f"{what} needs a flat shape (the lot or a comp(f) face)")
    return face_frames(shape)


def selector_branches(program, node, params, allowed: set[str], edges: bool):
    """``(selector, body, merge, branch)`` for each branch: a name or an edge index."""
    from shapegen.grammar import expressions as ex

    out = []
    for branch in node.branches:
        name = selector_name(branch.key)
        if name is None and isinstance(branch.key, ex.Number) and edges:
            selector: str | int = int(branch.key.value)
        elif name in allowed or (edges and name in _EDGE_SELECTORS):
            selector = name
        elif edges and (tagged := tag_selector(program, branch.key, params)) is not None:
            selector = tagged
        else:
            choices = sorted(allowed | (set(_EDGE_SELECTORS) if edges else set()))
            raise program.error(
                branch,
                f"{node.name}() has no selector {name or 'of this form'}; "
                f"shapegen knows {', '.join(choices)} and edge indices"
                if edges
                else f"{node.name}() selects {' or '.join(sorted(allowed))}, not {name}",
            )
        out.append((selector, program.body(branch.body, params), branch.merge, branch))
    return out


def emit_pieces(state, args, branches, pieces_of, out, lines=None) -> None:
    """Give each branch its face groups: ``:`` one shape per group, ``=`` one for all;
    ``lines`` (a :class:`SetbackLines`) gives the pieces the setback's auto-tags."""
    run = state.run
    parent = state.shape
    for selector, body, merge, branch in branches:
        pieces = pieces_of(selector)
        if not pieces:
            continue
        groups = [[face for group in pieces for face in group]] if merge else pieces
        for index, group in enumerate(groups):
            piece = _face_shape(parent, group)
            if lines is not None and run.tags:
                piece = piece.with_tags(Pending(parent, lines.rule(selector == "remainder")))
            child = run.child(state, piece, branch)
            child.comp_index = index
            child.comp_total = len(groups)
            if body(child, args, out) and child.is_leaf():
                out.append((child, None, ()))


def _face_shape(parent: Shape, group: list) -> Shape:
    """:func:`flat_shape` of a group of faces, each ``(k, 3)`` or ``(outer, holes)``."""
    if all(isinstance(face, np.ndarray) for face in group):
        return flat_shape(parent, group)
    faces = [face if isinstance(face, np.ndarray) else face[0] for face in group]
    holes = [[] if isinstance(face, np.ndarray) else list(face[1]) for face in group]
    return flat_shape(parent, faces, FACE, holes)


def array_elements(value):
    """The elements of a CGA array (or a Python sequence), or None for a single value."""
    from shapegen.engine.expressions.arrays import Array

    if isinstance(value, Array):
        return value.values
    return value if isinstance(value, (list, tuple)) else None


@operation("innerRectangle", "innerRect")
def compile_inner_rectangle(program, node: ast.Operation, params):
    """``innerRectangle(scope|edge) { shape : ... | remainder : ... }``."""
    values = plain_arguments(
        program, node, range(0 if node.name == "innerRect" else 1, 2), block=True
    )
    alignment = selector_name(values[0]) if values else "scope"
    if alignment not in ("scope", "edge"):
        raise program.error(node, f"{node.name}()'s alignment is scope or edge")
    branches = selector_branches(program, node, params, {"shape", "remainder"}, edges=False)

    def inner_op(state, args, out):
        pieces: dict[str, list] = {"shape": [], "remainder": []}
        frames = flat_faces(state, node, program, f"{node.name}()")
        for (frame, polygon), rings in zip(frames, face_holes(state.shape), strict=True):
            rectangle, rest = inner_rectangle(polygon, alignment, holes=rings)
            if rectangle is not None:
                pieces["shape"].append([frame.lift(rectangle)])
            if rings:  # the remainder keeps the holes no cut reaches
                pieces["remainder"] += [
                    [(frame.lift(outer), [frame.lift(h) for h in inner])] for outer, inner in rest
                ]
            else:
                pieces["remainder"] += [[frame.lift(p)] for p in rest]
        if not node.branches:  # innerRect without a block: the shape becomes the rectangle
            if not pieces["shape"]:
                return False
            state.shape = flat_shape(state.shape, [g[0] for g in pieces["shape"]])
            return True
        emit_pieces(state, args, branches, lambda s: pieces[s], out)
        return True

    return inner_op


@operation("footprint")
def compile_footprint(program, node: ast.Operation, params):
    """``footprint()``: the shape's geometry projected on its scope's plane y = 0, as a flat
    shape facing +y (the union of the projected faces)."""
    plain_arguments(program, node, range(0, 1), block=True)

    def footprint_op(state, args, out):
        mesh = state.shape.mesh()
        # (x, -z) is counter-clockwise seen from +y.
        plan = [
            np.column_stack([p[:, 0], -p[:, 2]])
            for p in (mesh.face_points(k) for k in range(mesh.n_faces))
        ]
        plan = [polygon2d.counter_clockwise(p) for p in plan if len(p) >= 3]
        plan = [p for p in plan if len(p) >= 3 and polygon2d.signed_area(p) > 0]
        if not plan:
            return False
        faces = [np.column_stack([p[:, 0], np.zeros(len(p)), -p[:, 1]]) for p in plan]
        faces = [
            np.column_stack([q[:, 0], np.zeros(len(q)), -q[:, 1]]) for q in polygon2d.union(plan)
        ] or faces
        shape = flat_shape(state.shape, faces)
        state.shape = Shape(shape.scope, FACE, 1, None, shape.geometry)
        return True

    return footprint_op
