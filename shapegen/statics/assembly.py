"""Sparse assembly of the tension-penalty problem (Whiting, Ochsendorf, Durand 2009).

Per interface vertex ``v`` there are four variables: compression ``c_v >= 0``, tension
``s_v >= 0`` and two friction components ``u_v``, ``t_v`` along the interface tangents. The force
on block ``second`` at the vertex is ``(c_v - s_v) n + u_v t1 + t_v t2``; block ``first`` gets the
opposite force. Each free block (structural and not fixed) contributes six equilibrium rows (force,
torque about its centroid): ``A f + w = 0``.

The problem is stored dimensionless so that every solver sees numbers of order one whatever the
units of the model: forces are divided by the total weight ``W`` (N) of the free blocks and
lengths by the model size ``L`` (m). Torque rows are therefore divided by ``W * L``. The objective
``sum s^2`` of the scaled variables is ``y / W^2``.

The variable vector is ``x = [c, s, u, t]`` (four groups of ``m`` entries). The inequalities are
per vertex and the same for every vertex: ``cone @ [c, u, t] <= 0`` (the friction pyramid sides
and ``c >= 0``) and ``s >= 0``. With the exact Coulomb cone (``pyramid="cone"``) the linear rows are
only ``c >= 0``, and friction is the second-order cone ``||(u, t)|| <= mu c`` per vertex, which
only the back-ends that take cones can solve.
"""

from __future__ import annotations

__all__ = [
    "StaticsProblem",
    "assemble",
    "friction_cone",
    "load_vector",
    "tilted",
    "PYRAMIDS",
    "OBJECTIVES",
]

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from shapegen.errors import OptionError, StaticsError
from shapegen.model.friction import checked_friction
from shapegen.statics.interface import GROUND, Interface
from shapegen.statics.loading import Loading, block_loading, load_vector, tilted, wrench
from shapegen.statics.statics_options import (
    DEFAULT_PYRAMID,
    PYRAMIDS,
    checked_kern,
    checked_pyramid,
)
from shapegen.tolerances import TRIG_ROUNDOFF

if TYPE_CHECKING:
    import scipy.sparse as sp

OBJECTIVES = ("tension_squared", "tension_sum")

# A minute Tikhonov term on c, u, t (dimensionless, relative to the unit weight) keeps the optimal
# set bounded when a self-stress exists (e.g. blocks wedged between two fixed supports); its effect
# on the tensions is of order 1e-10 W, far below every verdict tolerance.
REGULARIZATION = 1e-10


def friction_cone(pyramid: str, mu: float) -> np.ndarray:
    """Rows ``g`` of the per-vertex inequalities ``g @ (c, u, t) <= 0``.

    The friction polygon with ``K`` sides is inscribed in the Coulomb circle of radius ``mu c``:
    its sides are at distance ``mu cos(pi / K) c`` from the centre. ``"4"`` has sides normal to the
    tangents (``|u|, |t| <= mu / sqrt(2) c``), ``"4r"`` is that square turned by 45 degrees
    (``|u| + |t| <= mu c``) and ``"8"`` is the octagon. The last row is ``-c <= 0``.

    For ``"cone"`` the friction is not linear (``||(u, t)|| <= mu c``, see
    :meth:`StaticsProblem.second_order_matrix`): the rows are ``-c <= 0`` alone.

    Returns
    -------
    numpy.ndarray
        ``(K + 1, 3)`` dimensionless (``(1, 3)`` for the cone).
    """
    checked_pyramid(pyramid)
    if pyramid == "cone":
        return np.array([[-1.0, 0.0, 0.0]])
    sides = {"4": 4, "4r": 4, "8": 8}[pyramid]
    offset = np.pi / 4 if pyramid == "4r" else 0.0
    angles = offset + 2 * np.pi * np.arange(sides) / sides
    rows = np.empty((sides + 1, 3))
    rows[:sides, 0] = -mu * np.cos(np.pi / sides)
    rows[:sides, 1] = np.cos(angles)
    rows[:sides, 2] = np.sin(angles)
    rows[sides] = (-1.0, 0.0, 0.0)
    rows[np.abs(rows) < TRIG_ROUNDOFF] = 0.0
    return rows


