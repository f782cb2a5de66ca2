"""Convex pieces of a right prism (an extruded footprint), worked out on its footprint.

:func:`~shapegen.geometry.cut.convex_decomposition` cuts a non-convex closed mesh by the plane of
the face with the most corners in front of it until every piece is convex. On a right prism (two
congruent parallel caps, one planar side face per cap edge, the caps normal to the extrusion) a
cap never has a corner in front of it, and a piece always lies behind the planes it was cut by,
so every cut is the plane of an original side face: the decomposition is that of the footprint by
the lines of its edges, extruded. :func:`prism_decomposition` does that on the footprint, as the
general cut does it (the same choice of edge with the same relative tolerances, ties to the
earliest side face; the same clip of a ring and the same joining of the parts of a ring the line
cuts into several; the halves in the same order), so the pieces are the general path's, up to
round-off, in far less time. Any mesh it is not sure of (not an extrusion's face layout, caps not
congruent or not normal to the extrusion, a footprint that crosses or touches itself, a piece or
face so thin the general cut might drop it, two parts of a half meeting in a point) is left to
the general path: it returns None.
"""

from __future__ import annotations

__all__ = ["prism_decomposition"]

import math
from functools import lru_cache

import numpy as np

from shapegen.geometry.hole_rings import turned
from shapegen.geometry.mesh import Mesh
from shapegen.geometry.rings import chain_loops, corners_apart, is_simple, turns_left, winds_once
from shapegen.model.polygons import CheckedFaces
from shapegen.tolerances import COINCIDENT_REL, DEFAULT, SIZE_FLOOR_M

SPLIT_HEIGHT = DEFAULT.convex_rel / COINCIDENT_REL / math.sqrt(3.0)
"""A face's plane (an edge's line) splits a piece with corners this many ``COINCIDENT_REL`` of
the piece's size beyond it; a piece with none is taken as convex. The size is the bounding
box's diagonal in the frame the piece is cut in, which is up to sqrt(3) times its diagonal in
another frame (the world's, where its block is checked against ``convex_rel`` times the model's
size): hence the sqrt(3), so that a piece taken as convex is convex for the check whatever the
frame (cut in a rotated scope, it once lay 3.2e-6 m out of convex against 3.1e-6 m allowed)."""
_SPLIT_HEIGHT = SPLIT_HEIGHT
_THIN = 10.0  # a face with area within this many times cut.py's drop limit is left to it
_FAR = 4e-3  # a piece smaller than this times the prism is left to the general path
# corners this many COINCIDENT_REL of the size apart or closer are left to the general path
_NEAR = 4.0


class _Doubt(Exception):
    """The footprint's cut reached a case the general path may settle otherwise."""


@lru_cache(maxsize=128)
def _layouts(n: int) -> tuple[CheckedFaces, CheckedFaces]:
    """The faces of :func:`~shapegen.geometry.extrude.prism` on ``n`` corners, and reversed."""
    bottom = (1, 0) + tuple(range(n - 1, 1, -1))
    faces = (bottom, tuple(range(n, 2 * n))) + tuple(
        (k, (k + 1) % n, n + (k + 1) % n, n + k) for k in range(n)
    )
    backward = tuple(turned(f) for f in faces)
    return CheckedFaces(faces), CheckedFaces(backward)


def prism_decomposition(mesh: Mesh, max_pieces: int = 64) -> list[Mesh] | None:
    """The convex pieces :func:`~shapegen.geometry.cut.convex_decomposition` gives for ``mesh``
    when it is a clean right prism in an extrusion's face layout, else None (not a prism, or a
    case to leave to the general path, or more than ``max_pieces`` pieces)."""
    prism = _footprint(mesh)
    if prism is None:
        return None
    try:
        return prism.decomposed(mesh, max_pieces)
    except _Doubt:
        return None


