"""Arches: exact volumes against closed forms, convex voussoirs, radial joints, shared faces."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import minimize_scalar
from stereotomy_checks import interface_counts

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.model.scope import Scope
from shapegen.primitives import insert
from shapegen.primitives.arch import semicircular_arch
from shapegen.statics import analyze
from shapegen.statics.contacts import find_interfaces
from shapegen.statics.interface import GROUND


def half_ring_area(outer: float, inner: float) -> float:
    return math.pi * (outer**2 - inner**2) / 2


def pointed_opening_area(radius: float, offset: float) -> float:
    """Area under a two-centred arc of ``radius`` whose centres lie ``offset`` from the middle."""
    return radius**2 * math.acos(offset / radius) - offset * math.sqrt(radius**2 - offset**2)


def total_volume(blocks) -> float:
    return sum(b.volume for b in blocks)


@pytest.mark.parametrize(
    "width, thickness, depth", [(3.0, 0.3, 0.5), (10.0, 1.0, 2.0), (2.0, 0.9, 0.1)]
)
def test_semicircular_arch_volume_is_the_half_annulus(width, thickness, depth):
    blocks = insert(
        "arch", Scope.axis_aligned((1, 2, 3), (width, 1.0, depth)), thickness=thickness, segments=64
    )
    outer = width / 2
    exact = half_ring_area(outer, outer - thickness) * depth
    assert len(blocks) == 64
    assert total_volume(blocks) == pytest.approx(exact, rel=5e-3)
    # Chords cut more from the extrados than they add at the intrados.
    assert total_volume(blocks) < exact


@pytest.mark.parametrize("pointedness", [0.0, 0.5, 1.0, 1.5])
def test_pointed_arch_volume(pointedness):
    width, thickness, depth = 4.0, 0.4, 0.7
    blocks = insert(
        "arch",
        Scope.axis_aligned((0, 0, 0), (width, 1.0, depth)),
        style="gothic",
        thickness=thickness,
        segments=80,
        pointedness=pointedness,
    )
    offset = pointedness * width / 2
    outer = width / 2 + offset
    area = pointed_opening_area(outer, offset) - pointed_opening_area(outer - thickness, offset)
    assert total_volume(blocks) == pytest.approx(area * depth, rel=5e-3)
    # The extrados crown of a two-centred arch is at sqrt(R^2 - e^2).
    top = max(b.vertices[:, 1].max() for b in blocks)
    assert top == pytest.approx(math.sqrt(outer**2 - offset**2), rel=1e-12)


def test_gothic_with_zero_pointedness_is_the_semicircular_arch():
    scope = Scope.axis_aligned((0, 0, 0), (3.0, 2.0, 1.0))
    round_arch = insert("arch", scope, segments=10)
    pointed = insert("arch", scope, style="gothic", segments=10, pointedness=0.0)
    for a, b in zip(round_arch, pointed, strict=True):
        np.testing.assert_allclose(
            np.sort(a.vertices, axis=0), np.sort(b.vertices, axis=0), atol=1e-12
        )


@pytest.mark.parametrize("style", ["romanesque", "gothic"])
def test_capped_arch_fills_the_scope_but_the_opening(style):
    width, height, depth, thickness, pointedness = 3.0, 2.5, 0.4, 0.3, 0.6
    blocks = insert(
        "capped_arch",
        Scope.axis_aligned((0, 0, 0), (width, height, depth)),
        style=style,
        thickness=thickness,
        segments=100,
        pointedness=pointedness,
    )
    offset = pointedness * width / 2 if style == "gothic" else 0.0
    opening = pointed_opening_area(width / 2 + offset - thickness, offset)
    assert total_volume(blocks) == pytest.approx((width * height - opening) * depth, rel=5e-3)
    assert max(b.vertices[:, 1].max() for b in blocks) == pytest.approx(height)
    assert sum("spandrel" in b.tags for b in blocks) == 100


def test_bezier_arch_volume_is_thickness_times_curve_length():
    # With vertical tangents at the springings every joint is normal to the curve, and a band of
    # constant thickness t about a curve of length L has area t * L.
    width, height, depth, thickness = 4.0, 3.0, 0.5, 0.25
    c1x, c1y, c2x, c2y = 0.0, 0.9, 1.0, 1.3
    blocks = insert(
        "bezier_arch",
        Scope.axis_aligned((0, 0, 0), (width, height, depth)),
        thickness=thickness,
        segments=120,
        c1x=c1x,
        c1y=c1y,
        c2x=c2x,
        c2y=c2y,
    )
    x0, span = thickness / 2, width - thickness
    px = np.array([x0, x0 + c1x * span, x0 + c2x * span, x0 + span])
    py = np.array([0.0, c1y * height, c2y * height, 0.0])

    def basis(s):
        return np.array([(1 - s) ** 3, 3 * (1 - s) ** 2 * s, 3 * (1 - s) * s**2, s**3])

    def dbasis(s):
        return np.array(
            [-3 * (1 - s) ** 2, 3 * (1 - s) * (1 - 3 * s), 3 * s * (2 - 3 * s), 3 * s**2]
        )

    rise = -minimize_scalar(lambda s: -basis(s) @ py, bounds=(0, 1), method="bounded").fun
    py *= (height - thickness / 2) / rise
    length = quad(lambda s: math.hypot(dbasis(s) @ px, dbasis(s) @ py), 0, 1)[0]
    assert total_volume(blocks) == pytest.approx(thickness * length * depth, rel=5e-3)
    assert max(b.vertices[:, 1].max() for b in blocks) == pytest.approx(height, rel=1e-3)


def test_bezier_arch_that_folds_is_an_error():
    scope = Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 0.5))
    with pytest.raises(GeometryError, match="bezier_arch.*voussoir .* not convex"):
        insert("bezier_arch", scope, thickness=1.5, segments=40, c1x=1.0, c1y=2.0, c2x=0.0, c2y=2.0)


@pytest.mark.parametrize(
    "name, params",
    [
        ("arch", {"segments": 12}),
        ("arch", {"style": "gothic", "segments": 30, "pointedness": 1.0, "thickness": 0.9}),
        ("capped_arch", {"segments": 7}),
        ("capped_arch", {"style": "gothic", "segments": 8}),
        ("bezier_arch", {"segments": 9, "c1x": 0.2, "c2x": 0.6}),
    ],
)
def test_every_voussoir_is_convex_and_in_the_scope(name, params):
    rotation = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # 90 deg about y
    scope = Scope(np.array([5.0, 1.0, -2.0]), rotation, np.array([3.0, 2.7, 0.6]))
    blocks = insert(name, scope, **params)
    for block in blocks:
        distances = block.vertices @ block.face_normals.T - block.face_offsets
        assert distances.max() < 1e-9
        assert block.volume > 0
        local = scope.to_local(block.vertices)
        assert np.all(local > -1e-9) and np.all(local < scope.size + 1e-9)


def test_semicircular_joints_are_radial():
    radius, thickness = 2.0, 0.3
    model = Model(semicircular_arch(radius, thickness, 12, depth=0.5, centre=(1.0, 0.0, 0.0)))
    internal = [i for i in find_interfaces(model) if i.second != GROUND]
    for interface in internal:
        to_centre = interface.centroid - [1.0, 0.0, interface.centroid[2]]
        # The joint plane contains the line through the centre: its normal is perpendicular to it.
        assert abs(np.dot(interface.normal, to_centre)) < 1e-9
        assert interface.area == pytest.approx(thickness * 0.5, rel=1e-9)
    for block in model.blocks:
        r = np.hypot(block.vertices[:, 0] - 1.0, block.vertices[:, 1])
        assert np.all(np.isclose(r, radius - thickness / 2) | np.isclose(r, radius + thickness / 2))


@pytest.mark.parametrize("style", ["romanesque", "gothic"])
def test_twelve_segment_arch_on_the_ground_has_11_joints_and_2_springings(style):
    blocks = insert(
        "arch", Scope.axis_aligned((0, 0, 0), (4.0, 2.0, 1.0)), style=style, segments=12
    )
    assert interface_counts(blocks) == (11, 2)
    springings = [i for i in find_interfaces(Model(blocks, ground=0.0)) if i.second == GROUND]
    assert sum(i.area for i in springings) == pytest.approx(2 * 0.3 * 1.0, rel=1e-9)


def test_capped_arch_pieces_share_faces():
    blocks = insert("capped_arch", Scope.axis_aligned((0, 0, 0), (4.0, 2.5, 1.0)), segments=12)
    interfaces = find_interfaces(Model(blocks, ground=0.0))
    # 11 voussoir joints, 12 voussoir-spandrel beds, 11 vertical joints between spandrels.
    assert sum(i.second != GROUND for i in interfaces) == 11 + 12 + 11
    assert sum(i.second == GROUND for i in interfaces) == 2


def test_mirrored_scope_keeps_faces_outward():
    mirror = np.diag([-1.0, 1.0, 1.0])
    blocks = insert("arch", Scope(np.zeros(3), mirror, np.array([3.0, 2.0, 1.0])), segments=8)
    assert all(b.volume > 0 for b in blocks)
    assert total_volume(blocks) == pytest.approx(8 / 2 * (1.5**2 - 1.2**2) * math.sin(math.pi / 8))


# (primitive, parameters (the scope 3 x 2 x 1 m unless given), words of the error)
MISTAKES = [
    ("arch", {"thickness": 2.0},
     "primitive 'arch': parameter 'thickness' must be less than the extrados radius 1.5 m"),
    ("arch", {"thickness": 0.0},
     "primitive 'arch': parameter 'thickness' must be positive, got 0 m"),
    ("arch", {"thickness": -0.1},
     "primitive 'arch': parameter 'thickness' must be positive, got -0.1 m"),
    ("arch", {"segments": 1}, "'segments' must be at least 2, got 1"),
    ("arch", {"segments": 0}, "'segments' must be at least 2, got 0"),
    ("arch", {"style": "baroque"}, "parameter 'style' must be one of 'romanesque', 'gothic'"),
    ("arch", {"style": "gothic", "segments": 7}, "'segments' must be even for a gothic arch"),
    ("arch", {"style": "gothic", "pointedness": -1.0},
     "'pointedness' must be 0 (semicircular) or more, got -1"),
    ("arch", {"scope": (0, 2, 1)},
     "primitive 'arch': parameter 'scope' needs a positive width and depth"),
    ("arch", {"segments": 2.5}, "parameter 'segments' must be a whole number"),
    ("capped_arch", {"scope": (3, 1, 1)},
     "primitive 'capped_arch': parameter 'scope' height 1 m is below the arch's crown at 1.5 m"),
    ("capped_arch", {"thickness": 1.5}, "'thickness' must be less than the extrados radius"),
    ("bezier_arch", {"thickness": 1.6},
     "primitive 'bezier_arch': parameter 'thickness' must be less than half"),
    ("bezier_arch", {"segments": 1},
     "primitive 'bezier_arch': parameter 'segments' must be at least 2, got 1"),
    ("bezier_arch", {"c1y": 0.0, "c2y": 0.0}, "does not rise above the springings"),
    ("bezier_arch", {"c1y": -1.0, "c2y": 1.0}, "dips below the springings"),
]  # fmt: skip


@pytest.mark.parametrize("name, params, message", MISTAKES)
def test_impossible_parameters_are_named(name, params, message):
    params = dict(params)
    size = params.pop("scope", (3, 2, 1))
    with pytest.raises(GeometryError) as error:
        insert(name, Scope.axis_aligned((0, 0, 0), size), **params)
    assert message in str(error.value)


@pytest.mark.parametrize("style", ["romanesque", "gothic"])
@pytest.mark.parametrize("segments", [12, 13, 24])
def test_capped_arch_between_piers_stands(style, segments):
    # The seed paper's Figure 3: capped arches stand between piers that hold the spandrels' sides.
    if style == "gothic" and segments % 2:
        segments += 1
    height = 2.4
    blocks = insert(
        "capped_arch",
        Scope.axis_aligned((0, 0, 0), (3.0, height, 1.0)),
        style=style,
        segments=segments,
        pointedness=0.4,
    )
    piers = [
        Block.box([-1.0, 0.0, 0.0], [0.0, height, 1.0]),
        Block.box([3.0, 0.0, 0.0], [4.0, height, 1.0]),
    ]
    assert analyze(Model(blocks + piers, friction=0.7)).feasible
