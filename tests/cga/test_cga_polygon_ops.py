"""The CGA polygon and roof operations on shapes: geometry, scopes and branches as CityEngine
makes them (areas and heights in closed form; the roofs' layout as PyPRT builds it)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from operation_nodes import SIMPLE_RULE_DATASET, lot_state, operation, operations_program

import shapegen
from shapegen.engine.operations.registry import compiler_for
from shapegen.engine.shapes.shape import FACE, MASS, Shape, lot_scope
from shapegen.errors import GrammarError
from shapegen.geometry.queries import border_faces
from shapegen.grammar import ast


@pytest.fixture(scope="module")
def program():
    return operations_program()


def _state(program, width=12.0, depth=8.0):
    return lot_state(program, width, depth)


_operation = operation


def run(program, operation, state=None):
    """Run one operation; returns the state and the leaves its branches made."""
    state = state or _state(program)
    out: list = []
    assert compiler_for(operation.name)(program, operation, {})(state, (), out) is True
    return state, [leaf for leaf, _, _ in out]


def _area(shape: Shape) -> float:
    return shape.mesh().area()


def _world(shape: Shape) -> np.ndarray:
    return shape.scope.to_world(shape.mesh().vertices)


# ---------------------------------------------------------------------------------- offset
def test_offset_inside_shrinks_the_lot_and_fits_the_scope(program):
    state, _ = run(program, _operation("offset", -1, "inside"))
    shape = state.shape
    assert shape.kind == FACE and shape.normal_axis == 1
    assert _area(shape) == pytest.approx(10 * 6)
    np.testing.assert_allclose(shape.scope.size, [10, 0, 6], atol=1e-12)
    np.testing.assert_allclose(shape.scope.origin, [1, 0, 1], atol=1e-12)


def test_offset_keeps_inside_and_border_faces_told_apart_by_adjacency(program):
    state, _ = run(program, _operation("offset", -1))
    mesh = state.shape.mesh()
    assert border_faces(mesh) == [False] + [True] * 4  # what comp(f) { inside | border } reads
    assert mesh.area() == pytest.approx(96)
    assert mesh.face_area(0) == pytest.approx(60)
    normals = mesh.face_normals()
    assert np.allclose(normals @ [0, 1, 0], 1)  # every face still faces up, as the lot


def test_offset_border_only_and_outward(program):
    state, _ = run(program, _operation("offset", -1, "border"))
    assert _area(state.shape) == pytest.approx(96 - 60)
    state, _ = run(program, _operation("offset", 2, "inside"))
    assert _area(state.shape) == pytest.approx(16 * 12)
    np.testing.assert_allclose(state.shape.scope.origin, [-2, 0, -2], atol=1e-12)


def test_offset_past_the_middle_is_ignored_with_a_warning(program):
    # CityEngine's runtime: "offset(): no face selected, ignoring operation"
    state = _state(program)
    before = state.shape
    op = compiler_for("offset")(program, _operation("offset", -5, "inside"), {})
    assert op(state, (), []) is True
    assert state.shape is before
    assert any("left no face" in w for w in state.run.warnings)


# --------------------------------------------------------------------------------- setback
def test_setback_front_strip_and_remainder(program):
    operation = _operation("setback", 2, branches=[("front", False), ("remainder", False)])
    _, leaves = run(program, operation)
    front, remainder = (leaf.shape for leaf in leaves)
    assert _area(front) == pytest.approx(12 * 2)
    assert _area(remainder) == pytest.approx(12 * 6)
    # front is the lot's first edge, at z = depth (scope +z, CityEngine's street side)
    assert _world(front)[:, 2].min() == pytest.approx(6)
    assert _world(remainder)[:, 2].max() == pytest.approx(6)


def test_setback_all_is_one_ring_with_a_hole(program):
    # CityEngine's runtime joins the strips of a branch that meet: all four edges are one
    # face with a hole, with ":" as with "=" (tests/data/prt_setback.json)
    for merge in (False, True):
        _, leaves = run(program, _operation("setback", 1, branches=[("all", merge)]))
        assert len(leaves) == 1
        mesh = leaves[0].shape.mesh()
        assert (mesh.n_faces, mesh.n_holes) == (1, 1)
        assert _area(leaves[0].shape) == pytest.approx(96 - 60)


def test_setback_by_edge_index_and_side(program):
    _, leaves = run(program, _operation("setback", 3, branches=[(1, False)]))
    assert _area(leaves[0].shape) == pytest.approx(3 * 8)
    _, leaves = run(program, _operation("setback", 3, branches=[("left", True)]))
    assert _area(leaves[0].shape) == pytest.approx(3 * 8)
    # side is comp's: every edge whose normal is not vertical, so all of a lot's
    _, leaves = run(program, _operation("setback", 1, branches=[("side", True)]))
    assert _area(leaves[0].shape) == pytest.approx(96 - 60)
    # world.* by the world directions: the lot's +z edge faces south
    _, leaves = run(program, _operation("setback", 2, branches=[("world.south", False)]))
    assert _world(leaves[0].shape)[:, 2].min() == pytest.approx(6)


def test_setback_to_area(program):
    operation = _operation("setbackToArea", 24, branches=[("all", False), ("remainder", False)])
    _, leaves = run(program, operation)
    assert _area(leaves[-1].shape) == pytest.approx(24)


@pytest.mark.parametrize(
    "name, widths, area",
    [
        ("shapeL", (2, 3), 96 - 9 * 6),
        ("shapeU", (2, 3, 3), 96 - 6 * 6),
        ("shapeO", (2, 1, 2, 1), 96 - 10 * 4),
    ],
)
def test_shape_l_u_o(program, name, widths, area):
    operation = _operation(name, *widths, branches=[("shape", False), ("remainder", False)])
    _, leaves = run(program, operation)
    assert len(leaves) == 2
    assert _area(leaves[0].shape) == pytest.approx(area)
    assert _area(leaves[0].shape) + _area(leaves[1].shape) == pytest.approx(96)


def test_inner_rectangle(program):
    operation = _operation("innerRectangle", "scope", branches=[("shape", False)])
    _, leaves = run(program, operation)
    assert _area(leaves[0].shape) == pytest.approx(96)


@pytest.mark.parametrize(
    "operation, message",
    [
        (_operation("offset", -1, "outside"), "all, inside or border"),
        (_operation("setback", 1, branches=[("uv.left", False)]), "no selector uv.left"),
        (_operation("shapeL", 1), "takes 2 arguments"),
        (_operation("innerRectangle", "diagonal"), "scope or edge"),
    ],
)
def test_bad_calls_are_one_clear_error(program, operation, message):
    with pytest.raises(GrammarError, match=message):
        run(program, operation)


def test_polygon_operations_need_a_flat_shape_but_offset_takes_a_mass(program):
    state = _state(program)
    state.shape = Shape(state.shape.scope.__class__.axis_aligned(size=(12, 3, 8)), MASS)
    with pytest.raises(GrammarError, match="needs a flat shape"):
        run(program, _operation("setback", 1, branches=[("all", False)]), state)
    # offset works on every face of a 3D shape, each in its own plane (op_offset)
    state, _ = run(program, _operation("offset", -0.5, "inside"), state)
    assert state.shape.kind == MASS
    mesh = state.shape.mesh()
    assert mesh.n_faces == 6 and not mesh.is_closed
    expected = 2 * (11 * 7 + 11 * 2 + 7 * 2)  # each face 1 m smaller in both directions
    assert mesh.area() == pytest.approx(expected)


# ----------------------------------------------------------------------------------- roofs
def test_hip_roof_on_the_lot_as_pyprt_builds_it(program):
    # PyPRT on a 12 x 8 m face at 45 degrees: ridge (4, 4, 4)-(8, 4, 4), one face per edge.
    state, _ = run(program, _operation("roofHip", 45))
    shape = state.shape
    assert shape.kind == MASS
    np.testing.assert_allclose(shape.scope.rotation, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(shape.scope.size, [12, 4, 8], atol=1e-12)
    world = _world(shape)
    ridge = world[np.isclose(world[:, 1], 4)]
    assert sorted(map(tuple, np.round(ridge, 9))) == [(4, 4, 4), (8, 4, 4)]
    mesh = shape.mesh()
    assert mesh.is_closed and mesh.is_convex()
    assert mesh.volume() == pytest.approx(4 * 8 * (3 * 12 - 8) / 6)
    assert np.sign(mesh.face_normals()[:, 1]).tolist() == [-1] + [1] * 4  # bottom, then slopes


def test_gable_roof_on_the_lot(program):
    # PyPRT: ridge along the 12 m side at height 4, vertical gables on the 8 m sides.
    state, _ = run(program, _operation("roofGable", 45))
    world = _world(state.shape)
    ridge = world[np.isclose(world[:, 1], 4)]
    assert sorted(map(tuple, np.round(ridge, 9))) == [(0, 4, 4), (12, 4, 4)]
    assert state.shape.mesh().volume() == pytest.approx(12 * 8**2 / 4)
    assert np.isclose(state.shape.mesh().face_normals()[:, 1], 0).sum() == 2  # the gables
    # with index 0 the lot's first edge (12 m, along x) is a gable: the ridge runs along z
    state, _ = run(program, _operation("roofGable", 45, 0, 0, False, 0))
    world = _world(state.shape)
    ridge = world[np.isclose(world[:, 1], 6)]
    assert sorted(map(tuple, np.round(ridge, 9))) == [(6, 6, 0), (6, 6, 8)]


def test_roof_ridge_runs_along_the_scope_x(program):
    state, _ = run(program, _operation("roofRidge", "byAngle", 45))
    world = _world(state.shape)
    ridge = world[np.isclose(world[:, 1], 4)]
    assert sorted(map(tuple, np.round(ridge, 9))) == [(0, 4, 4), (12, 4, 4)]


def test_shed_pyramid_by_height_and_taper(program):
    t = math.tan(math.radians(15))
    state, _ = run(program, _operation("roofShed", 15))
    world = _world(state.shape)
    # rises from the lot's first edge (z = 8) towards z = 0
    assert world[np.isclose(world[:, 2], 0), 1].max() == pytest.approx(8 * t)
    assert world[np.isclose(world[:, 2], 8), 1].max() == pytest.approx(0)
    state, _ = run(program, _operation("roofPyramid", "byHeight", 3))
    assert state.shape.scope.sy == pytest.approx(3)
    assert state.shape.mesh().volume() == pytest.approx(96)
    state, _ = run(program, _operation("roofHip", "byHeight", 2))
    assert state.shape.scope.sy == pytest.approx(2)
    state, _ = run(program, _operation("taper", 5))
    assert state.shape.mesh().volume() == pytest.approx(96 * 5 / 3)
    assert state.shape.mesh().face_normals()[0] @ [0, 1, 0] == pytest.approx(-1)  # its bottom


def test_roof_on_an_offset_face_and_on_a_comp_face(program):
    state, _ = run(program, _operation("offset", -1, "inside"))
    state, _ = run(program, _operation("roofHip", 45), state)
    world = _world(state.shape)
    assert world[:, 1].max() == pytest.approx(3)
    assert world[:, 0].min() == pytest.approx(1)
    # a vertical face (a comp face: flat along its z): the roof grows along the face normal
    from shapegen.engine.shapes.shape import face_scopes

    front = dict(face_scopes(lot_scope(12, 8).__class__.axis_aligned(size=(12, 6, 8))))["front"]
    state = _state(program)
    state.shape = Shape(front, FACE, 2)
    state, _ = run(program, _operation("roofGable", 45), state)
    np.testing.assert_allclose(state.shape.scope.rotation[:, 1], [0, 0, 1], atol=1e-12)
    assert _world(state.shape)[:, 2].max() == pytest.approx(8 + 3)


@pytest.mark.parametrize(
    "operation, message",
    [
        (_operation("roofHip", 95), "between -90 and 90"),
        (_operation("roofShed", 10, 1, 2), "up to: index"),
        (_operation("roofPyramid", 10, 1), "angle .* only"),
        (_operation("roofHip", 30, 1, 2), "even must be true or false"),
        (_operation("taper", ast.String("high")), r"taper\(\): the height must be a finite number"),
    ],
)
def test_bad_roof_calls_are_one_clear_error(program, operation, message):
    with pytest.raises(GrammarError, match=message):
        run(program, operation)


def test_offset_faces_share_their_edges_so_comp_finds_inside_and_border(program):
    from shapegen.geometry.queries import border_faces

    state, _ = run(program, _operation("offset", -1))
    mesh = state.shape.mesh()
    assert mesh.n_vertices == 8  # the inner and outer rectangles' corners, each once
    assert border_faces(mesh) == [False, True, True, True, True]


def test_envelope_on_the_lot(program):
    operation = _operation("envelope", "world.up", 10, 3, 45, 3, 45, 3, 45)
    state, _ = run(program, operation)
    assert state.shape.kind == MASS
    assert state.shape.scope.sy == pytest.approx(7)  # the slopes meet at 3 + 4 m
    assert state.shape.mesh().volume() == pytest.approx(96 * 3 + 4 * 8 * (3 * 12 - 8) / 6)
    with pytest.raises(GrammarError, match="4, 6, 8 or 10 arguments"):
        run(program, _operation("envelope", "normal", 10, 3))


def test_footprint_of_a_roof_is_its_plan(program):
    state, _ = run(program, _operation("roofHip", 30))
    state, _ = run(program, _operation("footprint"), state)
    shape = state.shape
    assert shape.kind == FACE and shape.normal_axis == 1
    assert shape.mesh().area() == pytest.approx(96)
    assert shape.scope.sy == 0
    assert np.allclose(shape.mesh().face_normals() @ [0, 1, 0], 1)


@pytest.mark.skipif(not SIMPLE_RULE_DATASET.exists(), reason="the CGA corpus test data is missing")
@pytest.mark.parametrize(
    "lot, rel, area",
    [
        ([(0, 0), (2, 9), (11, 9), (14, 0)], 10.0, 615.5955266677777),
        ([(0, 0), (0, 10), (4, 10), (4, 4), (10, 4), (10, 0)], 25.0, 269.99655000999996),
        ([(0, 0), (-2, 6), (5, 11), (13, 7), (12, -1)], 25.0, 474.68487521048553),
    ],
)
def test_corpus_setback_and_inner_rectangle_report_pyprts_footprint(lot, rel, area):
    """The corpus rule's setback(d) { front : NIL | remainder = ... } and innerRectangle(edge)
    on lots three times these sizes: the 'Footprint Area (m2)' PyPRT reports."""
    grammar = shapegen.load_grammar(SIMPLE_RULE_DATASET)
    model = grammar.build(attrs={"frontSetbackRel": rel}, lot=[(3 * x, 3 * z) for x, z in lot])
    assert model.metadata["reports"]["Footprint Area (m2)"] == pytest.approx(area, rel=2e-5)


def _built(text: str):
    """The model of the rule file ``text`` (CGA) on a 12 x 8 m lot."""
    return shapegen.parse_grammar(text, "rules.cga").build(lot=(12, 8))


def _surface_areas(model) -> list[float]:
    from shapegen.geometry.mesh import Mesh

    return [Mesh(s.vertices, s.faces).area() for s in model.surfaces]


@pytest.mark.parametrize(
    "body, lot, areas",
    [
        ("{ 20 : A | ~1 : A | '0.25 : A }", (12, 8), [20, 52, 24]),
        # a triangle (48 m²): the cuts are where the area below them reaches 20 and 36
        ("{ 20 : A | ~1 : A | '0.25 : A }", [(0, 0), (12, 0), (6, -8)], [20, 16, 12]),
        ("{ 10 : A }*", [(0, 0), (12, 0), (6, -8)], [10, 10, 10, 10, 8]),
    ],
)
def test_split_area(tmp_path, body, lot, areas):
    rule = tmp_path / "split_area.cga"
    rule.write_text(f"@StartRule\nLot --> splitArea(x) {body}\nA --> color(1, 0, 0)\n")
    model = shapegen.load_grammar(rule).build(lot=lot)
    assert _surface_areas(model) == pytest.approx(areas, rel=1e-6)  # cuts bisected


def test_split_area_refuses_an_unknown_adjust_mode(program):
    operation = ast.Operation(
        "splitArea",
        (
            ast.OperationArgument("plain", ast.Name("x")),
            ast.OperationArgument("plain", ast.Name("stretch")),
        ),
        (ast.OperationBranch(ast.Number(1.0), "absolute", ast.Sequence(())),),
    )
    with pytest.raises(GrammarError, match="adjust or noAdjust"):
        run(program, operation)


@pytest.mark.parametrize(
    "rule",
    [
        "Lot --> setback([2, 0, 0, 3]) { all = Strip | remainder : Rest }",
        # op_setbackPerEdge's example: the distance evaluated once per edge with comp.index
        "const dists = [2, 0, 0, 3]\ndist = dists[comp.index]\n@StartRule\n"
        "Lot --> setbackPerEdge(dist) { all = Strip | remainder : Rest }",
    ],
)
def test_setback_distances_per_edge_from_an_array(rule):
    text = rule if "@StartRule" in rule else "@StartRule\n" + rule
    model = _built(text + "\nStrip --> color(1, 0, 0)\nRest --> color(0, 1, 0)\n")
    # edge 0 (front, 12 m) by 2 m and edge 3 (left, 8 m) by 3 m: the rest is 9 x 6
    assert _surface_areas(model) == pytest.approx([96 - 54, 54])


def test_envelope_per_edge_arrays():
    model = _built(
        "@StartRule\nLot --> envelope(normal, 10, [3, 3, 3, 3], [45, 45, 45, 45]) Mass\n"
    )
    volume = sum(b.volume for b in model.blocks)
    assert volume == pytest.approx(96 * 3 + 4 * 8 * (3 * 12 - 8) / 6)


def test_envelope_classes_edges_in_the_object_axes():
    # op_envelope classes the edges by street.*, falling back to object.*: on a mass's top,
    # whose comp(f) scope has its y across the face, the sides are still front, back, left
    # and right, so all four slope as on the lot (candler's ventilators, as PyPRT builds them)
    model = _built(
        "@StartRule\nLot --> extrude(4) comp(f){ top: envelope(world.up, 10, 3, 45, 3, 45, "
        "3, 45) Mass }\n"
    )
    volume = sum(b.volume for b in model.blocks)
    assert volume == pytest.approx(96 * 3 + 4 * 8 * (3 * 12 - 8) / 6)
    top = max(float(np.max(np.asarray(b.vertices)[:, 1])) for b in model.blocks)
    assert top == pytest.approx(4 + 7)


def test_a_split_cap_begins_at_the_cut_of_the_first_face():
    # PyPRT's gambrel (Building_From_FootprintSMALL: roofGable(70, 0, 0, false, 0), split(y),
    # a gable on the cap): the cap of the cut roof begins at the cut of its first gable, so its
    # first edge runs along the 12 m edges (11.27 m at 1 m up a 70-degree roof), not across
    model = _built(
        "@StartRule\nLot --> roofGable(70, 0, 0, false, 0) split(y) { 1 : Lower }\n"
        'Lower --> comp(f) { top : report("cap", scope.sx) }\n'
    )
    assert model.metadata["reports"]["cap"] == pytest.approx(12 - 2 / math.tan(math.radians(70)))


def test_a_shed_roof_lists_its_roof_face_after_the_bottom():
    # the order PyPRT's saltbox implies: a split's cap begins at the cut of the shed's roof
    # face, so the roof face comes before the walls (the saltbox's gable then matches)
    model = _built(
        '@StartRule\nLot --> roofShed(30) comp(f) { 1 : report("area", geometry.area) }\n'
    )
    assert model.metadata["reports"]["area"] == pytest.approx(96 / math.cos(math.radians(30)))
