"""Arches: ``arch`` (semicircular or pointed), ``bezier_arch`` and ``capped_arch``.

Every arch lies in the scope's x-y plane and is extruded along the scope's z axis over its depth.
The springings sit on the scope's bottom face (y = 0) at its two ends, x = 0 and x = W (the scope's
width). Each voussoir is a convex hexahedron: its two joints are straight segments across the arch
ring and its intrados and extrados arcs are replaced by their chords, so the exact volume tends to
the volume of the curved ring as the number of segments grows (the error of ``n`` equal circular
segments is about ``(pi / n)**2 / 6`` of the ring's volume).

Neighbouring voussoirs share their joint faces point for point, so contact detection finds them.
"""

from __future__ import annotations

__all__ = [
    "arch",
    "bezier_arch",
    "capped_arch",
    "semicircular_arch",
    "circular_arch_line",
    "pointed_arch_line",
    "bezier_arch_line",
]

import math

import numpy as np

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import extrusion_pool, polygon_is_convex, prism_blocks
from shapegen.primitives.registry import Choice, primitive, require, require_blocks
from shapegen.tolerances import DEFAULT, ROUNDOFF_REL

# Samples per segment of the dense polyline used to place Bezier joints at equal arc lengths.
_BEZIER_SAMPLES_PER_SEGMENT = 64


