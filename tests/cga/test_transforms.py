"""translate and rotate (op_translate, op_rotate) in the scope, pivot, object and world frames,
the pivot (attr_pivot) that comp, setPivot and the alignScopeTo* operations set, and what reads
the frames: pivot.*, initialShape.origin.*, scope.t* / scope.r* (relative to the pivot in .cga
files) and convert(..., pivot, ...). Checked on the reference's examples and on shapes whose
answers follow from their coordinates."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import parse_grammar

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_translate_rel_world_moves_along_the_world_axis": ("op:translate",),
    "test_translate_in_each_frame": ("op:translate",),
    "test_rotate_abs_world_sets_the_orientation": ("op:rotate",),
    "test_rotate_rel_adds_the_angles": ("op:rotate",),
    "test_the_pivot_after_comp": (
        "attr:pivot.px",
        "attr:pivot.py",
        "attr:pivot.pz",
        "attr:pivot.ox",
        "attr:pivot.oy",
        "attr:pivot.oz",
    ),
    "test_initial_shape_origin_is_the_first_vertex": (
        "attr:initialShape.origin.px",
        "attr:initialShape.origin.py",
        "attr:initialShape.origin.pz",
        "attr:initialShape.origin.ox",
        "attr:initialShape.origin.oy",
        "attr:initialShape.origin.oz",
    ),
    "test_scope_placement_is_relative_to_the_pivot": (
        "attr:scope.tx",
        "attr:scope.ty",
        "attr:scope.tz",
        "attr:scope.rx",
        "attr:scope.ry",
        "attr:scope.rz",
    ),
    "test_convert_to_the_pivot_as_the_reference_example": ("func:convert",),
    "test_scope_sizes": ("attr:scope.sx", "attr:scope.sy", "attr:scope.sz"),
    "test_operations_that_put_the_pivot_at_the_scope": (
        "op:alignScopeToAxes",
        "op:setPivot",
    ),
}


def _reports(text: str, lot=(12.0, 8.0)) -> dict:
    grammar = parse_grammar("@StartRule\n" + text, "frames.cga")
    return grammar.build(lot=lot).metadata["reports"]


def _corners(text: str, lot=(12.0, 8.0)) -> np.ndarray:
    model = parse_grammar("@StartRule\n" + text, "frames.cga").build(lot=lot)
    (block,) = model.blocks
    return np.round(np.array(sorted(map(tuple, np.round(block.vertices, 9)))), 9)


def test_translate_rel_world_moves_along_the_world_axis():
    # op_translate's example: the copy moved by two units along the world's x axis, whichever
    # way the scope is turned
    moved = _corners("Lot --> extrude(3) r(0, 90, 0) translate(rel, world, 2, 0, 0) X.")
    turned = _corners("Lot --> extrude(3) r(0, 90, 0) X.")
    assert np.allclose(moved, turned + [2, 0, 0])


@pytest.mark.parametrize(
    ("move", "origin"),
    [
        # scope: t() in the scope's axes; after r(0, 90, 0) the scope's x is world -z
        ("r(0, 90, 0) translate(rel, scope, 1, 0, 0)", (0, 0, -1)),
        ("r(0, 90, 0) translate(abs, scope, 1, 0, 0)", (0, 0, -1)),
        ("translate(abs, world, 5, 1, 2)", (5, 1, 2)),
        ("r(0, 90, 0) translate(rel, world, 0, 0, 3)", (0, 0, 3)),
        # object: origin at the lot's first vertex (0, 0, 8), axes the world's here
        ("translate(abs, object, 1, 2, 3)", (1, 2, 11)),
        ("translate(rel, object, 1, 2, 3)", (1, 2, 3)),
        # pivot: the initial shape's is the object frame
        ("translate(abs, pivot, 0, 0, -8)", (0, 0, 0)),
        ("translate(rel, pivot, 0, 0, -8)", (0, 0, -8)),
    ],
)
def test_translate_in_each_frame(move, origin):
    reports = _reports(
        f"Lot --> extrude(3) {move} "
        "report('x', convert(x, scope, world, pos, 0, 0, 0)) "
        "report('y', convert(y, scope, world, pos, 0, 0, 0)) "
        "report('z', convert(z, scope, world, pos, 0, 0, 0)) X.".replace("'", '"')
    )
    assert np.allclose([reports["x"], reports["y"], reports["z"]], origin)


def test_rotate_abs_world_sets_the_orientation():
    # op_rotate's example: rotate(abs, world, 0, 90, 0) sets the scope's world angles
    reports = _reports(
        "Lot --> extrude(10) t('0.2, 0, '0.3) s('0.5, '1, '0.5) r(10, 20, 30) "
        "rotate(abs, world, 0, 90, 0) "
        'report("a", convert(scope, world, orient, [0, 0, 0])) '
        'report("t", convert(scope, world, pos, [0, 0, 0])) X.'
    )
    assert np.allclose(list(reports["a"].values), [0, 90, 0])
    # the scope turns about its origin, which stays where t() put it
    assert np.allclose(list(reports["t"].values), [2.4, 0, 2.4])


@pytest.mark.parametrize(
    ("rotation", "same_as"),
    [
        ("rotate(rel, scope, 0, 30, 0)", "r(0, 30, 0)"),
        ("rotate(rel, scope, 20, 30, 40)", "r(20, 30, 40)"),
        # the scope is the pivot's axes here, so rel pivot is r() (op_r's note)
        ("rotate(rel, pivot, 20, 30, 40)", "r(20, 30, 40)"),
        ("rotate(rel, world, 0, 45, 0) rotate(rel, world, 0, 45, 0)", "r(0, 90, 0)"),
        ("r(0, 30, 0) rotate(rel, object, 0, 60, 0)", "rotate(abs, object, 0, 90, 0)"),
        ("r(0, 0, 25) rotate(abs, pivot, 0, 0, 0)", "t(0, 0, 0)"),
    ],
)
def test_rotate_rel_adds_the_angles(rotation, same_as):
    assert np.allclose(
        _corners(f"Lot --> extrude(3) {rotation} X."), _corners(f"Lot --> extrude(3) {same_as} X.")
    )


def test_the_pivot_after_comp():
    # op_comp: the pivot at the face's first vertex, along its axes; measured in the object
    # frame (attr_pivot), whose origin is the lot's first vertex (0, 0, 8)
    reports = _reports(
        "Lot --> extrude(3) comp(f) { front : F(0) | right : F(1) }\n"
        "F(k) --> report(k + 'p', [pivot.px, pivot.py, pivot.pz]) "
        "report(k + 'o', [pivot.ox, pivot.oy, pivot.oz]) X.".replace("'", '"')
    )
    assert np.allclose(list(reports["0p"].values), [0, 0, 0])
    assert np.allclose(list(reports["0o"].values), [0, 0, 0])
    assert np.allclose(list(reports["1p"].values), [12, 0, 0])  # the corner at (12, 0, 8)
    assert np.allclose(list(reports["1o"].values), [0, 90, 0])  # x along -z: 90 about y
    before = _reports('Lot --> extrude(3) report("p", [pivot.px, pivot.py, pivot.pz]) X.')
    assert np.allclose(list(before["p"].values), [0, 0, 0])


def test_initial_shape_origin_is_the_first_vertex():
    text = (
        'Lot --> report("p", [initialShape.origin.px, initialShape.origin.py, '
        "initialShape.origin.pz]) "
        'report("o", [initialShape.origin.ox, initialShape.origin.oy, initialShape.origin.oz]) X.'
    )
    rectangle = _reports(text)
    assert np.allclose(list(rectangle["p"].values), [0, 0, 8])
    assert np.allclose(list(rectangle["o"].values), [0, 0, 0])
    # a lot whose first edge runs from (2, 0, 1) along (1, 0, -1): turned 45 degrees about y
    polygon = _reports(text, lot=[(2, 1), (6, -3), (4, -5), (0, -1)])
    assert np.allclose(list(polygon["p"].values), [2, 0, 1])
    assert np.allclose(list(polygon["o"].values), [0, 45, 0])


def test_scope_placement_is_relative_to_the_pivot():
    # attr_scope: "relative to the pivot"; the lot's pivot is its first vertex (0, 0, 8)
    reports = _reports(
        'Lot --> report("t", [scope.tx, scope.ty, scope.tz]) extrude(3) r(0, 30, 0) '
        'report("r", [scope.rx, scope.ry, scope.rz]) comp(f) { top : '
        'report("top", [scope.tx, scope.ty, scope.tz, scope.rx, scope.ry, scope.rz]) X. }'
    )
    assert np.allclose(list(reports["t"].values), [0, 0, -8])
    assert np.allclose(list(reports["r"].values), [0, 30, 0])
    # a comp face's scope and pivot are aligned: zero rotation, the origin at its first vertex
    assert np.allclose(list(reports["top"].values)[3:], [0, 0, 0])


def test_scope_sizes():
    # attr_scope's example: s() sets the size, scope.s* read it
    reports = _reports(
        "Lot --> extrude(3) s('0.5, '1, 2) report(\"s\", [scope.sx, scope.sy, scope.sz]) X."
    )
    assert list(reports["s"].values) == [6.0, 3.0, 2.0]


def test_convert_to_the_pivot_as_the_reference_example():
    # func_convert's example; on a 2 x 2 lot its pivot's answer is the reference's
    reports = _reports(
        "Lot --> extrude(3) t('0.2, 0, '0.7) s('0.5, '1, '0.5) r(-10, 70, 0) "
        'report("p", convert(scope, pivot, pos, [0, 0, 0])) '
        'report("a", convert(scope, pivot, orient, [0, 0, 0])) X.',
        lot=(2.0, 2.0),
    )
    assert np.allclose(list(reports["p"].values), [0.4, 0, -0.6])
    assert np.allclose(list(reports["a"].values), [-10, 70, 0])


@pytest.mark.parametrize(
    "operation", ["alignScopeToAxes()", "alignScopeToAxes(y)", "setPivot(xyz, 0)"]
)
def test_operations_that_put_the_pivot_at_the_scope(operation):
    # op_alignScopeToAxes: "After this operation, the scope.r and the scope.t vectors are
    # zero"; op_setPivot: "The new scope will have zero translation and rotation"
    reports = _reports(
        f"Lot --> extrude(3) r(0, 30, 0) t(1, 0, 2) {operation} "
        'report("s", [scope.tx, scope.ty, scope.tz, scope.rx, scope.ry, scope.rz]) X.'
    )
    assert np.allclose(list(reports["s"].values), 0, atol=1e-9)


def test_reset_geometry_puts_the_pivot_back():
    reports = _reports(
        "Lot --> extrude(3) comp(f) { right : resetGeometry() "
        'report("p", [pivot.px, pivot.py, pivot.pz, pivot.oy]) X. }'
    )
    assert np.allclose(list(reports["p"].values), 0)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        ("translate(world, world, 1, 0, 0)", "mode is one of abs, rel"),
        ("rotate(rel, abs, 1, 0, 0)", "coordSystem is one of scope, pivot, object, world"),
        ("translate(rel, world, 1, 0)", "takes 5 arguments"),
    ],
)
def test_bad_calls_are_refused_when_loaded(call, message):
    from shapegen.errors import GrammarError

    with pytest.raises(GrammarError, match=message):
        parse_grammar(f"@StartRule\nLot --> extrude(3) {call} X.", "frames.cga").build(lot=(4, 2))


def test_a_nan_offset_is_zero_with_a_warning():
    # cga_changelog 2013.1: an inf or nan parameter of a builtin operation is replaced by 0
    model = parse_grammar(
        "@StartRule\nLot --> extrude(3) translate(rel, world, ln(-1), 0, 0) "
        'report("x", convert(x, scope, world, pos, 0, 0, 0)) X.',
        "frames.cga",
    ).build(lot=(12.0, 8.0))
    assert model.metadata["reports"]["x"] == 0.0
    assert any("replaced by 0" in w for w in model.metadata["warnings"])
