"""alignScopeToGeometry in every form of op_alignScopeToGeometry (face index or selector, edge
index or selector, and the forms the changelog deprecates), alignScopeToGeometryBBox, and the
pivot both put at the new scope's origin. The shapes are masses whose edges and faces follow
from their coordinates."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import parse_grammar

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_align_scope_to_geometry_selectors": ("op:alignScopeToGeometry",),
    "test_deprecated_two_argument_forms": ("op:alignScopeToGeometry",),
    "test_align_scope_to_geometry_bbox": ("op:alignScopeToGeometryBBox",),
    "test_scope_operations_take_edge_shapes": ("op:alignScopeToAxes", "op:rotateScope"),
}

# A trapezoid lot (x, z), counter-clockwise seen from above: its first edge (0, 8)-(12, 8) is
# 12 m, the opposite one 6 m, the slanted ones 8.54 m.
TRAPEZOID = [(0, 8), (12, 8), (9, 0), (3, 0)]

_AXES = (
    'report("o", convert(scope, world, pos, [0, 0, 0])) '
    'report("x", convert(scope, world, pos, [1, 0, 0])) '
    'report("y", convert(scope, world, pos, [0, 1, 0])) '
    'report("t", [scope.tx, scope.ty, scope.tz, scope.rx, scope.ry, scope.rz]) '
)


def _frame(text: str, lot=TRAPEZOID):
    """The scope's origin, x and y axes (world) and its placement relative to the pivot, and
    the derivation's warnings."""
    model = parse_grammar("@StartRule\n" + text, "align.cga").build(lot=lot)
    reports = model.metadata["reports"]
    point = {k: np.array(reports[k].values) for k in "oxy"}
    return (
        point["o"],
        point["x"] - point["o"],
        point["y"] - point["o"],
        list(reports["t"].values),
        model.metadata["warnings"],
    )


@pytest.mark.parametrize(
    ("selectors", "x_axis", "y_axis"),
    [
        # face 0 is the extruded lot's bottom (normal down); its edge 0 is the first edge turned
        # (op_extrude: the bottom starts on the lot's second vertex): along -x
        ("0, 0", (-1, 0, 0), (0, -1, 0)),
        ("1, 0", (1, 0, 0), (0, 1, 0)),  # the top: the lot's first edge, along +x
        ("largest, longest", (-1, 0, 0), (0, -1, 0)),  # bottom and top tie: the first, bottom
        ("world.lowest, longest", (-1, 0, 0), (0, -1, 0)),
        ("1, longest", (1, 0, 0), (0, 1, 0)),
        ("any, longest", None, None),
        ("any, world.lowest", None, None),
    ],
)
def test_align_scope_to_geometry_selectors(selectors, x_axis, y_axis):
    origin, x, y, placement, _ = _frame(
        f"Lot --> extrude(3) alignScopeToGeometry(yUp, {selectors}) {_AXES} X."
    )
    # the x axis runs along a 12 m edge (the longest, the lowest first) and the up axis along
    # its face's normal; the pivot is the scope's origin
    assert np.isclose(abs(x[0]), 1) and np.isclose(abs(y @ [0, 1, 0]) + abs(y @ [0, 0, 1]), 1)
    if x_axis is not None:
        assert np.allclose(x, x_axis) and np.allclose(y, y_axis)
    assert np.allclose(placement, 0, atol=1e-9)


def test_negative_indices_count_from_the_end():
    # op_alignScopeToGeometry: "-1 is the last face"; the last side is the left one, x along
    # its first edge from (3, 0, 0) to (0, 0, 8)
    origin, x, y, _, _ = _frame(f"Lot --> extrude(3) alignScopeToGeometry(zUp, -1, 0) {_AXES} X.")
    assert np.allclose(x, np.array([-3, 0, 8]) / np.hypot(3, 8))


