"""CityEngine's occlusion queries ``inside()``, ``overlaps()`` and ``touches()``.

Semantics follow CityEngine's reference (func_occlusion, cga_context):

* The occluders are the *closed* geometries of the derivation: its leaf shapes, and the shapes on
  which a component split (or an offset) was applied -- here: a closed mass from which a shape of
  another kind (faces, edges) is made. Open geometry (faces) never occludes.
* A query ignores the shape's own ancestors and descendants (its place in the shape tree, a
  prefix of the other's), since they occlude it by construction.
* ``intra`` tests against occluders of the same initial shape, ``inter`` against those of other
  initial shapes, ``all`` both (the default). shapegen derives one lot at a time, so ``inter``
  has no occluders and answers false.
* A label restricts the occluders to shapes carrying that label (``label("block")``); an empty
  label is an unlabelled query.
* Two passes: in the first every query answers false (the reference's default value) while the
  occluders are recorded; if any query was asked, the derivation is run again and the queries
  test against the first pass's occluders (:meth:`Occlusion.second_pass`).

Geometry, with a tolerance of :data:`TOLERANCE` metres, on convex pieces (a non-convex closed
occluder is cut into convex pieces, a concave face into convex faces):

* ``inside``: every corner of the shape lies inside or on one occluder (exact for a convex
  occluder; for a non-convex one a corner test, which misses an edge that leaves through a notch).
* ``overlaps``: some point of the shape lies strictly inside an occluder, deeper than the
  tolerance (a linear program per pair of convex pieces), or an occluder lies in the shape.
* ``touches``: overlaps, or a face of the shape and a face of an occluder lie in one plane and
  share an area larger than ``TOLERANCE**2`` (a planar contact; touching along an edge or at a
  corner is not a contact).
"""

from __future__ import annotations

__all__ = ["TOLERANCE", "Occluder", "Occlusion", "inside", "overlaps", "touches"]

from dataclasses import dataclass, field

import numpy as np

from shapegen.errors import GrammarError
from shapegen.geometry.convex import convex_faces
from shapegen.geometry.cut import convex_decomposition
from shapegen.geometry.mesh import Mesh
from shapegen.limits import check_clock
from shapegen.tolerances import COINCIDENT_M, DEFAULT

TOLERANCE = 1e-4
"""Distance (m) under which two surfaces are taken to be in contact."""

_TARGETS = ("intra", "inter", "all")


