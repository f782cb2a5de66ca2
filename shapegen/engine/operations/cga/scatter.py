"""CityEngine's ``scatter(domain, n, uniform|gaussian[, mean[, stddev]]) { operations }``.

op_scatter: ``n`` point shapes are placed on the geometry's faces (``surface``), inside its
closed mesh (``volume``; an open mesh falls back to ``surface``) or in its scope (``scope``),
drawn uniformly or from a normal distribution around ``mean`` (``center``, the default, or the
scope's ``front``, ``back``, ``left``, ``right``, ``top`` or ``bottom`` side) with standard
deviation ``stddev`` (metres, or ``'r`` for r times the scope's size on each axis; default
``'0.16``). Each point shape has a scope of size 0 at its point, the parent's axes (on a surface:
y along the face normal), and a geometry of one vertex, so it draws nothing until something is
inserted (``i()``, a primitive). Points are drawn from the shape's own random generator: a rule
file and a seed give the same points (CityEngine's exact sequence is not reproduced).
A gaussian on a surface or in a volume keeps the draws that land on or in the geometry
(uniform draws accepted with the normal density's weight).
"""

from __future__ import annotations

__all__ = ["compile_scatter"]

import math

import numpy as np

from shapegen.engine.operations.cga.arguments import number, selector_name
from shapegen.engine.operations.registry import operation, warn_at
from shapegen.engine.shapes.shape import FACE, MASS, Shape
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.scope_frames import rotation_keeping_x
from shapegen.grammar import ast
from shapegen.limits import check_clock
from shapegen.model.scope import Scope
from shapegen.tolerances import RAY_PARALLEL_DET, SIZE_FLOOR_M

_DOMAINS = ("surface", "volume", "scope")
_MEANS = {  # scope coordinates, in units of the scope's size
    "center": (0.5, 0.5, 0.5),
    "front": (0.5, 0.5, 1.0),
    "back": (0.5, 0.5, 0.0),
    "left": (0.0, 0.5, 0.5),
    "right": (1.0, 0.5, 0.5),
    "top": (0.5, 1.0, 0.5),
    "bottom": (0.5, 0.0, 0.5),
}
_DEFAULT_STDDEV = 0.16  # relative
_MAX_TRIES = 1000  # draws per point before a gaussian point is taken as drawn
POINT = Mesh([(0.0, 0.0, 0.0)], [])
"""A point shape's geometry: one vertex, no face."""


@operation("scatter")
def compile_scatter(program, node: ast.Operation, params):
    args = node.arguments
    if any(a.kind not in ("plain", "relative") for a in args) or not 3 <= len(args) <= 5:
        raise program.error(
            node, "scatter() takes (surface|volume|scope, n, uniform|gaussian[, mean[, stddev]])"
        )  # fmt: skip
    domain = selector_name(args[0].value)
    if domain not in _DOMAINS:
        raise program.error(node, "scatter()'s domain is surface, volume or scope")
    count = number(program, node, args[1].value, params, "the number of points")
    distribution = selector_name(args[2].value)
    if distribution not in ("uniform", "gaussian"):
        raise program.error(node, "scatter()'s distribution is uniform or gaussian")
    if len(args) > 3 and distribution != "gaussian":
        raise program.error(node, "scatter()'s mean and deviation belong to a gaussian")
    mean = selector_name(args[3].value) if len(args) > 3 else "center"
    if mean not in _MEANS:
        raise program.error(node, f"scatter()'s mean is one of {', '.join(_MEANS)}")
    stddev = None
    relative = True
    if len(args) > 4:
        stddev = number(program, node, args[4].value, params, "the deviation")
        relative = args[4].kind == "relative"
    if len(node.branches) != 1 or node.branches[0].key is not None:
        raise program.error(node, "scatter() takes one { operations } block")
    branch = node.branches[0]
    body = program.body(branch.body, params)
    error = program.error

    def scatter_op(state, args_, out):
        n = count(args_, state)
        if n < 0 or n != int(n):
            # op_scatter's nPoints is a float; the reference does not say how a fractional
            # count is made whole: its whole part (C's conversion), none for a negative count
            whole = max(int(n), 0)
            warn_at(
                state, node, f"scatter(): {n:g} points is not a whole number >= 0; shapegen "
                f"places {whole} (the whole part; CityEngine's rounding is not documented)"
            )  # fmt: skip
            n = whole
        shape = state.shape
        if shape.kind in ("edge", "vertex"):
            raise program.operation_error(
                node, "scatter(): the shape has no faces (an edge or a vertex of comp())"
            )
        if shape.kind not in (FACE, MASS):
            raise error(node, "scatter() needs a shape with faces (not an inserted primitive)")
        size = shape.scope.size
        sigma = None
        if distribution == "gaussian":
            deviation = _DEFAULT_STDDEV if stddev is None else stddev(args_, state)
            if deviation < 0:
                raise program.operation_error(
                    node, f"scatter()'s deviation must be >= 0, got {deviation:g}"
                )
            sigma = deviation * size if relative else np.full(3, deviation)
        centre = np.asarray(_MEANS[mean]) * size
        sampler = _Sampler(shape, domain, state.random, centre, sigma)
        run = state.run
        for index in range(int(n)):
            point, rotation = sampler.draw()
            child = run.child(state, Shape.with_geometry(Scope(point, rotation, np.zeros(3)),
                                                         POINT, MASS), branch)  # fmt: skip
            child.split_index = index
            child.split_total = int(n)
            if body(child, args_, out) and child.is_leaf():
                out.append((child, None, ()))
        return True

    return scatter_op