@pytest.mark.parametrize(
    ("deprecated", "modern", "warning"),
    [
        # cga_changelog: alignScopeToGeometry(upAxis, faceIndex), the face's first edge
        ("yUp, 1", "yUp, 1, 0", "(upAxis, faceIndex) is deprecated"),
        # (upAxis, auto): the lowest edge; a side face's is its bottom edge
        ("zUp, auto", "zUp, any, world.lowest", "(upAxis, auto) is deprecated"),
    ],
)
def test_deprecated_two_argument_forms(deprecated, modern, warning):
    old = _frame(f"Lot --> extrude(3) alignScopeToGeometry({deprecated}) {_AXES} X.")
    new = _frame(f"Lot --> extrude(3) alignScopeToGeometry({modern}) {_AXES} X.")
    for a, b in zip(old[:3], new[:3], strict=True):
        assert np.allclose(a, b)
    assert any(warning in w for w in old[4])


def test_auto_on_a_flat_shape_takes_the_longest_edge():
    # 2009.2: "if all edges are on the same y-coordinate, the longest edge is taken"
    _, x, _, _, _ = _frame(f"Lot --> alignScopeToGeometry(yUp, auto) {_AXES} X.", lot=(6, 8))
    assert np.allclose(np.abs(x), [0, 0, 1])


def test_an_index_past_the_end_is_taken_modulo_with_a_warning():
    wrapped = _frame(f"Lot --> extrude(3) alignScopeToGeometry(yUp, 1, 5) {_AXES} X.")
    plain = _frame(f"Lot --> extrude(3) alignScopeToGeometry(yUp, 1, 1) {_AXES} X.")
    assert np.allclose(wrapped[1], plain[1])
    assert any("taken modulo 4" in w for w in wrapped[4])


# a 10 x 4 rectangle turned 30 degrees about y, extruded 2 m: seen from above its minimum-area
# rectangle is itself (10 x 4); seen along world z it is 10 cos 30 + 4 sin 30 wide and 2 high;
# seen along world x, 10 sin 30 + 4 cos 30 deep and 2 high
_C, _S = np.cos(np.radians(30)), np.sin(np.radians(30))
_SEEN = {1: (10.0, 4.0), 2: (10 * _C + 4 * _S, 2.0), 0: (10 * _S + 4 * _C, 2.0)}


@pytest.mark.parametrize("axes", ["xz", "zx", "xy", "yx", "yz", "zy"])
def test_align_scope_to_geometry_bbox(axes):
    # op_alignScopeToGeometryBBox: the two axes span the minimum-area rectangle seen along the
    # third, which stays; the first named runs along its longer side; the pivot at the scope
    first, second = ("xyz".index(c) for c in axes)
    fixed = 3 - first - second
    lot = [(0, 0), (10 * _C, -10 * _S), (10 * _C - 4 * _S, -10 * _S - 4 * _C), (-4 * _S, -4 * _C)]
    text = (
        f"Lot --> extrude(2) alignScopeToAxes() alignScopeToGeometryBBox({axes}) "
        'report("s", [scope.sx, scope.sy, scope.sz]) '
        'report("t", [scope.tx, scope.ty, scope.tz, scope.rx, scope.ry, scope.rz]) X.'
    )
    reports = parse_grammar("@StartRule\n" + text, "bbox.cga").build(lot=lot).metadata["reports"]
    size = list(reports["s"].values)
    longer, shorter = _SEEN[fixed]
    assert np.isclose(size[first], longer) and np.isclose(size[second], shorter)
    assert np.allclose(list(reports["t"].values), 0, atol=1e-9)


def test_scope_operations_take_edge_shapes():
    # cga_changelog: alignScopeToAxes works on the empty geometry of comp(e|v) and scatter;
    # the bottom's first edge runs 12 m along -x: aligned to the world it spans x
    reports = (
        parse_grammar(
            "@StartRule\nLot --> extrude(3) comp(e) { 0 : "
            'alignScopeToAxes() report("a", [scope.sx, scope.sy, scope.sz]) '
            'rotateScope(0, 90, 0) report("r", [scope.sx, scope.sy, scope.sz]) X. }',
            "edges.cga",
        )
        .build(lot=(12.0, 8.0))
        .metadata["reports"]
    )
    assert np.allclose(list(reports["a"].values), [12, 0, 0])
    assert np.allclose(list(reports["r"].values), [0, 0, 12])  # turned: the edge along z