@dataclass
class Occluder:
    """A closed geometry of the first pass, in world coordinates."""

    path: tuple
    labels: tuple
    mesh: Mesh
    low: np.ndarray = field(init=False)
    high: np.ndarray = field(init=False)
    _pieces: list | None = field(default=None, init=False, repr=False)

    def __post_init__(self):
        self.low, self.high = self.mesh.bounds()

    def pieces(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Convex pieces as half-spaces ``A x <= b`` (unit normals)."""
        if self._pieces is None:
            meshes = (
                [self.mesh]
                if self.mesh.is_convex(COINCIDENT_M)
                else convex_decomposition(self.mesh)
            )
            self._pieces = [_halfspaces(m) for m in meshes or []]
        return self._pieces


class Occlusion:
    """The occlusion state of one derivation pass, kept on ``Derivation.occlusion``.

    First pass (``occluders`` None): queries answer false and set :attr:`asked`; the closed
    masses that become something else (a comp) are noted by :meth:`parent`. Second pass: the
    queries test against ``occluders``.
    """

    __slots__ = ("occluders", "labelled", "asked", "_parents", "_boxes")

    def __init__(self, occluders: list[Occluder] | None = None, labelled: list | None = None):
        self.occluders = occluders
        #: every ``label()`` of the first pass as ``(label, path, shape)``: each one "creates a
        #: labeled copy of the current shape" (cga_context), which the context queries count
        self.labelled: list[tuple] = [] if labelled is None else labelled
        self.asked = False
        self._parents: dict[tuple, tuple] = {}
        self._boxes: tuple[np.ndarray, np.ndarray] | None = None

    def boxes(self) -> tuple[np.ndarray, np.ndarray]:
        """The occluders' bounding boxes as two ``(n, 3)`` arrays (lowest, highest corners)."""
        if self._boxes is None:
            occluders = self.occluders or []
            self._boxes = (
                np.array([o.low for o in occluders]).reshape(-1, 3),
                np.array([o.high for o in occluders]).reshape(-1, 3),
            )
        return self._boxes

    def label(self, state, text: str) -> None:
        """Record a ``label(text)`` of the first pass."""
        if self.occluders is None:
            self.labelled.append((text, state.path, state.shape))

    def parent(self, state) -> None:
        """Note ``state``'s current shape: a child of another kind is being made from it."""
        if self.occluders is None and state.shape.kind == "mass":
            self._parents.setdefault((state.path, id(state.shape)), (state, state.shape))

    def second_pass(self, leaves) -> Occlusion:
        """The state the second pass starts from: this (first) pass's occluders (the noted comp
        parents and the leaves, closed) and its labelled shapes."""
        found = []
        for state, shape in [*self._parents.values(), *((s, s.shape) for s in leaves)]:
            if shape.kind != "mass":
                continue
            mesh = shape.world_mesh()
            if mesh.is_closed and mesh.volume() > TOLERANCE**3:
                found.append(Occluder(state.path, tuple(state.labels), mesh))
        return Occlusion(found, self.labelled)


def inside(state, target: str = "all", label: str = "") -> bool:
    """True when the shape lies inside or on the surface of one closed occluder."""
    return _query(state, target, label, _inside)


def overlaps(state, target: str = "all", label: str = "") -> bool:
    """True when the shape and a closed occluder share interior points."""
    return _query(state, target, label, _overlaps)


def touches(state, target: str = "all", label: str = "") -> bool:
    """True when the shape overlaps a closed occluder or lies against one of its faces."""
    return _query(state, target, label, lambda q, o: _overlaps(q, o) or _planar_contact(q, o))


# ---------------------------------------------------------------------- queries
def _query(state, target: str, label, test) -> bool:
    if target not in _TARGETS:
        raise GrammarError(f"an occlusion query's target is intra, inter or all, got {target!r}")
    if not isinstance(label, str):
        raise GrammarError(f"an occlusion query's label is a string, got {label!r}")
    occlusion = getattr(state.run, "occlusion", None)
    if occlusion is None:
        raise GrammarError("occlusion queries need a derivation that runs them in two passes")
    if occlusion.occluders is None:
        occlusion.asked = True
        return False
    if target == "inter":
        return False  # one initial shape per derivation: no other shape trees
    mesh = state.shape.world_mesh()
    if mesh.n_vertices == 0:  # geometry cleaned away: no point of it is inside or touches any
        return False
    query = _Query(mesh)
    path = state.path
    lows, highs = occlusion.boxes()
    near = ~(
        np.any(query.low > highs + TOLERANCE, axis=1)
        | np.any(lows > query.high + TOLERANCE, axis=1)
    )  # the occluders whose boxes meet the query's, all at once
    for index in np.flatnonzero(near):
        occluder = occlusion.occluders[index]
        other = occluder.path
        if other[: len(path)] == path or path[: len(other)] == other:
            continue  # an ancestor or a descendant
        if label and label not in occluder.labels:
            continue
        if test(query, occluder):
            return True
    return False


class _Query:
    """The query shape's geometry, convex parts made on demand."""

    def __init__(self, mesh: Mesh):
        self.mesh = mesh
        self.low, self.high = mesh.bounds()
        self._parts = None

    def parts(self) -> list[np.ndarray]:
        """Convex corner sets whose union is the shape (pieces of a solid, faces of a surface)."""
        if self._parts is None:
            mesh = self.mesh
            solids = None
            if mesh.is_closed:
                solids = [mesh] if mesh.is_convex(COINCIDENT_M) else convex_decomposition(mesh)
            if solids:
                self._parts = [m.vertices for m in solids]
            else:
                flat = convex_faces(mesh)
                self._parts = [flat.face_points(k) for k in range(len(flat.faces))]
        return self._parts


def _halfspaces(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    normals = mesh.face_normals()
    keep = np.linalg.norm(normals, axis=1) > 0.5
    points = np.array([mesh.face_points(k).mean(axis=0) for k in range(len(mesh.faces))])
    return normals[keep], np.einsum("ij,ij->i", normals[keep], points[keep])


def _inside(query: _Query, occluder: Occluder) -> bool:
    corners = query.mesh.vertices
    pieces = occluder.pieces()
    inside_some = np.zeros(len(corners), dtype=bool)
    for a, b in pieces:
        inside_some |= np.all(corners @ a.T <= b + TOLERANCE, axis=1)
    return bool(pieces) and bool(inside_some.all())


def _depth(corners: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """How deep (m) a point of the convex hull of ``corners`` gets inside ``a x <= b``."""
    k = len(corners)
    # variables: weights of the corners (k), depth t; maximise t
    cost = np.zeros(k + 1)
    cost[-1] = -1.0
    a_ub = np.hstack([a @ corners.T, np.ones((len(a), 1))])
    a_eq = np.hstack([np.ones((1, k)), np.zeros((1, 1))])
    bounds = [(0, None)] * k + [(None, 1.0)]
    from scipy.optimize import linprog  # loaded when a rule asks an occlusion query

    result = linprog(cost, A_ub=a_ub, b_ub=b, A_eq=a_eq, b_eq=[1.0], bounds=bounds)
    return -float(result.fun) if result.status == 0 else -np.inf


def _overlaps(query: _Query, occluder: Occluder) -> bool:
    pieces = occluder.pieces()
    for corners in query.parts():
        for a, b in pieces:
            if _depth(corners, a, b) > TOLERANCE:
                return True
    # vice versa: the occluder (closed, with volume) lies inside a closed query shape
    if query.mesh.is_closed:
        q_pieces = [_halfspaces(m) for m in (convex_decomposition(query.mesh) or [])]
        for a, b in q_pieces:
            if _depth(occluder.mesh.vertices, a, b) > TOLERANCE:
                return True
    return False


def _planar_contact(query: _Query, occluder: Occluder) -> bool:
    mesh = occluder.mesh
    normals = mesh.face_normals()
    q_mesh = convex_faces(query.mesh)
    q_normals = q_mesh.face_normals()
    for j in range(len(q_mesh.faces)):
        check_clock()
        q_points = q_mesh.face_points(j)
        q_normal = q_normals[j]
        for k in range(len(mesh.faces)):
            normal = normals[k]
            if abs(float(q_normal @ normal)) < DEFAULT.normal_cos:
                continue
            points = mesh.face_points(k)
            if np.max(np.abs((q_points - points[0]) @ normal)) > TOLERANCE:
                continue
            if _shared_area(points, q_points, normal) > TOLERANCE**2:
                return True
    return False


def _shared_area(first: np.ndarray, second: np.ndarray, normal: np.ndarray) -> float:
    helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(normal, helper)
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    basis = np.stack([u, v], axis=1)
    import shapely

    a = shapely.Polygon(first @ basis).buffer(0)
    b = shapely.Polygon(second @ basis).buffer(0)
    return float(a.intersection(b).area)