class _Sampler:
    """Draws world points (with their scope axes) on, in or around one shape."""

    def __init__(self, shape: Shape, domain: str, random, centre, sigma):
        self.scope = shape.scope
        self.random = random
        self.centre = centre
        self.sigma = sigma
        mesh = shape.mesh()
        if domain == "volume" and not (shape.kind == MASS and mesh.is_closed):
            domain = "surface"
        if domain == "surface" and (mesh.n_faces == 0 or mesh.area() <= 0):
            domain = "scope"
        self.domain = domain
        self.mesh = mesh
        if domain == "surface":
            triangles = []
            for k, face in enumerate(mesh.faces):
                for j in range(1, len(face) - 1):
                    triangles.append((k, face[0], face[j], face[j + 1]))
            v = mesh.vertices
            self.triangles = triangles
            areas = [
                0.5 * float(np.linalg.norm(np.cross(v[b] - v[a], v[c] - v[a])))
                for _, a, b, c in triangles
            ]
            self.cumulative = np.cumsum(areas) / sum(areas)
            self.normals = mesh.face_normals()

    def draw(self) -> tuple[np.ndarray, np.ndarray]:
        for _ in range(_MAX_TRIES):
            local, normal = self._uniform()
            if self.sigma is None or self._accepted(local):
                break
        rotation = self.scope.rotation
        if normal is not None:
            rotation = rotation_keeping_x(rotation[:, 0], rotation @ normal)
        return self.scope.to_world(local[None, :])[0], rotation

    def _uniform(self):
        r = self.random
        size = self.scope.size
        if self.domain == "scope":
            if self.sigma is not None:  # drawn from the normal itself, nothing to reject
                return self.centre + self.sigma * _normal3(r), None
            return np.array([r(), r(), r()]) * size, None
        if self.domain == "volume":
            lo, hi = self.mesh.bounds()
            for _ in range(_MAX_TRIES):
                point = lo + np.array([r(), r(), r()]) * (hi - lo)
                if _inside(self.mesh, point):
                    return point, None
            return 0.5 * (lo + hi), None
        k = int(np.searchsorted(self.cumulative, r() * self.cumulative[-1], side="right"))
        face, a, b, c = self.triangles[min(k, len(self.triangles) - 1)]
        u, w = r(), r()
        if u + w > 1:
            u, w = 1 - u, 1 - w
        v = self.mesh.vertices
        return v[a] + u * (v[b] - v[a]) + w * (v[c] - v[a]), self.normals[face]

    def _accepted(self, local: np.ndarray) -> bool:
        if self.domain == "scope":
            return True
        spread = np.where(self.sigma > 0, self.sigma, SIZE_FLOOR_M)
        z = (local - self.centre) / spread
        return self.random() < math.exp(-0.5 * float(z @ z))


def _normal3(random) -> np.ndarray:
    """Three standard normal draws (Box-Muller) from a uniform generator."""
    out = []
    while len(out) < 3:
        u, v = 1.0 - random(), random()
        if u <= 0.0:  # CityEngine's draws reach 1.0
            continue
        radius = math.sqrt(-2.0 * math.log(u))
        out += [radius * math.cos(2 * math.pi * v), radius * math.sin(2 * math.pi * v)]
    return np.array(out[:3])


def _inside(mesh: Mesh, point: np.ndarray) -> bool:
    """Whether ``point`` lies inside the closed ``mesh`` (a ray's crossings, odd = inside)."""
    direction = np.array([0.5773502691896258, 0.5773502691896257, 0.5773502691896259])
    crossings = 0
    v = mesh.vertices
    for face in mesh.faces:
        check_clock()
        for j in range(1, len(face) - 1):
            a, b, c = v[face[0]], v[face[j]], v[face[j + 1]]
            e1, e2 = b - a, c - a
            h = np.cross(direction, e2)
            det = float(e1 @ h)
            if abs(det) < RAY_PARALLEL_DET:
                continue
            s = point - a
            u = float(s @ h) / det
            q = np.cross(s, e1)
            w = float(direction @ q) / det
            t = float(e2 @ q) / det
            if u >= 0 and w >= 0 and u + w <= 1 and t > 0:
                crossings += 1
    return crossings % 2 == 1
