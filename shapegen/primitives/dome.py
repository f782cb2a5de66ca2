"""``dome``: a hemispherical dome of voussoirs in rings and meridians, optionally with an oculus."""

from __future__ import annotations

__all__ = ["dome"]

import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.registry import primitive, require, require_blocks
from shapegen.primitives.stereotomy import hexahedra_in_scope


@primitive("dome", scope_relative=True)
def dome(
    scope: Scope,
    *,
    thickness: float = 0.3,
    rings: int = 8,
    meridians: int = 16,
    oculus: float = 0.0,
) -> list[Block]:
    """A hemispherical dome centred on the scope's plan, springing from its bottom face.

    The extrados radius is ``min(sx, sz) / 2``; the centre is at the middle of the scope's bottom
    face. Voussoirs lie between two meridian planes and two ring joints; ring joints are cones
    through the centre (normal to the meridian arch line), approximated by planes through the
    centre, and the intrados and extrados are planar facets, so every voussoir is a convex
    hexahedron sharing its faces exactly with its neighbours. Without an oculus the top ring is
    made of wedges meeting on the vertical axis.

    Parameters
    ----------
    thickness
        Radial thickness of the shell, metres; smaller than the extrados radius.
    rings
        Courses of voussoirs from the springing to the top (>= 1).
    meridians
        Voussoirs around each ring (>= 3).
    oculus
        Half-angle of the opening at the top, degrees, measured from the vertical axis
        (0 = closed; below 90).
    """
    name = "dome"
    radius_out = min(scope.sx, scope.sz) / 2
    require(
        radius_out > 0, name, "scope", f"needs a positive width and depth, got {scope.size_text}"
    )
    require(thickness > 0, name, "thickness", f"must be positive, got {thickness:g} m")
    require(
        thickness < radius_out,
        name,
        "thickness",
        f"({thickness:g} m) must be smaller than the extrados radius (min(sx, sz) / 2 = "
        f"{radius_out:g} m)",
    )
    require(rings >= 1, name, "rings", f"must be at least 1, got {rings}")
    require(meridians >= 3, name, "meridians", f"must be at least 3, got {meridians}")
    require(0 <= oculus < 90, name, "oculus", f"must be in [0, 90) degrees, got {oculus:g}")
    require_blocks(name, rings * meridians, "rings x meridians")

    latitudes = np.linspace(0.0, np.radians(90.0 - oculus), rings + 1)
    longitudes = np.linspace(0.0, 2 * np.pi, meridians + 1)
    longitudes[-1] = 0.0  # the last meridian plane is the first one: close the ring exactly
    radii = np.array([radius_out - thickness, radius_out])
    # points[j, k, r]: ring joint j, meridian k, intrados (r = 0) or extrados (r = 1); local scope
    # coordinates with the centre on the bottom face's middle.
    cos_lat, sin_lat = np.cos(latitudes), np.sin(latitudes)
    if oculus == 0:
        cos_lat[-1] = 0.0  # the pole lies exactly on the axis
    direction = np.stack(
        [
            cos_lat[:, None] * np.cos(longitudes)[None, :],
            np.broadcast_to(sin_lat[:, None], (rings + 1, meridians + 1)),
            cos_lat[:, None] * np.sin(longitudes)[None, :],
        ],
        axis=-1,
    )
    centre = np.array([scope.sx / 2, 0.0, scope.sz / 2])
    points = centre + direction[:, :, None, :] * radii[None, None, :, None]
    lower, upper = points[:-1], points[1:]
    corners = np.stack(
        [
            lower[:, :-1, 0], lower[:, 1:, 0], lower[:, 1:, 1], lower[:, :-1, 1],
            upper[:, :-1, 0], upper[:, 1:, 0], upper[:, 1:, 1], upper[:, :-1, 1],
        ],
        axis=2,
    )  # fmt: skip
    if oculus > 0:
        return hexahedra_in_scope(corners.reshape(-1, 8, 3), scope, tags=("voussoir",))
    blocks = hexahedra_in_scope(corners[:-1].reshape(-1, 8, 3), scope, tags=("voussoir",))
    # Top ring: both upper corners of each side coincide on the axis, so each block is a wedge.
    wedge_corners = corners[-1][:, [0, 1, 2, 3, 4, 6]]
    wedge_points = scope.to_world(wedge_corners.reshape(-1, 3)).reshape(meridians, 6, 3)
    blocks += [Block.from_hull(p, tags=("voussoir", "keystone")) for p in wedge_points]
    return blocks