# ---------------------------------------------------------------------------------- arch lines
def circular_arch_line(
    width: float, thickness: float, segments: int
) -> tuple[np.ndarray, np.ndarray]:
    """Joint end points of a semicircular arch of extrados radius ``width / 2`` (m).

    Returns ``(intrados, extrados)``, each ``(segments + 1, 2)`` points (m) in the arch plane,
    from the left springing to the right one; joint ``j`` runs from ``intrados[j]`` to
    ``extrados[j]`` along a radius through the centre ``(width / 2, 0)``.
    """
    outer = width / 2.0
    inner = outer - thickness
    angles = np.pi * (1.0 - np.arange(segments + 1) / segments)
    direction = np.column_stack([np.cos(angles), np.sin(angles)])
    # Springing and crown directions exact, so the springing joints lie exactly on y = 0.
    direction[0] = (-1.0, 0.0)
    direction[-1] = (1.0, 0.0)
    if segments % 2 == 0:
        direction[segments // 2] = (0.0, 1.0)
    centre = np.array([outer, 0.0])
    return centre + inner * direction, centre + outer * direction


def pointed_arch_line(
    width: float, thickness: float, segments: int, pointedness: float
) -> tuple[np.ndarray, np.ndarray]:
    """Joint end points of a pointed (two-centred) arch; ``segments`` must be even.

    Each half is a circular arc whose centre lies on the springing line at a distance
    ``e = pointedness * width / 2`` beyond the scope's middle (the left half turns about
    ``(width / 2 + e, 0)``); its extrados radius is ``width / 2 + e`` so that it springs from the
    scope's corner. ``pointedness`` 0 is the semicircular arch, 1 the equilateral arch (each
    centre at the opposite springing), above 1 a lancet arch. The halves meet at a vertical
    crown joint ``x = width / 2``; the other joints are radial, at equal angles between the
    springing and the intrados crown.
    Returns ``(intrados, extrados)`` as in :func:`circular_arch_line`.
    """
    half = segments // 2
    offset = pointedness * width / 2.0
    outer = width / 2.0 + offset
    inner = outer - thickness
    # The intrados reaches the crown at the largest angle: joints placed below it stay inside
    # the half-arc however thick the ring and however many the segments.
    crown_angle = math.acos(-offset / inner)
    angles = np.pi - (np.pi - crown_angle) * np.arange(half) / half
    direction = np.column_stack([np.cos(angles), np.sin(angles)])
    direction[0] = (-1.0, 0.0)
    centre = np.array([width / 2.0 + offset, 0.0])
    left_in = np.vstack(
        [centre + inner * direction, [width / 2.0, math.sqrt(inner**2 - offset**2)]]
    )
    left_out = np.vstack(
        [centre + outer * direction, [width / 2.0, math.sqrt(outer**2 - offset**2)]]
    )
    mirror = np.array([-1.0, 1.0])
    right_in = (left_in[-2::-1] * mirror) + [width, 0.0]
    right_out = (left_out[-2::-1] * mirror) + [width, 0.0]
    return np.vstack([left_in, right_in]), np.vstack([left_out, right_out])


def bezier_arch_line(
    width: float,
    height: float,
    thickness: float,
    segments: int,
    controls: tuple[float, float, float, float],
) -> tuple[np.ndarray, np.ndarray]:
    """Joint end points of an arch whose centreline is a cubic Bezier curve.

    The curve runs from ``(thickness / 2, 0)`` to ``(width - thickness / 2, 0)``; its inner
    control points are ``(x0 + c1x * span, c1y * height)`` and ``(x0 + c2x * span, c2y * height)``
    with ``x0 = thickness / 2`` and ``span = width - thickness``. The curve is then scaled
    vertically so that its highest point lies at ``height - thickness / 2``: the extrados crown
    touches the scope's top. Joints are placed at equal arc lengths along the centreline, normal
    to it; the two springing joints are horizontal, on y = 0 (from x = 0 to x = thickness, and
    from x = width - thickness to x = width). Returns ``(intrados, extrados)``.
    """
    c1x, c1y, c2x, c2y = controls
    x0, span = thickness / 2.0, width - thickness
    points = np.array(
        [[x0, 0.0], [x0 + c1x * span, c1y * height], [x0 + c2x * span, c2y * height],
         [x0 + span, 0.0]]
    )  # fmt: skip
    dense = np.linspace(0.0, 1.0, _BEZIER_SAMPLES_PER_SEGMENT * segments + 1)
    curve = _bezier(points, dense)
    top = float(curve[:, 1].max())
    if top <= 0.0:
        raise GeometryError(
            "primitive 'bezier_arch': the control points give an arch line that does not rise "
            "above the springings (c1y, c2y must make the curve go up)"
        )
    if float(curve[:, 1].min()) < -ROUNDOFF_REL * width:
        raise GeometryError("primitive 'bezier_arch': the arch line dips below the springings")
    points[:, 1] *= (height - thickness / 2.0) / top
    curve = _bezier(points, dense)
    chord = np.linalg.norm(np.diff(curve, axis=0), axis=1)
    length = np.concatenate([[0.0], np.cumsum(chord)])
    targets = length[-1] * np.arange(segments + 1) / segments
    parameters = np.interp(targets, length, dense)
    centre = _bezier(points, parameters)
    tangent = _bezier_derivative(points, parameters)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])  # outward: up at the crown
    intrados = centre - thickness / 2.0 * normal
    extrados = centre + thickness / 2.0 * normal
    intrados[0], extrados[0] = (thickness, 0.0), (0.0, 0.0)
    intrados[-1], extrados[-1] = (width - thickness, 0.0), (width, 0.0)
    return intrados, extrados


def _bezier(points: np.ndarray, s: np.ndarray) -> np.ndarray:
    s = np.asarray(s, dtype=float)[:, None]
    r = 1.0 - s
    return r**3 * points[0] + 3 * r**2 * s * points[1] + 3 * r * s**2 * points[2] + s**3 * points[3]


def _bezier_derivative(points: np.ndarray, s: np.ndarray) -> np.ndarray:
    s = np.asarray(s, dtype=float)[:, None]
    r = 1.0 - s
    d = np.diff(points, axis=0)
    return 3 * (r**2 * d[0] + 2 * r * s * d[1] + s**2 * d[2])


