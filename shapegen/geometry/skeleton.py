"""The weighted straight skeleton of a polygon (with holes), by simulating its wavefront.

Every edge of the polygon moves inward, parallel to itself, at its own speed (its weight: 1 for
an ordinary roof plane or offset, 0 for an edge that stays put, such as a gable). The polygon's
vertices slide along the intersections of their two edges; an edge that shrinks to nothing
vanishes (an edge event) and a reflex vertex that reaches another edge splits the wavefront in
two (a split event). The traces of the vertices are the skeleton's arcs; the region swept by
edge ``k`` is its face. A point's time ``t`` is when the wavefront reaches it, so a hip roof is
the skeleton lifted to ``z = t tan(angle)``, an inward offset by ``d`` is the wavefront at
``t = d``, and a setback by per-edge distances ``d_k`` is the wavefront at ``t = 1`` with
weights ``d_k`` (Aichholzer et al. 1995; Eppstein and Erickson 1999 for the weighted form).

With holes (clockwise rings: every edge moves into the material) the loops move in one time, a
reflex vertex of one reaching an edge of another joining the two (an annulus's wavefront becomes
a simple loop); once one loop is left it runs as a simple polygon's does.

The simulation is exact arithmetic's algorithm in floating point: simultaneous events (a
rectangle's two ends, a square's four corners, the arms of an L) are taken one after another at
the same time, and points within ``merge_rel`` of the polygon's size are one point.
"""

from __future__ import annotations

__all__ = ["Skeleton", "straight_skeleton"]

from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from shapegen.errors import GeometryError
from shapegen.limits import check_clock, current_limits, limit_hint
from shapegen.tolerances import COSINE_SLACK, DEFAULT, DIVISION_FLOOR, ROUNDOFF_REL


@dataclass(frozen=True)
class Skeleton:
    """A straight skeleton, possibly stopped at a time.

    Attributes
    ----------
    nodes
        ``(m, 2)`` node positions (the polygon's units); the first ``n`` are the polygon's
        vertices.
    times
        ``(m,)`` when the wavefront reached each node (the polygon's units over weight units).
    faces
        One per input edge ``k``: node indices counter-clockwise, starting with the edge's
        start vertex ``k`` and ending with its end vertex (``k + 1``, or the next vertex of
        its hole's ring). With a stop time, a face also runs along the front.
    fronts
        With a stop time: the wavefront then, as node-index loops counter-clockwise (empty
        where the polygon has shrunk away); without one, ``()``.
    """

    nodes: np.ndarray
    times: np.ndarray
    faces: tuple[tuple[int, ...], ...]
    fronts: tuple[tuple[int, ...], ...]

    def face_points(self, k: int) -> np.ndarray:
        """Face ``k`` as ``(j, 2)`` positions, repeated points dropped."""
        return _dedupe(self.nodes[list(self.faces[k])], self._eps)

    def face_xyt(self, k: int) -> np.ndarray:
        """Face ``k`` as ``(j, 3)`` rows ``(x, y, t)``, repeated points dropped."""
        ids = list(self.faces[k])
        return _dedupe(np.column_stack([self.nodes[ids], self.times[ids]]), self._eps)

    def front_points(self) -> list[np.ndarray]:
        """The fronts as ``(j, 2)`` position arrays, degenerate ones (no area) dropped."""
        out = []
        for loop in self.fronts:
            points = _dedupe(self.nodes[list(loop)], self._eps)
            if len(points) >= 3 and _area(points) > self._eps**2:
                out.append(points)
        return out

    @property
    def _eps(self) -> float:
        span = float(np.ptp(self.nodes, axis=0).max()) if len(self.nodes) else 1.0
        return DEFAULT.merge_rel * max(span, DIVISION_FLOOR) * 10


