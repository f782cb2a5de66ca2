"""Rule inlining (op_inline) and the Boolean operations (op_boolOp), checked on the reference's
own examples where they give numbers (the cube's vertices appended and recomposed) and on boxes
whose union, difference and intersection follow from their coordinates."""

from __future__ import annotations

import math

import pytest

from shapegen import parse_grammar
from shapegen.errors import GrammarError
from shapegen.statics.standins import statics_model

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_inline_appends_or_recomposes_the_faces_of_a_cube": ("op:inline",),
    "test_boolean_operations_on_two_boxes": ("op:union", "op:subtract", "op:intersect"),
}


def _model(text: str, lot=(12.0, 8.0)):
    return parse_grammar("@StartRule\n" + text, "inline.cga").build(lot=lot)


def _reports(text: str, lot=(12.0, 8.0)) -> dict:
    return _model(text, lot).metadata["reports"]


@pytest.mark.parametrize(("strategy", "vertices"), [("", 24.0), ("(recompose)", 8.0)])
def test_inline_appends_or_recomposes_the_faces_of_a_cube(strategy, vertices):
    # op_inline's example: the six faces of a cube inlined are appended without sharing
    # vertices ("three times as many vertices as before"); recompose restores the topology
    reports = _reports(
        'Lot --> primitiveCube report("start", geometry.nVertices) '
        f'inline{strategy} comp(f) {{ all : Face. }} report("inline", geometry.nVertices) X.'
    )
    assert reports == {"start": 8.0, "inline": vertices}


def test_the_shape_after_inline_is_what_was_derived():
    # two 6 m pieces of a split appended: one shape of their twelve faces, a leaf of 288 m3
    model = _model(
        'Lot --> extrude(3) inline split(x) { 6 : A. }* report("f", geometry.nFaces) '
        'report("sx", scope.sx) X.'
    )
    assert model.metadata["reports"] == {"f": 12.0, "sx": 12.0}
    (leaf,) = model.surfaces  # one solid kept as derived, cut into convex parts when judged
    assert leaf.reason == "not convex" and not model.blocks
    assert math.isclose(sum(b.volume for b in statics_model(model).blocks), 288.0)


def test_one_inlined_shape_is_taken_as_it_is():
    reports = _reports(
        "attr h = 1\n"
        'Lot --> extrude(3) inline Half report("sx", scope.sx) report("h", h) X.\n'
        "Half --> s('0.5, '1, '1) set(h, 2) Done."
    )
    assert reports == {"sx": 6.0, "h": 2.0}


def test_unify_joins_the_pieces_into_one_solid():
    reports = _reports(
        'Lot --> extrude(3) inline(unify) split(x) { 6 : A. }* report("f", geometry.nFaces) '
        'report("v", geometry.volume) X.'
    )
    assert reports == {"f": 6.0, "v": 288.0}  # the cut between the pieces is gone


@pytest.mark.parametrize(
    ("operation", "b", "volume"),
    [
        ("union", "t(6, 0, 0)", 18 * 3 * 8),
        ("subtract", "t(6, 0, 0)", 6 * 3 * 8),
        ("intersect", "t(6, 1, 0)", 6 * 2 * 8),
        ("subtract", "t(20, 0, 0)", 12 * 3 * 8),  # B misses A: A stays
    ],
)
def test_boolean_operations_on_two_boxes(operation, b, volume):
    reports = _reports(
        f"Lot --> extrude(3) {operation} {{ A. | {b} B. }} "
        'report("v", geometry.volume) report("f", geometry.nFaces) X.'
    )
    assert math.isclose(reports["v"], volume, rel_tol=1e-6)
    assert reports["f"] == 6.0  # a box again: its coplanar triangles joined into faces


def test_a_boolean_of_closed_solids_is_closed_and_splits_into_closed_parts():
    # op_boolOp's mass-modelling example: a lot extruded 40 m intersected with a sphere; where a
    # face of the box meets the sphere's facets its corners are theirs, so that the solid stays
    # closed (no vertex of one face in the middle of another's edge) and a split caps its parts
    reports = _reports(
        "Lot --> extrude(40) intersect { A. | s('1, 40, '2) center(z) t(0, '-0.2, 0) "
        'primitiveSphere } report("closed", geometry.isClosedSurface) '
        'split(y) { ~1 : P | 20 : P }\nP --> report("part", geometry.isClosedSurface) X.'
    )
    assert reports == {"closed": True, "part": [True, True]}


def test_a_plane_through_a_solid_takes_what_lies_below_it_as_inside():
    # op_boolOp, "Behavior with open operands": "Everything below the plane is regarded as
    # 'inside'": the 12 x 4 x 8 m box less a 20 x 20 m quad at half its height is its upper half
    model = _model(
        "Lot --> extrude(4) subtract { A. | s(20, 0, 20) center(xz) t(0, 2, 0) primitiveQuad } "
        'report("v", geometry.volume) report("closed", geometry.isClosedSurface) '
        'report("y", scope.ty) X.'
    )
    assert model.metadata["reports"] == pytest.approx({"v": 192.0, "closed": True, "y": 2.0})
    assert model.metadata["warnings"] == []


def test_an_open_boundary_crossing_the_other_operand_is_a_warning():
    # op_boolOp's open cube (its left face removed) whose opening cuts the closed cube: the
    # reference defines no result there; shapegen derives its reading and says so
    model = _model(
        "Lot --> primitiveCube union { A. | t(2, 2, 2) comp(f) { left : NIL | all = B. } } "
        'report("f", geometry.nFaces) X.'
    )
    assert model.metadata["reports"]["f"] > 6
    (warning,) = model.metadata["warnings"]
    assert "the open boundary of an operand crosses the other operand" in warning


def test_operand_a_gives_the_attributes():
    # op_boolOp's example: "The first operand A determines the attributes of the resulting shape"
    reports = _reports(
        "attr H = 0\n"
        'Lot --> extrude(3) intersect { set(H, 10) A. | set(H, 1) t(2, 0, 0) B. } report("h", H) '
        "X."
    )
    assert reports["h"] == 10.0


def test_faces_in_one_plane_combine_in_2d():
    # two 12 x 8 lots 6 m and 4 m apart overlap on 6 x 4 m
    reports = _reports('Lot --> union { A. | t(6, 0, 4) B. } report("a", geometry.area) X.')
    assert math.isclose(reports["a"], 2 * 96 - 24)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("Lot --> extrude(3) inline(all) A", "merge strategy is one of append, unify"),
    ],
)
def test_what_shapegen_cannot_combine_is_one_line(text, message):
    with pytest.raises(GrammarError, match=message):
        _model(text)