# ---------------------------------------------------------------------------------- blocks
def _voussoir_polygons(
    name: str, intrados: np.ndarray, extrados: np.ndarray, width: float
) -> tuple[np.ndarray, list[list[int]]]:
    """The arch-plane profile (intrados then extrados points) and one convex quadrilateral per
    voussoir (indices into the profile, counter-clockwise)."""
    m = len(intrados)
    profile = np.vstack([intrados, extrados])
    polygons = [[j, j + 1, m + j + 1, m + j] for j in range(m - 1)]
    tolerance = DEFAULT.merge_rel * width
    for k, polygon in enumerate(polygons):
        if not polygon_is_convex(profile[polygon], tolerance):
            raise GeometryError(
                f"primitive {name!r}: voussoir {k} is not convex (its joints cross or the arch "
                "line bends too sharply for the thickness); use a smaller thickness, fewer "
                "segments or a smoother arch line"
            )
    return profile, polygons


def _arch_blocks(
    name: str, scope: Scope, intrados: np.ndarray, extrados: np.ndarray, top: float | None = None
) -> list[Block]:
    """Voussoirs (and, when ``top`` is a height in m, spandrel blocks up to it) in world
    coordinates."""
    profile, polygons = _voussoir_polygons(name, intrados, extrados, scope.sx)
    m = len(intrados)
    spandrels: list[list[int]] = []
    if top is not None:
        profile, spandrels = _spandrel_polygons(name, profile, m, scope.sx, top)
    pool = extrusion_pool(profile, scope.sz)
    count = len(profile)
    blocks = prism_blocks(
        scope, pool, [(p, [i + count for i in p]) for p in polygons], tags=("voussoir",)
    )
    blocks += prism_blocks(
        scope, pool, [(p, [i + count for i in p]) for p in spandrels], tags=("spandrel",)
    )
    return blocks


def _spandrel_polygons(
    name: str, profile: np.ndarray, m: int, width: float, top: float
) -> tuple[np.ndarray, list[list[int]]]:
    """Spandrel pieces filling the rectangle ``[0, width] x [0, top]`` around the arch ring.

    Every joint is extended beyond the extrados, along its own line, to the rectangle's
    boundary; the piece above voussoir ``j`` lies between the extensions of its two joints, above
    its extrados chord. The pieces continue the voussoirs outwards (as the long-tailed
    voussoirs of a wall arch), so each one leans on its neighbours across a joint plane normal to
    the arch line rather than resting on a steep extrados. Each is the intersection of a wedge, a
    half-plane and the rectangle, hence convex, and neighbours share the extended joint exactly.
    """
    intrados, extrados = profile[:m], profile[m:]
    direction = extrados - intrados
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    snap = DEFAULT.merge_rel * width
    # Distance along each joint line to the rectangle's boundary.
    with np.errstate(divide="ignore", invalid="ignore"):
        to_x = np.where(
            direction[:, 0] > 0,
            (width - extrados[:, 0]) / direction[:, 0],
            np.where(direction[:, 0] < 0, -extrados[:, 0] / direction[:, 0], np.inf),
        )
        to_y = np.where(direction[:, 1] > 0, (top - extrados[:, 1]) / direction[:, 1], np.inf)
    reach = np.maximum(np.minimum(to_x, to_y), 0.0)
    exits = extrados + reach[:, None] * direction
    # Exact boundary coordinates, so that the pieces' outer faces are coplanar with the scope's.
    exits[:, 0] = np.where(to_x <= to_y, np.where(direction[:, 0] > 0, width, 0.0), exits[:, 0])
    exits[:, 1] = np.where(to_y < to_x, top, exits[:, 1])
    corners = np.array([[width, 0.0], [width, top], [0.0, top], [0.0, 0.0]])
    perimeter = 2 * (width + top)
    corner_at = np.array([width, width + top, 2 * width + top, perimeter])
    exit_at = _perimeter_position(exits, width, top)
    exit_at[0] = perimeter  # the left springing's outer corner closes the boundary walk
    points = [profile, exits, corners]
    exit_base, corner_base = 2 * m, 3 * m
    polygons = []
    for j in range(m - 1):
        polygon = [m + j, m + j + 1]
        if reach[j + 1] > snap:
            polygon.append(exit_base + j + 1)
        # Walk the boundary counter-clockwise from this joint's exit back to the previous one's.
        between = (corner_at > exit_at[j + 1] + snap) & (corner_at < exit_at[j] - snap)
        polygon += [corner_base + int(k) for k in np.flatnonzero(between)]
        if reach[j] > snap:
            polygon.append(exit_base + j)
        if len(polygon) >= 3:
            polygons.append(polygon)
    everything = np.vstack(points)
    for k, polygon in enumerate(polygons):
        if not polygon_is_convex(everything[polygon], snap):
            raise GeometryError(
                f"primitive {name!r}: spandrel piece {k} is not convex; use a smaller thickness "
                "or fewer segments"
            )
    return everything, polygons


