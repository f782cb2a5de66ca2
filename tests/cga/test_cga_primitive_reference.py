"""CityEngine's primitives against its runtime: each case of ``tests/data/prt_primitives.json``
was run through PyPRT by ``tools/prt_primitives.py`` (its source field says how); shapegen
must give the same scope (size and origin), the same vertices and faces and, for a quad or
disk, the same facing. op_primitive: "If dimensions are specified the cube is positioned in the
xz-center of the scope lying on y=0"; "If no width, height and depth are given the bounding box
coincides with the scope. Zero scope sizes are handled the same way as in the i operation"; a
quad or disk "will be inserted with respect to the plane defined by the valued scope sizes"."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.distance import cdist

import shapegen

_DATA = json.loads(
    (Path(__file__).resolve().parents[1] / "data" / "prt_primitives.json").read_text()
)
_CASES = _DATA["cases"]
_LOT = [tuple(p) for p in _DATA["lot"]]
_TOLERANCE_M = 2e-4  # PyPRT's figures are rounded to 0.1 mm
_SCOPE = ("sx", "sy", "sz", "tx", "ty", "tz")


def _derive(rule: str, lot=None):
    reports = " ".join(f'report("{k}", scope.{k})' for k in _SCOPE)
    text = f"@StartRule\nLot --> {rule} {reports} X.\n"
    return shapegen.parse_grammar(text, "primitives.cga").build(lot=lot or (10.0, 10.0))


def _points(model) -> np.ndarray:
    return np.vstack([b.vertices for b in model.blocks] + [s.vertices for s in model.surfaces])


def test_the_lot_is_the_one_pyprt_was_given():
    # shapegen's 10 x 10 lot is PyPRT's initial shape, first vertex and first edge included
    model = shapegen.parse_grammar("@StartRule\nLot --> X.", "lot.cga").build(lot=(10.0, 10.0))
    assert np.allclose(model.surfaces[0].vertices, _LOT)


@pytest.mark.parametrize("case", _CASES, ids=[c["rule"] for c in _CASES])
def test_primitive_as_cityengine_derives_it(case):
    model = _derive(case["rule"])
    reports = model.metadata["reports"]
    size = [reports[k] for k in _SCOPE[:3]]
    # scope.t is relative to the lot's first vertex in both runtimes
    origin = np.array([reports[k] for k in _SCOPE[3:]]) + _LOT[0]
    assert size == pytest.approx(case["scope_size"], abs=_TOLERANCE_M)
    assert origin.tolist() == pytest.approx(case["scope_origin"], abs=_TOLERANCE_M)
    points = _points(model)
    assert points.min(axis=0).tolist() == pytest.approx(case["lo"], abs=_TOLERANCE_M)
    assert points.max(axis=0).tolist() == pytest.approx(case["hi"], abs=_TOLERANCE_M)
    assert len(points) == case["vertices"]
    assert sum(len(leaf.faces) for leaf in [*model.blocks, *model.surfaces]) == case["faces"]
    if "points" in case:  # the same vertices, each within the rounding of the other's
        distances = cdist(points, np.array(case["points"]))
        assert distances.min(axis=0).max() < _TOLERANCE_M
        assert distances.min(axis=1).max() < _TOLERANCE_M
    if "normal" in case:
        (surface,) = model.surfaces
        (face,) = surface.faces
        normal = _face_normal(surface.vertices[list(face)])
        assert normal.tolist() == pytest.approx(case["normal"], abs=1e-6)


def _face_normal(points: np.ndarray) -> np.ndarray:
    """The unit normal of one polygon through ``points`` in order (Newell's sum)."""
    total = sum(np.cross(points[i] - points[0], points[i + 1] - points[0])
                for i in range(1, len(points) - 1))  # fmt: skip
    return total / np.linalg.norm(total)


def test_a_cube_with_sizes_becomes_the_scope_that_s_then_resizes():
    # the rule of issue 45 on a 10 x 10 lot: the scope is the 20 x 2 x 20 cube, centred on the
    # lot and lying on y = 0, so s(4, 1, 4) keeps its corner (-5, 0, -5): C is 4 x 1 x 4 there
    text = "@StartRule\nLot --> primitiveCube(20, 2, 20) B\nB --> s(4, 1, 4) C.\n"
    model = shapegen.parse_grammar(text, "mausoleum.cga").build(lot=(10.0, 10.0))
    (block,) = model.blocks
    lo, hi = block.vertices.min(axis=0), block.vertices.max(axis=0)
    assert lo.tolist() == pytest.approx([-5, 0, -5]) and hi.tolist() == pytest.approx([-1, 1, -1])


@pytest.mark.parametrize(
    "rule, size",
    [
        # op_primitive's examples: "a width of 10, a height of 15, a depth of 20"; "8 sides, a
        # radius of 10, a height of 15" (a radius to the vertices: 20 cos(22.5 degrees) across
        # an octagon's flats, as CityEngine's runtime makes it)
        ("primitiveCube(10, 15, 20)", (10, 15, 20)),
        ("primitiveCylinder(8, 10, 15)", (20 * np.cos(np.pi / 8), 15, 20 * np.cos(np.pi / 8))),
        ("primitiveCone(8, 10, 15)", (20 * np.cos(np.pi / 8), 15, 20 * np.cos(np.pi / 8))),
        ("primitiveSphere(8, 4, 10)", (20 * np.cos(np.pi / 8), 20, 20 * np.cos(np.pi / 8))),
        ("primitiveQuad(10, 20)", (10, 0, 20)),
        ("primitiveDisk(8, 10)", (20 * np.cos(np.pi / 8), 0, 20 * np.cos(np.pi / 8))),
    ],
)
def test_the_reference_examples_keep_their_sizes_on_any_lot(rule, size):
    model = _derive(rule, lot=(30.0, 12.0))
    reports = model.metadata["reports"]
    assert [reports[k] for k in _SCOPE[:3]] == pytest.approx(size)
    centre = (_points(model).min(axis=0) + _points(model).max(axis=0)) / 2
    assert [centre[0], centre[2]] == pytest.approx([15, 6])  # the lot's x-z centre
    assert _points(model)[:, 1].min() == pytest.approx(0.0)  # lying on y = 0