def _footprint(mesh: Mesh) -> _Footprint | None:
    """The footprint of ``mesh`` if it is a right prism as :func:`extrude.prism` lays one
    out (or turned inside out by ``reversed``), else None."""
    n = len(mesh.faces) - 2
    if n < 3 or len(mesh.vertices) != 2 * n:
        return None
    forward, backward = _layouts(n)
    if mesh.faces == forward:
        sense = 1.0
    elif mesh.faces == backward:
        sense = -1.0
    else:
        return None
    v = mesh.vertices
    offset = v[n:] - v[:n]
    d = offset[0]
    size = math.dist(v.max(axis=0).tolist(), v.min(axis=0).tolist())
    eps = COINCIDENT_REL * max(size, SIZE_FLOOR_M)
    if float(np.abs(offset - d).max()) > eps:
        return None  # the caps are not translates
    height = math.hypot(*d.tolist())
    if not height > _THIN * _SPLIT_HEIGHT * eps:
        return None
    along = [k for k, c in enumerate(d.tolist()) if c != 0]
    if len(along) == 1:  # along an axis: the footprint's coordinates are the mesh's own
        axis = along[0]
        sign = 1.0 if d[axis] * sense > 0 else -1.0  # the corners 0..n-1 turn counter-
        iu, iw = (axis + 1) % 3, (axis + 2) % 3  # clockwise about e = sign * the axis
        if sign < 0:
            iu, iw = iw, iu
        u, w, e = [0.0] * 3, [0.0] * 3, [0.0] * 3
        u[iu], w[iw], e[axis] = 1.0, 1.0, sign
        order = [0, 0, 0]
        order[iu], order[iw], order[axis] = 0, 1, 2
        levels = [c * sign for c in v[:, axis].tolist()]
        xs, ys = v[:n, iu].tolist(), v[:n, iw].tolist()
    else:
        e = d * (sense / height)
        a = np.zeros(3)
        a[int(np.argmin(np.abs(e)))] = 1.0
        u = a - (a @ e) * e
        u /= np.linalg.norm(u)
        w = np.cross(e, u)
        order = None
        levels = (v @ e).tolist()
        xs, ys = (v[:n] @ u).tolist(), (v[:n] @ w).tolist()
        u, w, e = u.tolist(), w.tolist(), e.tolist()
    low, high = levels[0], levels[n]
    if max(abs(c - low) for c in levels[:n]) > eps or max(abs(c - high) for c in levels[n:]) > eps:
        return None  # a cap is not normal to the extrusion
    return _Footprint(xs, ys, (u, w, e), order, min(low, high), max(low, high), size)