def _perimeter_position(points: np.ndarray, width: float, top: float) -> np.ndarray:
    """Counter-clockwise distance along the rectangle's boundary from (0, 0) of points on it."""
    x, y = points[:, 0], points[:, 1]
    tol = DEFAULT.merge_rel * width
    return np.select(
        [y <= tol, x >= width - tol, y >= top - tol],
        [x, width + y, width + top + (width - x)],
        default=2 * width + top + (top - y),
    )


def _check_arch(
    name: str, scope: Scope, style: str, thickness: float, segments: int, pointedness: float
) -> None:
    width = scope.sx
    require(width > 0 and scope.sz > 0, name, "scope",
            f"needs a positive width and depth, got {scope.size_text}")  # fmt: skip
    require(segments >= 2, name, "segments", f"must be at least 2, got {segments}")
    require_blocks(name, 2 * segments if name == "capped_arch" else segments, "segments")
    require(thickness > 0, name, "thickness", f"must be positive, got {thickness:g} m")
    require(
        thickness < width / 2,
        name,
        "thickness",
        f"must be less than the extrados radius {width / 2:g} m (half the scope width), "
        f"got {thickness:g} m",
    )
    if style == "gothic":
        require(pointedness >= 0, name, "pointedness",
                f"must be 0 (semicircular) or more, got {pointedness:g}")  # fmt: skip
        require(
            segments % 2 == 0,
            name,
            "segments",
            f"must be even for a gothic arch (it has a joint at the crown), got {segments}",
        )


def _arch_line(
    style: str, width: float, thickness: float, segments: int, pointedness: float
) -> tuple[np.ndarray, np.ndarray]:
    if style == "gothic":
        return pointed_arch_line(width, thickness, segments, pointedness)
    return circular_arch_line(width, thickness, segments)


@primitive("arch", scope_relative=True)
def arch(
    scope: Scope,
    *,
    style: Choice("romanesque", "gothic") = "romanesque",
    thickness: float = 0.3,
    segments: int = 12,
    pointedness: float = 0.5,
) -> list[Block]:
    """A semicircular ("romanesque") or pointed ("gothic") arch of voussoirs.

    Parameters
    ----------
    style
        "romanesque": a semicircle about the middle of the scope's bottom edge. "gothic": two
        circular arcs meeting at a crown joint (see ``pointedness``).
    thickness
        Radial thickness of the ring, m; less than half the scope width.
    segments
        Number of voussoirs, at least 2 (even for "gothic").
    pointedness
        Gothic only: the distance of each arc's centre from the middle of the span, as a
        fraction of the half-span. 0 is the semicircular arch, 1 the equilateral arch (each
        centre at the opposite springing), larger values lancet arches.

    The extrados radius is half the scope width (for "gothic", the half-span plus the centre
    offset), the springings lie on the scope's bottom face at its two ends, and the ring is
    extruded along z over the scope depth; the centreline radius is ``width / 2 - thickness / 2``
    for "romanesque". Joints are radial (normal to the arch line). The scope height is not used:
    the rise follows from the width (``width / 2`` for "romanesque").
    """
    _check_arch("arch", scope, style, thickness, segments, pointedness)
    intrados, extrados = _arch_line(style, scope.sx, thickness, segments, pointedness)
    return _arch_blocks("arch", scope, intrados, extrados)