@dataclass
class StaticsProblem:
    """The assembled, dimensionless tension-penalty problem and the index arrays to read it.

    Attributes
    ----------
    interfaces
        The interfaces kept (scaled by the kern), in the order of ``vertex_interface``.
    free_index
        ``(nb,)`` row group of each block of ``model.blocks`` (-1 for supports and non-structural
        blocks): rows ``6 k .. 6 k + 5`` of the equalities belong to free block ``k``.
    free_blocks
        ``(nf,)`` index in ``model.blocks`` of each free block.
    vertex_interface
        ``(m,)`` interface of each vertex (non-decreasing).
    vertex_points
        ``(m, 3)`` vertex positions, m.
    vertex_blocks
        ``(m, 2)`` free index of ``first`` and ``second`` (-1 for a support).
    vertex_jacobian
        ``(m, 12, 3)`` dimensionless: rows 0-5 the wrench on ``first`` and rows 6-11 on ``second``
        (force, torque / L) of a unit force along ``(n, t1, t2)`` at the vertex; zero rows for a
        support.
    equality
        ``(6 nf, 4 m)`` sparse CSC ``A``, dimensionless: built from ``vertex_jacobian`` when
        first asked for (:meth:`product` and :meth:`transposed_product` apply ``A`` without it,
        so that a wall certified by its least-norm forces never imports scipy.sparse).
    load
        ``(6 nf,)`` scaled external wrench ``w`` (self-weight and point loads).
    cone
        ``(K + 1, 3)`` per-vertex linear inequality rows on ``(c, u, t)``, see
        :func:`friction_cone` (only ``c >= 0`` for the exact cone: see ``second_order``).
    quadratic, linear
        ``(4 m,)`` diagonal of ``P`` and ``q`` of the objective ``x P x / 2 + q x``.
    weight
        ``W``, N: the force scale (total weight of the free blocks).
    length
        ``L``, m: the length scale (model size).
    friction, pyramid, kern, objective
        The options the problem was assembled with.
    tilt, azimuth
        Degrees: every load turned by ``tilt`` towards ``azimuth`` (:func:`tilted`); 0 and None
        for the loads as the model gives them.
    cache
        Scratch space for solvers that reuse sparsity patterns and orderings across solves.
    bodies
        The :class:`~shapegen.statics.bodies.Bodies` the rows belong to (None: one body per
        block, as a ``.grammar`` rule's blocks are).
    loading
        Where each block's weight goes (its row and the point its torque is taken about), to
        turn the loads again (:func:`load_vector`).
    """

    interfaces: list[Interface]
    free_index: np.ndarray
    free_blocks: np.ndarray
    vertex_interface: np.ndarray
    vertex_points: np.ndarray
    vertex_blocks: np.ndarray
    vertex_jacobian: np.ndarray
    load: np.ndarray
    cone: np.ndarray
    quadratic: np.ndarray
    linear: np.ndarray
    weight: float
    length: float
    friction: float
    pyramid: str
    kern: float
    objective: str = "tension_squared"
    tilt: float = 0.0
    azimuth: float | None = None
    cache: dict = field(default_factory=dict, repr=False)
    bodies: object = None
    loading: Loading | None = field(default=None, repr=False)

    @property
    def n_vertices(self) -> int:
        return len(self.vertex_interface)

    @property
    def n_free(self) -> int:
        return len(self.free_blocks)

    @property
    def n_variables(self) -> int:
        return 4 * self.n_vertices

    @property
    def second_order(self) -> bool:
        """True when friction is the exact Coulomb cone ``||(u, t)|| <= mu c`` per vertex (a
        second-order cone, :meth:`second_order_matrix`) rather than linear pyramid rows."""
        return self.pyramid == "cone"

    def with_objective(self, objective: str) -> StaticsProblem:
        """The same constraints with objective ``"tension_squared"`` (``sum s^2``, the paper's)
        or ``"tension_sum"`` (``sum s``, a linear phase-one problem whose solution has no spurious
        small tensions: used to certify feasibility). Matrices and caches are shared."""
        if objective not in OBJECTIVES:
            raise StaticsError(
                f"objective must be one of {', '.join(OBJECTIVES)}; got {objective!r}"
            )
        quadratic, linear = _objective(self.n_vertices, objective)
        return replace(self, quadratic=quadratic, linear=linear, objective=objective)

    @property
    def equality(self) -> sp.csc_matrix:
        """``A`` as a sparse CSC matrix (built once, kept in :attr:`cache`)."""
        equality = self.cache.get("equality")
        if equality is None:
            equality = self.cache["equality"] = _equality_matrix(
                self.vertex_jacobian, self.vertex_blocks, self.n_free
            )
        return equality

    def _vertex_rows(self) -> np.ndarray:
        """``(m, 12)`` the equality row of each of a vertex's twelve wrench rows; ``6 nf`` (one
        past the last row) for a support's side."""
        rows = self.cache.get("vertex_rows")
        if rows is None:
            blocks = np.repeat(self.vertex_blocks, 6, axis=1)  # (m, 12)
            rows = np.where(blocks >= 0, 6 * blocks + np.arange(12) % 6, 6 * self.n_free)
            rows = self.cache["vertex_rows"] = rows
        return rows

    def product(self, x: np.ndarray) -> np.ndarray:
        """``A x`` for ``x = [c, s, u, t]``: the scaled wrench of the forces on each free block."""
        m = self.n_vertices
        local = np.stack([x[:m] - x[m : 2 * m], x[2 * m : 3 * m], x[3 * m :]], axis=1)
        wrenches = np.einsum("vrj,vj->vr", self.vertex_jacobian, local)
        return np.bincount(
            self._vertex_rows().ravel(), wrenches.ravel(), minlength=6 * self.n_free + 1
        )[:-1]

    def transposed_product(self, lam: np.ndarray) -> np.ndarray:
        """``A^T lam`` for ``lam`` one value per equality row: ``[c, s, u, t]``-shaped."""
        padded = np.append(lam, 0.0)
        local = np.einsum("vrj,vr->vj", self.vertex_jacobian, padded[self._vertex_rows()])
        return np.concatenate([local[:, 0], -local[:, 0], local[:, 1], local[:, 2]])

    def inequality_matrix(self) -> sp.csc_matrix:
        """Sparse ``G`` with ``G x <= 0``: per vertex the ``K + 1`` cone rows, then ``-s <= 0``.

        Rows are grouped per vertex: vertex ``v`` owns rows ``(K + 2) v .. (K + 2) v + K + 1``.
        """
        m = self.n_vertices
        rows_per = len(self.cone) + 1
        vertex = np.arange(m)
        k_idx, j_idx = np.nonzero(self.cone)
        # (c, u, t) are variable groups 0, 2, 3
        group = np.array([0, 2, 3])[j_idx]
        rows = (rows_per * vertex[:, None] + k_idx[None, :]).ravel()
        cols = (group[None, :] * m + vertex[:, None]).ravel()
        vals = np.broadcast_to(self.cone[k_idx, j_idx], (m, len(k_idx))).ravel()
        rows = np.concatenate([rows, rows_per * vertex + rows_per - 1])
        cols = np.concatenate([cols, m + vertex])
        vals = np.concatenate([vals, -np.ones(m)])
        import scipy.sparse as sp  # with the interior point's matrices, not the certificate's

        return sp.csc_matrix((vals, (rows, cols)), shape=(rows_per * m, 4 * m))

    def second_order_matrix(self) -> sp.csc_matrix:
        """Sparse ``K`` with ``-K x = (mu c_v, u_v, t_v)`` in three rows per vertex: vertex ``v``
        owns rows ``3 v .. 3 v + 2``, each triple a second-order cone (first entry at least the
        norm of the other two). Only meaningful when :attr:`second_order` is True."""
        m = self.n_vertices
        vertex = np.arange(m)
        rows = np.concatenate([3 * vertex, 3 * vertex + 1, 3 * vertex + 2])
        cols = np.concatenate([vertex, 2 * m + vertex, 3 * m + vertex])
        vals = np.concatenate([np.full(m, -self.friction), -np.ones(m), -np.ones(m)])
        import scipy.sparse as sp  # with the interior point's matrices, not the certificate's

        return sp.csc_matrix((vals, (rows, cols)), shape=(3 * m, 4 * m))

    def residual(self, x: np.ndarray) -> np.ndarray:
        """Scaled equilibrium residual ``A x + w`` (force rows / W, torque rows / (W L))."""
        return self.product(x) + self.load


