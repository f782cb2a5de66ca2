"""``barrel_vault`` and ``groin_vault``: semicircular vaults of voussoirs with radial joints."""

from __future__ import annotations

__all__ = ["barrel_vault", "groin_vault"]

import manifold3d
import numpy as np

from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives.arch import circular_arch_line
from shapegen.primitives.prism import prism_blocks
from shapegen.primitives.registry import primitive, require, require_blocks
from shapegen.primitives.stereotomy import arc_joints


def _check_span(name: str, scope: Scope, thickness: float, segments: int) -> None:
    require(scope.sx > 0 and scope.sz > 0, name, "scope", f"needs a positive width and depth, "
            f"got sx={scope.sx:g} m, sz={scope.sz:g} m")  # fmt: skip
    require(segments >= 2, name, "segments", f"must be at least 2, got {segments}")
    require(thickness > 0, name, "thickness", f"must be positive, got {thickness:g} m")
    require(
        thickness < scope.sx / 2,
        name,
        "thickness",
        f"({thickness:g} m) must be smaller than the extrados radius (scope width / 2 = "
        f"{scope.sx / 2:g} m)",
    )


def _voussoir_sections(scope: Scope, thickness: float, segments: int) -> np.ndarray:
    """``(segments, 4, 2)`` voussoir quadrilaterals of the semicircle spanning the scope's x
    (springing at y = 0, x = 0 and x = sx), counter-clockwise, metres."""
    intrados, extrados = circular_arch_line(scope.sx, thickness, segments)
    return np.stack([intrados[:-1], intrados[1:], extrados[1:], extrados[:-1]], axis=1)


def _staggered_section(scope: Scope, thickness: float, segments: int) -> np.ndarray:
    """``(segments + 2, 2, 2)`` joints of a semicircle shifted by half a voussoir: half voussoirs
    at both springings, ``segments - 1`` whole ones between (metres)."""
    radius_out = scope.sx / 2
    step = np.pi / segments
    angles = np.concatenate([[np.pi], np.pi - step * (np.arange(segments) + 0.5), [0.0]])
    joints = arc_joints(radius_out - thickness, radius_out, angles, centre=(radius_out, 0.0))
    joints[[0, -1], :, 1] = 0.0  # springing joints exactly on the scope's bottom face
    return joints


@primitive("barrel_vault", scope_relative=True)
def barrel_vault(
    scope: Scope,
    *,
    thickness: float = 0.3,
    segments: int = 12,
    courses: int = 1,
    running_bond: bool = False,
) -> list[Block]:
    """A semicircular barrel vault spanning the scope's x and running along its z.

    The extrados radius is half the scope width (``sx / 2``); the vault springs from the scope's
    bottom face (y = 0) at x = 0 and x = sx. The scope height is not used (the rise is ``sx / 2``).
    Joints are radial (normal to the arch line); curved faces are planar chords.

    Parameters
    ----------
    thickness
        Radial thickness of the vault, metres; smaller than ``sx / 2``.
    segments
        Voussoirs around the semicircle (>= 2).
    courses
        Rings of voussoirs along z (>= 1), each ``sz / courses`` metres deep; joints between
        courses are planes z = const.
    running_bond
        Shift every second course (the second, fourth...) by half a voussoir, with half
        voussoirs at both springings, so that the radial joints of neighbouring courses do not
        line up.
    """
    name = "barrel_vault"
    _check_span(name, scope, thickness, segments)
    require(courses >= 1, name, "courses", f"must be at least 1, got {courses}")
    require_blocks(name, (segments + 1) * courses, "segments x courses")
    intrados, extrados = circular_arch_line(scope.sx, thickness, segments)
    sections = [np.stack([intrados, extrados], axis=1)]
    if running_bond and courses > 1:
        sections.append(_staggered_section(scope, thickness, segments))
    levels = np.linspace(0.0, scope.sz, courses + 1)
    blocks = []
    for course in range(courses):
        joints = sections[course % len(sections)]
        m = len(joints)
        profile = np.vstack([joints[:, 0], joints[:, 1]])
        pool = np.zeros((4 * m, 3))  # the profile at the course's front and back planes
        pool[:, :2] = np.vstack([profile, profile])
        pool[: 2 * m, 2], pool[2 * m :, 2] = levels[course], levels[course + 1]
        rings = [
            ([j, j + 1, m + j + 1, m + j], [2 * m + j, 2 * m + j + 1, 3 * m + j + 1, 3 * m + j])
            for j in range(m - 1)
        ]
        blocks += prism_blocks(scope, pool, rings, tags=("voussoir",))
    return blocks


@primitive("groin_vault", scope_relative=True)
def groin_vault(scope: Scope, *, thickness: float = 0.3, segments: int = 12) -> list[Block]:
    """Two semicircular barrel vaults crossing over the scope's plan, meeting at diagonal groins.

    Vault A spans x and runs along z; vault B spans z and runs along x. Each voussoir of A (or B)
    is cut by the two vertical planes through the plan's diagonals and kept where A (or B) is the
    upper vault; the groins are those diagonal planes, and the pieces of A and B meeting there
    share their faces exactly. The vault is built for a square plan of side ``sx`` and stretched
    along z to the depth ``sz``: over a rectangular plan, vault B becomes elliptical with the same
    rise ``sx / 2`` as vault A (so the groins stay plane).

    Parameters
    ----------
    thickness
        Radial thickness of vault A, metres; smaller than ``sx / 2`` (vault B's is stretched by
        ``sz / sx`` along z).
    segments
        Voussoirs around each semicircle (>= 2); every voussoir yields two pieces, one at each end
        of its barrel.
    """
    name = "groin_vault"
    _check_span(name, scope, thickness, segments)
    require_blocks(name, 4 * segments, "4 x segments")
    side = scope.sx
    sections = _voussoir_sections(scope, thickness, segments)
    # Vault A: the sections in (x, y), extruded along z from 0 to the side.
    prisms = np.zeros((segments, 8, 3))
    prisms[:, :4, :2] = sections
    prisms[:, 4:, :2] = sections
    prisms[:, 4:, 2] = side
    # Vault B is vault A turned a quarter about the plan's vertical centre line: (x, z) -> (z, x).
    swap = np.array([2, 1, 0])
    root = np.sqrt(0.5)
    # Half-spaces n . p >= d (unit n) keeping each end of vault A, where |z - c| >= |x - c|.
    ends = (
        ((np.array([-root, 0.0, root]), 0.0), (np.array([root, 0.0, root]), side * root)),
        ((np.array([root, 0.0, -root]), 0.0), (np.array([-root, 0.0, -root]), -side * root)),
    )
    stretch = np.array([1.0, 1.0, scope.sz / side])
    blocks = []
    for tag, axes in (("vault_A", np.arange(3)), ("vault_B", swap)):
        for end in ends:
            for prism in prisms[:, :, axes]:
                solid = manifold3d.Manifold.hull_points(prism)
                for normal, offset in end:
                    solid = solid.trim_by_plane(tuple(normal[axes].tolist()), offset)
                if solid.is_empty():
                    continue
                points = np.asarray(solid.to_mesh64().vert_properties)[:, :3] * stretch
                blocks.append(Block.from_hull(scope.to_world(points), tags=("voussoir", tag)))
    return blocks