def _area(points: np.ndarray) -> float:
    x, y = points[:, 0], points[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _dedupe(points: np.ndarray, eps: float) -> np.ndarray:
    keep = []
    for p in points:
        if not keep or np.linalg.norm(p - keep[-1]) > eps:
            keep.append(p)
    while len(keep) > 1 and np.linalg.norm(keep[0] - keep[-1]) <= eps:
        keep.pop()
    return np.array(keep).reshape(-1, points.shape[1])


class _Vertex:
    __slots__ = ("node", "pos", "e_in", "e_out")

    def __init__(self, node: int, pos: np.ndarray, e_in: int, e_out: int):
        self.node = node
        self.pos = pos
        self.e_in = e_in
        self.e_out = e_out


class _Builder:
    def __init__(self, polygon: np.ndarray, weights: np.ndarray, following: np.ndarray):
        self.polygon = polygon
        self.following = following  # the next vertex of each vertex's ring
        n = len(polygon)
        direction = polygon[following] - polygon
        length = np.linalg.norm(direction, axis=1)
        if np.any(length <= 0):
            raise GeometryError("the polygon has a repeated vertex")
        self.u = direction / length[:, None]
        self.normal = np.stack([-self.u[:, 1], self.u[:, 0]], axis=1)  # inward for CCW
        self.weights = weights
        self.eps = DEFAULT.merge_rel * float(np.ptp(polygon, axis=0).max())
        self.nodes: list[np.ndarray] = [p.copy() for p in polygon]
        self.times: list[float] = [0.0] * n
        self.arcs: list[tuple[int, int, int, int]] = []  # node, node, side, side (-1: none)
        self.steps = 0

    def add_wall(self, point: np.ndarray, direction: np.ndarray) -> int:
        """A line that stays put (weight 0) through ``point`` along ``direction``: the step
        between two collinear edges that move at different speeds."""
        self.u = np.vstack([self.u, direction])
        self.normal = np.vstack([self.normal, [-direction[1], direction[0]]])
        self.weights = np.append(self.weights, 0.0)
        return len(self.weights) - 1

    def tick(self) -> None:
        """One step of the simulation: the clock checked, and a bound on the steps."""
        check_clock()
        self.steps += 1
        if self.steps > 100 * len(self.polygon) ** 2 + 1000:
            raise GeometryError("the straight skeleton did not converge")

    def node(self, pos: np.ndarray, t: float) -> int:
        self.nodes.append(pos.copy())
        self.times.append(t)
        return len(self.nodes) - 1

    def end(self, vertex: _Vertex, node: int) -> None:
        if vertex.node != node:
            self.arcs.append((vertex.node, node, vertex.e_in, vertex.e_out))

    def velocity(self, vertex: _Vertex) -> np.ndarray:
        a, b = vertex.e_in, vertex.e_out
        na, nb = self.normal[a], self.normal[b]
        det = na[0] * nb[1] - na[1] * nb[0]
        if abs(det) > ROUNDOFF_REL:
            wa, wb = self.weights[a], self.weights[b]
            return np.array([wa * nb[1] - wb * na[1], na[0] * wb - nb[0] * wa]) / det
        if na @ nb > 0:  # collinear continuation: the vertex rides with its edges
            return na * 0.5 * (self.weights[a] + self.weights[b])
        return np.zeros(2)  # a zero-width spike; cleanup retracts it before it moves

    def growing(self, a: _Vertex, b: _Vertex) -> bool:
        """Whether the edge from ``a`` to ``b`` lengthens (a step just born between them)."""
        return (self.velocity(b) - self.velocity(a)) @ self.u[a.e_out] > ROUNDOFF_REL

    def reflex(self, vertex: _Vertex) -> bool:
        ua, ub = self.u[vertex.e_in], self.u[vertex.e_out]
        return ua[0] * ub[1] - ua[1] * ub[0] < -ROUNDOFF_REL

    # -- the loop of one wavefront component ---------------------------------------------------

    def cleanup(self, loop: list[_Vertex], t: float) -> list[_Vertex]:
        """Merge coincident neighbours (edge events) and retract zero-width spikes."""
        changed = True
        while changed and len(loop) >= 2:
            changed = False
            for i in range(len(loop)):
                a, b = loop[i], loop[(i + 1) % len(loop)]
                if np.linalg.norm(a.pos - b.pos) <= self.eps and not self.growing(a, b):
                    loop = self.merge(loop, i, t)
                    changed = True
                    break
            if changed or len(loop) < 3:
                continue
            for i, vertex in enumerate(loop):
                if self.normal[vertex.e_in] @ self.normal[vertex.e_out] < -1 + COSINE_SLACK:
                    loop = self.retract(loop, i, t)
                    changed = True
                    break
        return loop

    def merge(self, loop: list[_Vertex], i: int, t: float) -> list[_Vertex]:
        a, b = loop[i], loop[(i + 1) % len(loop)]
        node = self.node(0.5 * (a.pos + b.pos), t)
        self.end(a, node)
        self.end(b, node)
        merged = _Vertex(node, self.nodes[node], a.e_in, b.e_out)
        if len(loop) == 2:
            return [merged]
        j = (i + 1) % len(loop)
        rest = [v for k, v in enumerate(loop) if k not in (i, j)]
        insert = i if j > i else i - 1
        rest.insert(insert, merged)
        return rest

    def retract(self, loop: list[_Vertex], i: int, t: float) -> list[_Vertex]:
        tip = loop[i]
        prev, nxt = loop[i - 1], loop[(i + 1) % len(loop)]
        if np.linalg.norm(tip.pos - nxt.pos) <= np.linalg.norm(tip.pos - prev.pos):
            node = self.node(nxt.pos, t)
            self.end(tip, node)
            self.end(nxt, node)
            loop[(i + 1) % len(loop)] = _Vertex(node, nxt.pos, tip.e_in, nxt.e_out)
        else:
            node = self.node(prev.pos, t)
            self.end(tip, node)
            self.end(prev, node)
            loop[i - 1] = _Vertex(node, prev.pos, prev.e_in, tip.e_out)
        del loop[i]
        return loop

    def next_event(self, loop: list[_Vertex], velocity: np.ndarray, after=None):
        """The earliest event of ``loop``: ``(dt, kind, i, j)`` or None. An edge event wins a
        tie; among split events the first reflex vertex, then the first edge. ``after``: the
        vertex after each (several loops laid end to end); by default the loop's next."""
        m = len(loop)
        pos = np.array([v.pos for v in loop])
        e_out = np.array([v.e_out for v in loop])
        e_in = np.array([v.e_in for v in loop])
        if after is None:
            after = np.roll(np.arange(m), -1)
        u = self.u[e_out]
        rate = np.einsum("ij,ij->i", velocity[after] - velocity, u)
        length = np.maximum(np.einsum("ij,ij->i", pos[after] - pos, u), 0.0)
        shrinking = rate < -ROUNDOFF_REL
        best = None
        if np.any(shrinking):
            times = np.full(m, np.inf)
            times[shrinking] = length[shrinking] / -rate[shrinking]
            i = int(np.argmin(times))
            best = (float(times[i]), "edge", i, i)
        ua, ub = self.u[e_in], u
        reflex = np.flatnonzero(ua[:, 0] * ub[:, 1] - ua[:, 1] * ub[:, 0] < -ROUNDOFF_REL)
        if len(reflex) == 0:
            return best
        # Every reflex vertex (rows) against every edge (columns), the edge from j to j + 1.
        normal = self.normal[e_out]  # (m, 2)
        gap = np.einsum("ijk,jk->ij", pos[reflex][:, None, :] - pos[None, :, :], normal)
        approach = self.weights[e_out][None, :] - velocity[reflex] @ normal.T
        j = np.arange(m)[None, :]
        rows = reflex[:, None]
        valid = (
            (j != rows)
            & (after[None, :] != rows)
            & (e_out[None, :] != e_in[rows])
            & (e_out[None, :] != e_out[rows])
            & (gap >= -self.eps)
            & (approach > ROUNDOFF_REL)
        )
        if not np.any(valid):
            return best
        dt = np.where(valid, np.maximum(gap, 0.0) / np.where(valid, approach, 1.0), 0.0)
        hit = pos[reflex][:, None, :] + dt[..., None] * velocity[reflex][:, None, :]
        start = pos[None, :, :] + dt[..., None] * velocity[None, :, :]
        end = pos[after][None, :, :] + dt[..., None] * velocity[after][None, :, :]
        span = np.einsum("ijk,jk->ij", end - start, u)
        along = np.einsum("ijk,jk->ij", hit - start, u)
        valid &= (along >= -self.eps) & (along <= span + self.eps)
        if not np.any(valid):
            return best
        dt = np.where(valid, dt, np.inf)
        row, column = np.unravel_index(int(np.argmin(dt)), dt.shape)
        if best is None or dt[row, column] < best[0]:
            best = (float(dt[row, column]), "split", int(reflex[row]), int(column))
        return best

    def split(self, loop: list[_Vertex], i: int, j: int, t: float):
        vertex = loop[i]
        e = loop[j].e_out
        node = self.node(vertex.pos, t)
        self.end(vertex, node)
        m = len(loop)
        # From the vertex forward to the edge's start, and from the edge's end back to it.
        first = [_Vertex(node, vertex.pos, e, vertex.e_out)]
        k = (i + 1) % m
        while k != (j + 1) % m:
            first.append(loop[k])
            k = (k + 1) % m
        second = [_Vertex(node, vertex.pos, vertex.e_in, e)]
        k = (j + 1) % m
        while k != i:
            second.append(loop[k])
            k = (k + 1) % m
        return first, second

    def finish(self, loop: list[_Vertex], t: float) -> None:
        if len(loop) == 1:
            self.end(loop[0], self.node(loop[0].pos, t))
        elif len(loop) == 2:
            a, b = loop
            na, nb = self.node(a.pos, t), self.node(b.pos, t)
            self.end(a, na)
            self.end(b, nb)
            self.arcs.append((na, nb, a.e_out, b.e_out))

    def joined(self, a: list[_Vertex], i: int, b: list[_Vertex], j: int, t: float):
        """Loop ``a``'s reflex vertex ``i`` reaching loop ``b``'s edge ``j`` (from its vertex
        ``j`` to the next): one loop, from the vertex round ``a`` and then round ``b``."""
        vertex, e = a[i], b[j].e_out
        node = self.node(vertex.pos, t)
        self.end(vertex, node)
        first = _Vertex(node, vertex.pos, e, vertex.e_out)
        last = _Vertex(node, vertex.pos, vertex.e_in, e)
        return [first, *a[i + 1 :], *a[:i], last, *b[j + 1 :], *b[: j + 1]]

    def _front(self, loop, velocity, dt: float, t: float) -> list[int]:
        front = []
        for vertex, v in zip(loop, velocity, strict=True):
            node = self.node(vertex.pos + dt * v, t)
            self.end(vertex, node)
            front.append(node)
        for k, node in enumerate(front):
            self.arcs.append((node, front[(k + 1) % len(front)], loop[k].e_out, -1))
        first = min(range(len(loop)), key=lambda k: loop[k].e_out)
        return front[first:] + front[:first]

    def run_together(self, loops: list[list[_Vertex]], until: float | None):
        """Several loops (a polygon's outline and its holes) moving in one time until one is
        left: ``(loop, t)`` to go on with as a simple polygon's, or None, and the fronts."""
        t, fronts = 0.0, []
        while True:
            self.tick()
            loops = [self.cleanup(loop, t) for loop in loops]
            for loop in [loop for loop in loops if len(loop) <= 2]:
                self.finish(loop, t)
            loops = [loop for loop in loops if len(loop) > 2]
            if len(loops) <= 1:
                return (loops[0], t) if loops else None, fronts
            flat = [v for loop in loops for v in loop]
            starts = np.cumsum([0] + [len(loop) for loop in loops])
            after = np.concatenate([np.roll(np.arange(a, b), -1) for a, b in pairwise(starts)])
            velocity = np.array([self.velocity(v) for v in flat]).reshape(-1, 2)
            event = self.next_event(flat, velocity, after)
            stop = until is not None and (event is None or t + event[0] > until)
            if event is None or stop:
                dt = (until - t) if stop else 0.0
                t += dt
                for a, b in pairwise(starts):
                    fronts.append(self._front(flat[a:b], velocity[a:b], dt, t))
                return None, fronts
            dt, kind, i, j = event
            t += dt
            for vertex, v in zip(flat, velocity, strict=True):
                vertex.pos = vertex.pos + dt * v
            li = int(np.searchsorted(starts, i, side="right")) - 1
            lj = int(np.searchsorted(starts, j, side="right")) - 1
            i, j = i - int(starts[li]), j - int(starts[lj])
            rest = [loop for k, loop in enumerate(loops) if k not in (li, lj)]
            if kind == "edge":
                loops = [*rest, self.merge(loops[li], i, t)]
            elif li == lj:
                loops = [*rest, *self.split(loops[li], i, j, t)]
            else:
                loops = [*rest, self.joined(loops[li], i, loops[lj], j, t)]

    def run(self, loop, until: float | None) -> list[list[int]]:
        fronts = []
        if loop and isinstance(loop[0], list):  # the loops of a polygon with holes
            single, fronts = self.run_together(loop, until)
            stack = [single] if single is not None else []
        else:
            stack = [(loop, 0.0)]
        while stack:
            loop, t = stack.pop()
            while True:
                self.tick()
                loop = self.cleanup(loop, t)
                if len(loop) <= 2:
                    self.finish(loop, t)
                    break
                velocity = np.array([self.velocity(v) for v in loop]).reshape(-1, 2)
                event = self.next_event(loop, velocity)
                stop = until is not None and (event is None or t + event[0] > until)
                if event is None or stop:
                    dt = (until - t) if stop else 0.0
                    t += dt
                    fronts.append(self._front(loop, velocity, dt, t))
                    break
                dt, kind, i, j = event
                t += dt
                for vertex, v in zip(loop, velocity, strict=True):
                    vertex.pos = vertex.pos + dt * v
                if kind == "edge":
                    loop = self.merge(loop, i, t)
                else:
                    first, second = self.split(loop, i, j, t)
                    stack.append((first, t))
                    stack.append((second, t))
                    break
        return fronts

    def faces(self) -> list[tuple[int, ...]]:
        n = len(self.polygon)
        by_side: dict[int, list[tuple[int, int]]] = {k: [] for k in range(n)}
        for a, b, s1, s2 in self.arcs:
            for side in {s1, s2}:
                if 0 <= side < n:  # not the walls added between collinear edges
                    by_side[side].append((a, b))
        out = []
        for k in range(n):
            start, goal = k, int(self.following[k])
            unused = list(by_side[k])
            path = [start]
            current = start
            while current != goal:
                for index, (a, b) in enumerate(unused):
                    if current in (a, b):
                        current = b if a == current else a
                        del unused[index]
                        path.append(current)
                        break
                else:
                    raise GeometryError(f"the straight skeleton's face {k} is not closed")
            # The walk runs k -> interior -> k + 1; counter-clockwise the face is the edge
            # k -> k + 1 and then the interior back (so too on a clockwise hole's edge).
            out.append((k, goal, *reversed(path[1:-1])))
        return out


def straight_skeleton(polygon, weights=None, until: float | None = None, holes=()) -> Skeleton:
    """The (weighted) straight skeleton of a polygon, or its part swept until a time.

    Parameters
    ----------
    polygon
        ``(n, 2)`` vertices, counter-clockwise, no repeated vertex.
    weights
        Speed of each edge ``k`` (from vertex ``k`` to ``k + 1``), >= 0; default 1. With
        holes, one per edge of the outline and then of each hole in turn.
    until
        Stop the wavefront at this time and return it as :attr:`Skeleton.fronts`.
    holes
        Clockwise rings inside the polygon, disjoint; their vertices follow the polygon's in
        :attr:`Skeleton.nodes`, their edges its edges in :attr:`Skeleton.faces`, ring by ring.

    Raises
    ------
    GeometryError
        A degenerate polygon (repeated vertices) or one the simulation cannot resolve.
    """
    polygon = np.asarray(polygon, dtype=float).reshape(-1, 2)
    if len(polygon) < 3:
        raise GeometryError(f"a polygon needs at least 3 vertices, got {len(polygon)}")
    rings = [polygon] + [np.asarray(h, dtype=float).reshape(-1, 2) for h in holes]
    if any(len(r) < 3 for r in rings):
        raise GeometryError("a hole needs at least 3 vertices")
    starts = np.cumsum([0] + [len(r) for r in rings])
    following = np.concatenate([np.roll(np.arange(a, b), -1) for a, b in pairwise(starts)])
    before = np.empty_like(following)
    before[following] = np.arange(len(following))
    polygon = np.concatenate(rings)
    n = len(polygon)
    limits = current_limits()
    if n > limits.max_skeleton_corners:
        raise GeometryError(
            f"a polygon of {n} corners is too large for a straight skeleton (a roof, an offset, "
            f"a setback): more than {limits.max_skeleton_corners} "
            + limit_hint("max_skeleton_corners", limits)
        )
    weights = np.ones(n) if weights is None else np.asarray(weights, dtype=float).reshape(n)
    if np.any(weights < 0) or not np.all(np.isfinite(weights)):
        raise GeometryError("straight skeleton weights must be finite and >= 0")
    builder = _Builder(polygon, weights, following)
    loops = []
    for a_start, b_end in pairwise(starts):
        loop = []
        for k in range(a_start, b_end):
            a = int(before[k])
            ua, ub = builder.u[a], builder.u[k]
            collinear = abs(ua[0] * ub[1] - ua[1] * ub[0]) <= ROUNDOFF_REL and ua @ ub > 0
            if collinear and weights[a] != weights[k]:
                # The faster edge runs ahead: a step grows between them along the inward normal.
                inward = builder.normal[k] * np.sign(weights[k] - weights[a])
                wall = builder.add_wall(polygon[k], inward)
                loop.append(_Vertex(k, polygon[k].copy(), a, wall))
                loop.append(_Vertex(k, polygon[k].copy(), wall, k))
            else:
                loop.append(_Vertex(k, polygon[k].copy(), a, k))
        loops.append(loop)
    fronts = builder.run(loops[0] if len(loops) == 1 else loops, until)
    faces = builder.faces()
    return Skeleton(
        np.array(builder.nodes),
        np.array(builder.times),
        tuple(faces),
        tuple(tuple(f) for f in fronts),
    )
