"""``flying_buttress``: a half arch leaning from a pier to a wall, with its pier."""

from __future__ import annotations

__all__ = ["flying_buttress", "FlyingButtressLayout", "flying_buttress_layout"]

from dataclasses import dataclass

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.prism import extrusion_pool, prism_blocks
from shapegen.primitives.registry import primitive, require, require_blocks
from shapegen.primitives.stereotomy import arc_joints
from shapegen.tolerances import DEFAULT


@dataclass(frozen=True)
class FlyingButtressLayout:
    """Where the flyer's arch line lies in the scope (metres, radians; scope coordinates).

    The arch line is a circular arc of centre ``(sx, centre_y)`` and radius ``radius`` from the
    polar angle ``pi / 2 + angle`` (on the pier) to ``pi / 2`` (against the wall, at x = sx).
    The pier's top is the springing joint's plane,
    ``y = springing_y - (x - pier_width) / tan(angle)``.
    """

    radius: float
    centre_y: float
    angle: float
    pier_width: float
    springing_y: (
        float  # intrados springing point's height, on the pier's inner face (x = pier_width)
    )


def flying_buttress_layout(
    scope: Scope, angle: float, thickness: float, pier_width: float
) -> FlyingButtressLayout:
    """The arch line of a :func:`flying_buttress` in ``scope``; angles in degrees, lengths in m."""
    name = "flying_buttress"
    require(scope.sx > 0 and scope.sy > 0 and scope.sz > 0, name, "scope",
            f"needs a positive size, got {scope.size_text}")  # fmt: skip
    require(0 < angle <= 90, name, "angle", f"must be in (0, 90] degrees, got {angle:g}")
    require(thickness > 0, name, "thickness", f"must be positive, got {thickness:g} m")
    require(
        0 < pier_width < scope.sx,
        name,
        "pier_width",
        f"must be positive and smaller than the scope width {scope.sx:g} m, got {pier_width:g} m",
    )
    a = np.radians(angle)
    # The intrados springs from the pier's inner top edge (x = pier_width); the extrados' crown
    # touches the scope's top at the wall (x = sx).
    radius = (scope.sx - pier_width) / np.sin(a) + thickness / 2
    centre_y = scope.sy - radius - thickness / 2
    springing_y = centre_y + (radius - thickness / 2) * np.cos(a)
    require(
        pier_width >= thickness * np.sin(a) * (1 - DEFAULT.merge_rel),
        name,
        "pier_width",
        f"({pier_width:g} m) must carry the whole springing joint: at least "
        f"thickness * sin(angle) = {thickness * np.sin(a):g} m",
    )
    require(
        springing_y > 0,
        name,
        "angle",
        f"({angle:g} degrees) with thickness {thickness:g} m needs a taller scope: the flyer would "
        f"spring {-springing_y:g} m below the ground (scope height {scope.sy:g} m)",
    )
    return FlyingButtressLayout(radius, centre_y, a, pier_width, springing_y)


@primitive("flying_buttress", scope_relative=True)
def flying_buttress(
    scope: Scope,
    *,
    angle: float = 60.0,
    thickness: float = 0.3,
    segments: int = 8,
    pier_width: float = 0.6,
    pier_courses: int = 4,
) -> list[Block]:
    """A flyer (half arch) springing from a pier at x = 0 and propping a wall at x = sx.

    The flyer's arch line is a circular arc that leaves the pier inclined ``angle`` degrees above
    the horizontal and reaches the wall plane x = sx horizontally, with its extrados touching the
    scope's top (y = sy). ``angle = 90`` gives a quarter circle; smaller angles give flatter,
    more inclined flyers. Joints are normal to the arch line: the last joint is the plane x = sx
    (where the wall, not part of this primitive, receives the thrust) and the first is the pier's
    sloping top. The pier (x from 0 to ``pier_width``) stands on the scope's bottom face in
    horizontal courses. Everything is extruded along z over the scope depth.

    Parameters
    ----------
    angle
        Inclination of the arch line at the springing, degrees, in (0, 90].
    thickness
        Radial thickness of the flyer, metres; at most ``pier_width / sin(angle)``.
    segments
        Voussoirs of the flyer (>= 1).
    pier_width
        Width of the pier along x, metres; smaller than the scope width.
    pier_courses
        Horizontal courses of the pier (>= 1); the top course carries the sloping springing.
    """
    name = "flying_buttress"
    require(segments >= 1, name, "segments", f"must be at least 1, got {segments}")
    require(pier_courses >= 1, name, "pier_courses", f"must be at least 1, got {pier_courses}")
    require_blocks(name, segments + pier_courses, "segments + pier_courses")
    layout = flying_buttress_layout(scope, angle, thickness, pier_width)
    angles = np.linspace(np.pi / 2 + layout.angle, np.pi / 2, segments + 1)
    joints = arc_joints(
        layout.radius - thickness / 2,
        layout.radius + thickness / 2,
        angles,
        centre=(scope.sx, layout.centre_y),
    )
    joints[-1, :, 0] = scope.sx  # the wall joint lies exactly in the plane x = sx
    joints[0, 0] = (pier_width, layout.springing_y)
    intrados, extrados = joints[:, 0], joints[:, 1]
    m = segments + 1
    # Pier: courses of equal height up to the intrados springing point; the top course's top is
    # the springing joint's plane, rising towards the outer face x = 0. The pier's inner top
    # corner is the flyer's intrados springing point (profile row 0).
    top_outer = layout.springing_y + pier_width / np.tan(layout.angle)
    levels = np.linspace(0.0, layout.springing_y, pier_courses + 1)[:-1]
    profile = np.vstack(
        [
            intrados,
            extrados,
            np.column_stack([np.full(pier_courses, pier_width), levels]),
            np.column_stack([np.zeros(pier_courses), levels]),
            [[0.0, top_outer]],
        ]
    )
    inner, outer = 2 * m, 2 * m + pier_courses  # first pier rows on x = pier_width and x = 0
    flyer = [[j, j + 1, m + j + 1, m + j] for j in range(segments)]
    pier = [[outer + c, inner + c, inner + c + 1, outer + c + 1] for c in range(pier_courses - 1)]
    pier.append([outer + pier_courses - 1, inner + pier_courses - 1, 0, outer + pier_courses])
    pool = extrusion_pool(profile, scope.sz)
    count = len(profile)
    return prism_blocks(
        scope, pool, [(p, [i + count for i in p]) for p in pier], tags=("pier",)
    ) + prism_blocks(
        scope, pool, [(p, [i + count for i in p]) for p in flyer], tags=("voussoir", "flyer")
    )