class _Footprint:
    """A prism's footprint: corners ``xs, ys`` in the frame ``u, w`` (m), counter-clockwise
    about the extrusion ``e``; the caps at levels ``low < high`` along ``e``; ``size`` the
    prism's bounding-box diagonal (m)."""

    def __init__(self, xs, ys, frame, order, low, high, size):
        self.xs, self.ys = xs, ys
        self.frame = frame  # u, w, e: each a unit vector in the mesh's coordinates
        # along the axes: the mesh's coordinate k is x, y or the level (order[k] = 0, 1, 2),
        # the level counted along the extrusion's axis with sign ``e_sign``
        self.order = order
        self.e_sign = sum(frame[2])
        self.low, self.high = low, high
        self.size = size
        self.cuts = 0

    # ------------------------------------------------------------ the cut-by-cut decomposition
    def decomposed(self, mesh: Mesh, max_pieces: int) -> list[Mesh] | None:
        n = len(self.xs)
        first = (list(range(n)), list(range(n)))  # a ring: its corners and its edges' tags
        area = self._ring_area(first[0])
        if not area > 0:
            raise _Doubt  # turned inside out
        if turns_left(first[0], self.xs, self.ys) and winds_once(self.xs, self.ys):
            return self._whole(mesh)
        done: list[tuple] = []
        todo = [[first]]
        while todo:
            piece = todo.pop()
            size = self._size(piece) if self.cuts else self.size
            if size < _FAR * self.size:
                raise _Doubt
            line = self._splitting_line(piece, COINCIDENT_REL * max(size, SIZE_FLOOR_M))
            if line is None:
                if len(piece) != 1:
                    raise _Doubt  # a convex piece is one ring
                done.append((piece[0], size))
                if len(done) > max_pieces:
                    raise _Doubt
                continue
            if self.cuts == 0 and not is_simple(
                self.xs, self.ys, _SPLIT_HEIGHT * COINCIDENT_REL * self.size
            ):
                raise _Doubt
            todo.extend(self._halves(piece, size, *line))
            if len(done) + len(todo) > max_pieces:
                raise _Doubt
        if len(done) == 1:
            return self._whole(mesh)
        total = sum(self._ring_area(ring) for (ring, _), _ in done)
        if abs(total - area) > _THIN * COINCIDENT_REL * area:
            raise _Doubt
        return [self._mesh(ring, tags, size) for (ring, tags), size in done]

    def _whole(self, mesh: Mesh) -> list[Mesh]:
        """A convex prism: its own one piece, when it is clean (else left to the general path,
        which cleans it)."""
        if not corners_apart(self.xs, self.ys, _NEAR * COINCIDENT_REL * self.size):
            raise _Doubt
        return [mesh]

    def _size(self, piece) -> float:
        """The diagonal of the piece's bounding box in the mesh's coordinates (m)."""
        ids = piece[0][0] if len(piece) == 1 else {i for ring, _ in piece for i in ring}
        xs, ys = self.xs, self.ys
        px = [xs[i] for i in ids]
        py = [ys[i] for i in ids]
        if self.order is not None:
            return math.hypot(max(px) - min(px), max(py) - min(py), self.high - self.low)
        total = 0.0
        for a, b, c in zip(*self.frame, strict=True):
            total += self._extent(px, py, a, b, c) ** 2
        return math.sqrt(total)

    def _extent(self, px, py, a, b, c) -> float:
        """The range of the coordinate ``a x + b y + c z`` over the corners ``px, py`` on both
        caps (m)."""
        values = [a * x + b * y for x, y in zip(px, py, strict=True)]
        return max(values) - min(values) + abs(c) * (self.high - self.low)

    def _splitting_line(self, piece, slack):
        """The line of the side face with the most corners in front of it (the first of cut.py's
        ``_splitting_planes``), as ``(nx, ny, offset)``, or None when the piece is convex (or
        so but for round-off); a piece that is neither is left to the general path."""
        xs, ys = self.xs, self.ys
        if len(piece) == 1 and self.cuts and turns_left(piece[0][0], xs, ys):
            return None  # a piece of a simple ring never turning right is convex
        edges = sorted(  # the general path keeps the side faces in their first order
            (tag, ring[m], ring[(m + 1) % len(ring)])
            for ring, tags in piece
            for m, tag in enumerate(tags)
            if tag >= 0  # a cut's face has every corner behind or on it
        )
        if not edges:
            return None  # bounded by cuts alone: behind all of them, so convex
        ids = piece[0][0] if len(piece) == 1 else sorted({i for r, _ in piece for i in r})
        points = [(xs[i], ys[i]) for i in ids]
        lines = []
        for _, i, j in edges:
            tx, ty = xs[j] - xs[i], ys[j] - ys[i]
            length = math.hypot(tx, ty)
            if length > 0:  # a face without a normal cannot split (as in cut.py)
                nx, ny = ty / length, -tx / length
                lines.append((nx, ny, 0.5 * (xs[i] + xs[j]) * nx + 0.5 * (ys[i] + ys[j]) * ny))
        limit = slack * _SPLIT_HEIGHT
        if len(points) * len(lines) <= 256:
            counts = []
            for nx, ny, c in lines:
                ahead = behind = 0
                for x, y in points:
                    h = x * nx + y * ny - c
                    if h > limit:
                        ahead += 1
                    elif h < -limit:
                        behind += 1
                counts.append((ahead, behind))
        else:
            normal = np.array(lines)
            xy = np.array(points)
            heights = np.outer(normal[:, 0], xy[:, 0]) + np.outer(normal[:, 1], xy[:, 1])
            heights -= normal[:, 2:]
            counts = zip(
                (heights > limit).sum(axis=1).tolist(),
                (heights < -limit).sum(axis=1).tolist(),
                strict=True,
            )
        best, most, beyond = None, 0, False
        for line, (ahead, behind) in zip(lines, counts, strict=True):
            beyond = beyond or ahead > 0
            if ahead > most and behind > 0:
                best, most = line, ahead
        if best is None and beyond:
            raise _Doubt  # the general path gives up here
        return best

    def _halves(self, piece, size, nx, ny, offset):
        """The piece behind the line ``nx x + ny y = offset`` and the piece in front of it (as
        cut.py's ``clip_half`` cuts the prism's top cap), each a list of rings; ``size`` the
        piece's (m)."""
        self.cuts += 1
        tag = -self.cuts
        xs, ys = self.xs, self.ys
        ids = piece[0][0] if len(piece) == 1 else {i for ring, _ in piece for i in ring}
        depth = {i: xs[i] * nx + ys[i] * ny - offset for i in ids}
        # cut.py's round-off is that of the piece turned to the cut: unless a corner lies in
        # the band where the turn decides, the piece's own size gives the same clip
        eps = COINCIDENT_REL * max(size, SIZE_FLOOR_M)
        if any(eps / 2 < abs(h) <= eps * 2 for h in depth.values()):
            eps = COINCIDENT_REL * max(self._turned_size(piece, nx, ny), SIZE_FLOOR_M)
        crossing: dict = {}
        halves = []
        # cut.py drops a face of area below COINCIDENT_REL span^2, span the piece's largest extent
        # in the turned frame, which is at most its diameter, at most ``size``
        floor = _THIN * COINCIDENT_REL * size * size
        for sign in (-1.0, 1.0):
            half = []
            along = (sign * ny, -sign * nx)  # the kept part's boundary runs this way on the line
            for ring, tags in piece:
                d = [depth[i] * sign for i in ring]
                if min(d) > eps:
                    half.append((ring, tags))
                elif max(d) > eps:
                    half.extend(self._clipped(ring, tags, d, eps, crossing, along, tag))
            if not half:
                raise _Doubt
            if len(half) > 1:
                corners = [i for ring, _ in half for i in ring]
                if len(set(corners)) != len(corners):
                    raise _Doubt  # parts meeting in a corner: the general cap may not close
            for ring, _ in half:
                self._check_thin(ring, floor)
            halves.append(half)
        return halves

    def _turned_size(self, piece, nx, ny) -> float:
        """The piece's bounding-box diagonal in the frame cut.py turns it to for a cut of
        normal ``(nx, ny)`` (its ``_frame_of``), m."""
        normal = [nx * a + ny * b for a, b in zip(self.frame[0], self.frame[1], strict=True)]
        guess = (1.0, 0.0, 0.0) if abs(normal[0]) < 0.9 else (0.0, 1.0, 0.0)
        along = sum(g * c for g, c in zip(guess, normal, strict=True))
        x = [g - c * along for g, c in zip(guess, normal, strict=True)]
        scale = math.sqrt(sum(c * c for c in x))
        x = [c / scale for c in x]
        z = [
            x[1] * normal[2] - x[2] * normal[1],
            x[2] * normal[0] - x[0] * normal[2],
            x[0] * normal[1] - x[1] * normal[0],
        ]
        ids = {i for ring, _ in piece for i in ring}
        px = [self.xs[i] for i in ids]
        py = [self.ys[i] for i in ids]
        u, w, e = self.frame
        total = 0.0
        for axis in (x, normal, z):
            a = sum(p * q for p, q in zip(axis, u, strict=True))
            b = sum(p * q for p, q in zip(axis, w, strict=True))
            c = sum(p * q for p, q in zip(axis, e, strict=True))
            total += self._extent(px, py, a, b, c) ** 2
        return math.sqrt(total)

    def _check_thin(self, ring, floor):
        """Leave to the general path a ring whose cap or a side face has an area within
        ``floor`` (m^2) of nothing."""
        if self._ring_area(ring) <= floor:
            raise _Doubt
        height = self.high - self.low
        xs, ys = self.xs, self.ys
        previous = ring[-1]
        for i in ring:
            if math.hypot(xs[i] - xs[previous], ys[i] - ys[previous]) * height <= floor:
                raise _Doubt
            previous = i

    def _ring_area(self, ring) -> float:
        xs, ys = self.xs, self.ys
        total = 0.0
        previous = ring[-1]
        for i in ring:
            total += xs[previous] * ys[i] - ys[previous] * xs[i]
            previous = i
        return 0.5 * total

    def _clipped(self, ring, tags, d, eps, crossing, along, tag):
        """The rings left of ``ring`` on the side where ``d`` (its corners' depths) is
        positive: clip_faces.py's ``clipped_faces`` and ``split_at_bridges`` on the ring."""
        kept: list[int] = []
        kept_tags: list[int] = []  # the tag of the edge that arrives at each kept corner
        flags: list[bool] = []  # the corner lies on the line
        count = len(ring)
        for m in range(count):
            p, q = ring[m], ring[(m + 1) % count]
            dp, dq = d[m], d[(m + 1) % count]
            if dp >= -eps:
                kept.append(p)
                kept_tags.append(tags[m - 1])
                flags.append(abs(dp) <= eps)
            if (dp > eps and dq < -eps) or (dp < -eps and dq > eps):
                key = (p, q) if p < q else (q, p)
                if key not in crossing:
                    low, high = (dp, dq) if p < q else (dq, dp)
                    crossing[key] = self._crossing(key[0], key[1], low / (low - high))
                kept.append(crossing[key])
                kept_tags.append(tags[m])
                flags.append(True)
        if len(kept) < 3:
            return []
        edge_tags = kept_tags[1:] + kept_tags[:1]  # edge m runs from kept[m] to kept[m + 1]
        return self._split(kept, edge_tags, flags, along, tag)

    def _crossing(self, i, j, t) -> int:
        """A new corner a fraction ``t`` of the way from corner ``i`` to ``j``: its number."""
        xs, ys = self.xs, self.ys
        xs.append(xs[i] + t * (xs[j] - xs[i]))
        ys.append(ys[i] + t * (ys[j] - ys[i]))
        return len(xs) - 1

    def _split(self, ring, tags, flags, along, tag):
        """clip_faces.py's ``split_at_bridges``: the ring cut at its edges on the line, the
        chains in between joined again along it in the direction ``along``; a joining edge is tagged
        ``tag`` (the cut's face)."""
        n = len(ring)
        if all(flags):  # a ring lying on the line: nothing of it is left
            return []
        on_edges = [flags[k] and flags[(k + 1) % n] for k in range(n)]
        count = on_edges.count(True)
        if count == 0:
            return [(ring, tags)]
        start = (on_edges.index(True) + 1) % n  # a chain begins after an edge on the line
        if count == 1:  # one chain, joined to itself: the ring from there, the edge the cut's
            ring = ring[start:] + ring[:start]
            tags = tags[start:] + tags[:start]
            tags[-1] = tag
            return [(ring, tags)]
        chains: list[tuple[list[int], list[int]]] = []
        current: list[int] = []
        current_tags: list[int] = []
        for step in range(n):
            k = (start + step) % n
            current.append(ring[k])
            current_tags.append(tags[k])
            if on_edges[k]:
                current_tags[-1] = tag
                chains.append((current, current_tags))
                current, current_tags = [], []
        if current:
            raise _Doubt  # not reached: the last corner's edge is on the line
        chains = [c for c in chains if len(c[0]) >= 2]
        if not chains:
            return []
        ax, ay = along
        position = {}
        for c, _ in chains:
            for i in (c[0], c[-1]):
                position[i] = self.xs[i] * ax + self.ys[i] * ay
        rings = []
        starts = [position[c[0]] for c, _ in chains]
        for loop in chain_loops(starts, [position[c[-1]] for c, _ in chains]):
            corners = [i for c in loop for i in chains[c][0]]
            corner_tags = [t for c in loop for t in chains[c][1]]
            if len(set(corners)) != len(corners):
                raise _Doubt  # a ring through a corner twice
            if len(corners) >= 3:
                rings.append((corners, corner_tags))
        return rings

    # ------------------------------------------------------------ the pieces as meshes
    def _mesh(self, ring, tags, size) -> Mesh:
        """The prism on a convex ring of size ``size`` (m), as the general path makes it: the
        caps, a side face per original edge and one per run of edges along a cut."""
        m = len(ring)
        runs = any(tags[k] < 0 and tags[k] == tags[k - 1] for k in range(m))
        if runs:  # start where a face starts
            start = next(k for k in range(m) if tags[k] >= 0 or tags[k] != tags[k - 1])
            ring = ring[start:] + ring[:start]
            tags = tags[start:] + tags[:start]
        px = [self.xs[i] for i in ring]
        py = [self.ys[i] for i in ring]
        if not corners_apart(px, py, _NEAR * COINCIDENT_REL * size):
            raise _Doubt
        if self.order is not None:
            low, high = self.low * self.e_sign, self.high * self.e_sign
            columns = np.array([px + px, py + py, [low] * m + [high] * m])
            vertices = columns[self.order].T
        else:
            u, w, e = (np.array(c) for c in self.frame)
            xy = np.array([px, py]).T
            base = xy[:, :1] * u + xy[:, 1:] * w
            vertices = np.concatenate([base + self.low * e, base + self.high * e])
        if not runs:
            return Mesh.of_valid_faces(vertices, _layouts(m)[0])
        faces = [(1, 0) + tuple(range(m - 1, 1, -1)), tuple(range(m, 2 * m))]
        k = 0
        while k < m:
            end = k + 1
            if tags[k] < 0:
                while end < m and tags[end] == tags[k]:
                    end += 1
            bottom = tuple(range(k, end + 1)) if end < m else tuple(range(k, m)) + (0,)
            faces.append(bottom + tuple(m + i for i in reversed(bottom)))
            k = end
        return Mesh.of_valid_faces(vertices, tuple(faces))
