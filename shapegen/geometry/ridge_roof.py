"""CGA's ``roofRidge`` on one flat face, as a polygon mesh in the face's frame: one ridge along
the face's x axis, halfway across it, two roof planes rising to it from the face's extreme lines
across x, the outline (and every hole) lifted onto them over vertical sides. The mesh is a
:class:`~shapegen.geometry.roof_mesh.RoofMesh` as the skeleton roofs'
(:mod:`shapegen.geometry.roofs`), its vertices ``(x, y, h)`` with ``h`` along the face's normal."""

from __future__ import annotations

__all__ = ["roof_ridge"]

import numpy as np

from shapegen.geometry.polygon2d import checked_polygon, signed_area
from shapegen.geometry.roof_mesh import RoofMesh, Welder, bottom_face, clockwise_rings, roof_slope
from shapegen.tolerances import DEFAULT, DIVISION_FLOOR


def roof_ridge(
    polygon, angle: float | None = None, *, height: float | None = None, holes=()
) -> RoofMesh:
    """CGA's ``roofRidge``: one ridge parallel to the x axis (the scope's x in the face's
    plane), halfway across the face; two planes at ``angle`` (degrees) rise to it from the
    face's extreme lines across x, and the outline is lifted onto them over vertical sides
    (``roof.side.outer``). ``height`` (m) instead of ``angle`` is the ridge's height.

    ``holes`` (rings inside the polygon) stay holes of the bottom and get vertical sides of
    their own (``roof.side.inner``, op_roofRidge); the roof planes are cut by them, a hole
    across the ridge line leaving a notch in each, as CityEngine's runtime builds them
    (tests/data/prt_roofs.json)."""
    import shapely
    from shapely.geometry import Polygon

    p = checked_polygon(polygon)
    rings = clockwise_rings(holes)
    low, high = float(p[:, 1].min()), float(p[:, 1].max())
    middle = 0.5 * (low + high)
    slope = roof_slope(angle, height, middle - low)

    def rise(y):
        return slope * np.minimum(np.asarray(y) - low, high - np.asarray(y))

    def side(a: np.ndarray, b: np.ndarray) -> list:
        """The side over the edge from ``a`` to ``b``: up at ``b``, back along the roof (over
        the ridge where the edge crosses it) and down at ``a``."""
        top = [b, a]
        if (a[1] - middle) * (b[1] - middle) < 0:
            top.insert(1, a + (b - a) * (middle - a[1]) / (b[1] - a[1]))
        return [(*a, 0.0), (*b, 0.0), *((*q, float(rise(q[1]))) for q in top)]

    # the bottom keeps the face's own corners; each side is one face over its edge, with a
    # corner where it crosses the ridge line, a side of no height left out (PyPRT's sides: a
    # triangle over an edge from eave to eave, a pentagon over a hole's edge across the ridge)
    welder = Welder(float(np.ptp(p, axis=0).max()))
    bottom_face(welder, p, "roof.bottom", rings)
    for ring, tag in [(p, "roof.side.outer"), *((r, "roof.side.inner") for r in rings)]:
        for k in range(len(ring)):
            welder.face(side(ring[k], ring[(k + 1) % len(ring)]), tag)
    # The roof planes: the face cut along the ridge line. A hole across the line leaves a notch
    # in each plane; one that does not cross it (touching it or not) stays a hole of the plane
    # on its side, as PyPRT keeps the hole on the ridge of the lot hole_on_ridge.
    eps = DEFAULT.merge_rel * max(float(np.ptp(p, axis=0).max()), DIVISION_FLOOR)
    across = [r for r in rings if r[:, 1].min() < middle - eps and r[:, 1].max() > middle + eps]
    aside = [r for r in rings if not any(r is c for c in across)]
    face = Polygon(p, [r[::-1] for r in across])
    far = 2 * float(np.abs(p).max()) + 1
    lower = [r for r in aside if r[:, 1].max() <= middle + eps]
    upper = [r for r in aside if r[:, 1].max() > middle + eps]
    halves = (shapely.box(-far, -far, far, middle), shapely.box(-far, middle, far, far))
    for half, inside in zip(halves, (lower, upper), strict=True):
        part = face.intersection(half)
        for piece in getattr(part, "geoms", [part]):
            if isinstance(piece, Polygon) and piece.area > 0:
                ring = np.asarray(piece.exterior.coords)[:-1]
                if signed_area(ring) < 0:
                    ring = ring[::-1]
                cut = clockwise_rings(np.asarray(r.coords)[:-1] for r in piece.interiors)
                cut += [r for r in inside if piece.covers(shapely.Point(r.mean(axis=0)))]
                welder.face(
                    np.column_stack([ring, rise(ring[:, 1])]),
                    "roof.top",
                    [np.column_stack([r, rise(r[:, 1])]) for r in cut],
                )
    return welder.mesh()