def _objective(m: int, objective: str) -> tuple[np.ndarray, np.ndarray]:
    quadratic = np.full(4 * m, 2 * REGULARIZATION)
    linear = np.zeros(4 * m)
    if objective == "tension_squared":
        quadratic[m : 2 * m] = 2.0
    else:
        linear[m : 2 * m] = 1.0
    return quadratic, linear


def _skew(r: np.ndarray) -> np.ndarray:
    """``(n, 3, 3)`` cross-product matrices: ``_skew(r) @ d == cross(r, d)``."""
    out = np.zeros(r.shape[:-1] + (3, 3))
    out[..., 0, 1], out[..., 0, 2] = -r[..., 2], r[..., 1]
    out[..., 1, 0], out[..., 1, 2] = r[..., 2], -r[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -r[..., 1], r[..., 0]
    return out


def _equality_matrix(jacobian: np.ndarray, vertex_blocks: np.ndarray, nf: int) -> sp.csc_matrix:
    """``A`` ``(6 nf, 4 m)`` written straight into compressed columns: column ``g m + v`` (group
    ``g`` of ``[c, s, u, t]``, vertex ``v``) holds the vertex's six wrench rows on each free
    block it touches, the lower block's first; ``s`` is minus ``c``. (Built through
    coordinates, the 10 021-brick wall's 0.9 M entries took 0.4 s of masks and a sort.)"""
    m = len(vertex_blocks)
    local = np.arange(12)
    # the block with the lower row numbers first, so that each column's rows are sorted
    swap = (vertex_blocks[:, 0] > vertex_blocks[:, 1]) & (vertex_blocks[:, 1] >= 0)
    position = np.where(swap[:, None], (local + 6) % 12, local)  # (m, 12) rows of jacobian
    block = vertex_blocks[np.arange(m)[:, None], position // 6]  # (m, 12)
    on = block >= 0
    indices = (6 * block + position % 6)[on].astype(np.int32)
    counts = on.sum(axis=1)
    data = []
    for direction, sign in ((0, 1.0), (0, -1.0), (1, 1.0), (2, 1.0)):  # c, s, u, t
        values = jacobian[np.arange(m)[:, None], position, direction][on]
        data.append(values if sign > 0 else -values)
    indptr = np.concatenate([[0], np.cumsum(np.tile(counts, 4))])
    import scipy.sparse as sp  # 0.1 s to import: only for the solvers that take A itself

    return sp.csc_matrix((np.concatenate(data), np.tile(indices, 4), indptr), shape=(6 * nf, 4 * m))


def polygon_centroids(points: np.ndarray, normals: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Area centroids of convex polygons stored back to back (fan triangulation), m.

    ``points`` ``(m, 3)``, ``normals`` ``(ni, 3)``, ``starts`` ``(ni + 1,)`` offsets.
    """
    counts = np.diff(starts)
    owner = np.repeat(np.arange(len(counts)), counts)
    apex = points[starts[:-1]][owner]
    nxt = np.arange(len(points)) + 1
    nxt[starts[1:] - 1] = starts[:-1]  # wrap inside each polygon
    b, c = points, points[nxt]
    weights = np.einsum("ij,ij->i", np.cross(b - apex, c - apex), normals[owner])
    # fan triangles that touch the apex have zero weight, so they can stay in the sums
    total = np.bincount(owner, weights, minlength=len(counts))
    moment = np.stack(
        [
            np.bincount(owner, weights * (apex + b + c)[:, k], minlength=len(counts))
            for k in range(3)
        ],
        axis=1,
    )
    mean = (
        np.stack(
            [np.bincount(owner, points[:, k], minlength=len(counts)) for k in range(3)], axis=1
        )
        / counts[:, None]
    )
    good = total > 0
    out = mean.copy()
    out[good] = moment[good] / (3 * total[good, None])
    return out


def assemble(
    model,
    interfaces: list[Interface],
    *,
    friction: float | None = None,
    pyramid: str = DEFAULT_PYRAMID,
    kern: float = 1.0,
    objective: str = "tension_squared",
    length: float | None = None,
    bodies=None,
) -> StaticsProblem:
    """Assemble the dimensionless tension-penalty problem of ``model`` over ``interfaces``.

    Interfaces between two supports, or touching a non-structural block, are dropped. Fixed
    blocks and the ground are supports (no equations). The whole assembly is vectorised over
    vertices; the only per-interface work is gathering the interface arrays.

    Parameters
    ----------
    model
        The :class:`~shapegen.model.model.Model`.
    interfaces
        Contact polygons (unscaled), e.g. from ``find_interfaces``.
    friction
        Coulomb coefficient mu (dimensionless); ``model.friction`` when None.
    pyramid
        ``"cone"`` (the default,
        :data:`~shapegen.statics.statics_options.DEFAULT_PYRAMID`), ``"4"``, ``"4r"`` or ``"8"``
        (see :func:`friction_cone`).
    kern
        Every interface polygon is scaled about its centroid by this factor in (0, 1].
    objective
        ``"tension_squared"`` (default) or ``"tension_sum"``.
    length
        The length scale ``L``; ``model.size`` when None (a caller that has it saves a pass
        over the blocks).
    bodies
        The :class:`~shapegen.statics.bodies.Bodies` whose rows the equilibrium has (six per
        free body, about its centroid; the contacts between parts of one body are dropped, the
        ornaments' weight is added to the body that carries it); None: each block its own body.
    """
    checked_pyramid(pyramid)
    kern = checked_kern(kern)
    if objective not in OBJECTIVES:
        raise OptionError(f"objective must be one of {', '.join(OBJECTIVES)}; got {objective!r}")
    mu = checked_friction(model.friction if friction is None else friction)

    blocks = model.blocks
    nb = len(blocks)
    g = float(np.linalg.norm(model.gravity))
    loading, free_index, free_blocks, support, usable, body = block_loading(model, bodies)
    weight = float(g * loading.masses[loading.loaded].sum()) if nb else 0.0
    weight_scale = weight if weight > 0 else 1.0
    length = float(model.size if length is None else length)
    centroids = loading.reference

    first = np.array([i.first for i in interfaces], dtype=int)
    second = np.array([i.second for i in interfaces], dtype=int)
    second_slot = np.where(second == GROUND, nb, second)
    keep = (
        usable[first] & usable[second_slot] & ~(support[first] & support[second_slot])
        if len(interfaces)
        else np.zeros(0, bool)
    )
    if body is not None and len(interfaces):  # contacts inside a body are not joints
        keep &= body[first] != np.append(body, -2)[second_slot]
    kept = [interfaces[k] for k in np.flatnonzero(keep)]
    first, second_slot = first[keep], second_slot[keep]
    ni = len(kept)

    if ni:
        counts = np.array([len(i.vertices) for i in kept])
        points = np.concatenate([np.asarray(i.vertices, float) for i in kept])
        frames = np.array([(i.normal, i.tangent1, i.tangent2) for i in kept], float)  # (ni,3,3)
    else:
        counts = np.zeros(0, int)
        points = np.zeros((0, 3))
        frames = np.zeros((0, 3, 3))
    starts = np.concatenate([[0], np.cumsum(counts)])
    vertex_interface = np.repeat(np.arange(ni), counts)
    if kern != 1.0 and ni:
        centres = polygon_centroids(points, frames[:, 0], starts)
        points = centres[vertex_interface] + kern * (points - centres[vertex_interface])
        kept = [
            Interface(i.first, i.second, i.normal, i.tangent1, i.tangent2, points[a:b])
            for i, a, b in zip(kept, starts[:-1], starts[1:], strict=True)
        ]
    m = len(points)

    # wrench of a unit force along (n, t1, t2) at each vertex on each side: [R; (p - c) x R / L]
    rotation = np.transpose(frames, (0, 2, 1))[vertex_interface]  # (m,3,3) columns n, t1, t2
    jacobian = np.zeros((m, 12, 3))
    vertex_blocks = np.stack([free_index[first], free_index[second_slot]], axis=1)[
        vertex_interface
    ].reshape(m, 2)
    for side, owner, sign in ((0, first, -1.0), (1, second_slot, 1.0)):
        on = vertex_blocks[:, side] >= 0
        lever = (points[on] - centroids[owner[vertex_interface[on]]]) / length
        rows = slice(6 * side, 6 * side + 6)
        block = np.concatenate([rotation[on], _skew(lever) @ rotation[on]], axis=1)
        jacobian[on, rows] = sign * block

    load = wrench(model, loading, len(free_blocks), length, weight_scale)

    quadratic, linear = _objective(m, objective)
    return StaticsProblem(
        interfaces=kept,
        free_index=free_index[:nb],
        free_blocks=free_blocks,
        vertex_interface=vertex_interface,
        vertex_points=points,
        vertex_blocks=vertex_blocks,
        vertex_jacobian=jacobian,
        load=load,
        cone=friction_cone(pyramid, mu),
        quadratic=quadratic,
        linear=linear,
        weight=weight_scale,
        length=length,
        friction=mu,
        pyramid=pyramid,
        kern=float(kern),
        objective=objective,
        bodies=bodies,
        loading=loading,
    )
