"""Flying buttresses: volume against the closed form, joints normal to the arch line, contacts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from stereotomy_checks import ROTATED, assert_convex, interface_counts, local_bounds

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.scope import Scope
from shapegen.primitives import insert

SCOPE = Scope.axis_aligned((0.0, 0.0, 0.0), (4.0, 6.0, 1.5))


def buttress_volume(scope: Scope, angle: float, thickness: float, pier: float) -> float:
    """Flyer (an annular sector of ``angle``) plus pier (a trapezoid under the sloping springing).

    The intrados leaves the pier's inner top edge and the extrados crown touches the scope's top
    at the wall, with a horizontal tangent: the centre lies on the wall plane, and the intrados
    radius r satisfies r sin(angle) = sx - pier.
    """
    a = math.radians(angle)
    inner = (scope.sx - pier) / math.sin(a)
    outer = inner + thickness
    centre_y = scope.sy - outer
    springing_y = centre_y + inner * math.cos(a)
    flyer = a / 2 * (outer**2 - inner**2) * scope.sz
    pier_volume = pier * scope.sz * (springing_y + pier / math.tan(a) / 2)
    return flyer + pier_volume


@pytest.mark.parametrize(
    "scope, angle, thickness, pier",
    [(SCOPE, 60.0, 0.3, 0.6), (SCOPE, 90.0, 0.5, 0.8), (ROTATED, 45.0, 0.25, 0.5)],
)
def test_flying_buttress_volume_closed_form(scope, angle, thickness, pier):
    blocks = insert(
        "flying_buttress",
        scope,
        angle=angle,
        thickness=thickness,
        pier_width=pier,
        segments=48,
        pier_courses=3,
    )
    assert len(blocks) == 48 + 3
    exact = buttress_volume(scope, angle, thickness, pier)
    assert sum(b.volume for b in blocks) == pytest.approx(exact, rel=5e-3)
    assert_convex(blocks)


@pytest.mark.parametrize("angle", [30.0, 60.0, 90.0])
def test_flyer_props_the_wall_and_springs_at_its_angle(angle):
    scope = ROTATED
    blocks = insert("flying_buttress", scope, angle=angle, segments=6, pier_width=0.6)
    lower, upper = local_bounds(blocks, scope)
    np.testing.assert_allclose(lower, [0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(upper[[0, 2]], [scope.sx, scope.sz], atol=1e-12)
    assert upper[1] == pytest.approx(scope.sy, abs=1e-12)
    flyer = [b for b in blocks if "flyer" in b.tags]
    pier_top = [b for b in blocks if "pier" in b.tags][-1]
    # The last joint is the wall plane x = sx; the first is the pier's top, whose normal is the
    # arch line's tangent at the springing, inclined `angle` above the horizontal.
    wall_side = scope.to_local(flyer[-1].vertices)[:, 0]
    assert np.sum(np.abs(wall_side - scope.sx) < 1e-12) == 4
    local_normals = pier_top.face_normals @ scope.rotation
    a = math.radians(angle)
    expected = np.array([math.cos(a), math.sin(a), 0.0])
    assert np.abs(local_normals - expected).sum(axis=1).min() < 1e-9


@pytest.mark.parametrize("segments, pier_courses", [(1, 1), (5, 3), (8, 4)])
def test_flying_buttress_interfaces(segments, pier_courses):
    blocks = insert("flying_buttress", SCOPE, segments=segments, pier_courses=pier_courses)
    internal, ground = interface_counts(blocks)
    assert internal == (pier_courses - 1) + 1 + (segments - 1)
    assert ground == 1


BAD_PARAMETERS = [
    ({"angle": 0.0}, "'angle' must be in \\(0, 90\\]"),
    ({"angle": 95.0}, "'angle' must be in \\(0, 90\\]"),
    ({"thickness": 0.0}, "'thickness' must be positive"),
    ({"pier_width": 4.0}, "'pier_width' must be positive and smaller than the scope width"),
    ({"pier_width": 0.1, "thickness": 0.3}, "'pier_width'.*must carry the whole springing"),
    ({"angle": 90.0}, "'angle'.*needs a taller scope"),
    ({"segments": 0}, "'segments' must be at least 1"),
    ({"pier_courses": 0}, "'pier_courses' must be at least 1"),
]


@pytest.mark.parametrize("params, message", BAD_PARAMETERS)
def test_impossible_parameters_are_reported(params, message):
    with pytest.raises(GeometryError, match=f"primitive 'flying_buttress'.*{message}"):
        insert("flying_buttress", Scope.axis_aligned((0, 0, 0), (4.0, 3.0, 1.0)), **params)


@pytest.mark.parametrize("angle, thickness", [(60.0, 0.3), (45.0, 0.4), (90.0, 0.5)])
def test_flying_buttress_stands_against_its_wall_and_falls_without_it(angle, thickness):
    from shapegen.model.model import Model
    from shapegen.statics import analyze

    scope = Scope.axis_aligned((0.0, 0.0, 0.0), (4.0, 6.0, 1.0))
    blocks = insert(
        "flying_buttress", scope, angle=angle, thickness=thickness, segments=8, pier_width=1.0
    )
    wall = Block.box([4.0, 0.0, 0.0], [5.0, 7.0, 1.0], fixed=True)
    assert analyze(Model(blocks + [wall])).feasible
    assert not analyze(Model(blocks)).feasible