@primitive("capped_arch", scope_relative=True)
def capped_arch(
    scope: Scope,
    *,
    style: Choice("romanesque", "gothic") = "romanesque",
    thickness: float = 0.3,
    segments: int = 12,
    pointedness: float = 0.5,
) -> list[Block]:
    """An :func:`arch` with its spandrels filled up to a flat top at the scope's top face.

    Parameters are those of ``arch``. Outside each voussoir lies one spandrel block: the
    voussoir's extrados face on one side, the extensions of its two joints (shared with the
    neighbouring spandrel blocks) on two others, and the scope's faces that it reaches. The
    spandrel blocks thus continue the voussoirs to the scope's outline, so the joints stay
    normal to the arch line. Every piece is convex. The scope height must reach the arch's crown.
    """
    _check_arch("capped_arch", scope, style, thickness, segments, pointedness)
    intrados, extrados = _arch_line(style, scope.sx, thickness, segments, pointedness)
    crown = float(extrados[:, 1].max())
    require(
        scope.sy >= crown - DEFAULT.merge_rel * scope.sx,
        "capped_arch",
        "scope",
        f"height {scope.sy:g} m is below the arch's crown at {crown:g} m; make the scope taller "
        "or narrower",
    )
    return _arch_blocks("capped_arch", scope, intrados, extrados, top=max(scope.sy, crown))


@primitive("bezier_arch", scope_relative=True)
def bezier_arch(
    scope: Scope,
    *,
    thickness: float = 0.3,
    segments: int = 16,
    c1x: float = 0.0,
    c1y: float = 1.0,
    c2x: float = 1.0,
    c2y: float = 1.0,
) -> list[Block]:
    """An arch whose centreline is a cubic Bezier curve (the seed paper's Figure 12).

    Parameters
    ----------
    thickness
        Thickness of the ring normal to the arch line, m.
    segments
        Number of voussoirs (at least 2), equal lengths along the centreline.
    c1x, c1y, c2x, c2y
        The two inner control points: x as a fraction of the centreline span (0 = above the
        left springing, 1 = above the right one), y as a fraction of the scope height.
        Control points outside the scope can carry the arch outside it.

    The curve's end points are fixed at the springings on the scope's bottom face
    (``(thickness / 2, 0)`` and ``(width - thickness / 2, 0)``); the curve is scaled vertically
    so that the extrados crown reaches the scope's top (only the ratio c1y : c2y and the x
    fractions shape it). Joints are normal to the curve except the two springing joints, which
    lie on the scope's bottom face. A curve that makes a voussoir non-convex is an error.
    """
    name = "bezier_arch"
    width, height = scope.sx, scope.sy
    require(width > 0 and height > 0 and scope.sz > 0, name, "scope",
            f"needs a positive size, got {scope.size_text}")  # fmt: skip
    require(segments >= 2, name, "segments", f"must be at least 2, got {segments}")
    require_blocks(name, segments, "segments")
    require(thickness > 0, name, "thickness", f"must be positive, got {thickness:g} m")
    require(
        thickness < width / 2,
        name,
        "thickness",
        f"must be less than half the scope width {width / 2:g} m, got {thickness:g} m",
    )
    require(
        thickness < height,
        name,
        "thickness",
        f"must be less than the scope height {height:g} m, got {thickness:g} m",
    )
    intrados, extrados = bezier_arch_line(width, height, thickness, segments, (c1x, c1y, c2x, c2y))
    return _arch_blocks(name, scope, intrados, extrados)


def semicircular_arch(
    radius: float,
    thickness: float,
    segments: int,
    depth: float = 1.0,
    centre: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> list[Block]:
    """A semicircular arch given by its centreline ``radius`` and ``thickness`` (m).

    The arch's centre is ``centre`` (m, world), its springings lie on the plane
    y = ``centre[1]``, and it spans x from ``centre[0] - radius - thickness / 2`` to
    ``centre[0] + radius + thickness / 2``, z from ``centre[2]`` to ``centre[2] + depth``.
    """
    width = 2.0 * radius + thickness
    origin = np.asarray(centre, dtype=float) - [width / 2.0, 0.0, 0.0]
    scope = Scope.axis_aligned(origin, (width, width / 2.0, depth))
    return arch(scope, style="romanesque", thickness=thickness, segments=segments)
