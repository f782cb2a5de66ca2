"""CityEngine's scope operations (alignScopeToAxes, alignScopeToGeometry, rotateScope, mirror,
mirrorScope, setPivot, reverseNormals, cleanupGeometry, resetGeometry, trim, convexify) and comp
on meshes: the geometry stays where it is in the world, the scope is refitted as op_*.html says."""

from __future__ import annotations

import math

import numpy as np
import pytest
from operation_nodes import SIMPLE_RULE_DATASET, operation, operations_program, shape_state

import shapegen
from shapegen.engine.operations.cga.scope_ops import pivot_frame
from shapegen.engine.operations.registry import compiler_for
from shapegen.engine.shapes.shape import extrude_shape, lot_shape
from shapegen.errors import GrammarError

L_LOT = [(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)]


@pytest.fixture(scope="module")
def program():
    return operations_program()


_state = shape_state
_operation = operation


def run(program, operation, state):
    out: list = []
    assert compiler_for(operation.name)(program, operation, {})(state, (), out) is True
    return state, [leaf for leaf, _, _ in out]


def _l_mass(height=2.0):
    start, _ = lot_shape(L_LOT)
    return extrude_shape(start, height, True)


def _world(shape):
    return shape.world_mesh().vertices


def test_rotate_scope_keeps_the_geometry_and_fits_the_scope(program):
    box = extrude_shape(lot_shape((4, 2))[0], 3, True)
    state = _state(program, box)
    before = _world(state.shape)
    run(program, _operation("rotateScope", 0, 45, 0), state)
    assert np.allclose(_world(state.shape), before)
    # a 4 x 2 footprint turned 45 degrees: its extent along the new axes is (4 + 2) / sqrt 2
    side = 6 / math.sqrt(2)
    assert np.allclose(state.shape.scope.size, [side, 3, side])
    assert np.allclose(state.shape.scope.rotation[:, 1], [0, 1, 0])


def test_align_scope_to_axes_undoes_a_turn(program):
    mass = _l_mass()
    state = _state(program, mass)
    run(program, _operation("rotateScope", 0, 30, 0), state)
    run(program, _operation("alignScopeToAxes"), state)
    assert np.allclose(state.shape.scope.rotation, np.eye(3))
    assert np.allclose(state.shape.scope.size, [4, 2, 4])
    assert np.allclose(state.shape.scope.origin, [0, 0, -4])


def test_align_scope_to_axes_y_keeps_x_in_the_ground_plane(program):
    mass = _l_mass()
    state = _state(program, mass)
    run(program, _operation("rotateScope", 20, 30, 0), state)
    run(program, _operation("alignScopeToAxes", "y"), state)
    rotation = state.shape.scope.rotation
    assert np.allclose(rotation[:, 1], [0, 1, 0])
    assert abs(rotation[1, 0]) < 1e-12  # x projected to the xz-plane


def test_align_scope_to_geometry_on_the_longest_edge(program):
    # a lot whose longest edge is its third (5 m along -z... turned): the scope's x follows it
    lot = [(0, 0), (2, 0), (2, -5), (0, -5)]
    start, _ = lot_shape(lot)
    state = _state(program, extrude_shape(start, 1, True))
    run(program, _operation("alignScopeToGeometry", "yUp", "world.lowest", "longest"), state)
    rotation = state.shape.scope.rotation
    assert np.allclose(rotation[:, 1], [0, -1, 0]) or np.allclose(rotation[:, 1], [0, 1, 0])
    assert abs(abs(rotation[2, 0]) - 1) < 1e-12  # x along the 5 m edge (world z)
    assert np.allclose(sorted(state.shape.scope.size), [1, 2, 5])


def test_mirror_flips_the_geometry_inside_its_scope(program):
    state = _state(program, _l_mass())
    run(program, _operation("mirror", True, False, False), state)
    mesh = state.shape.world_mesh()
    assert mesh.volume() == pytest.approx(24.0) and mesh.is_closed
    # the L's notch (x > 2, z < -2) moves to x < 2
    centre = mesh.vertices.mean(axis=0)
    assert centre[0] > 2 - 1e-9
    normals = mesh.face_normals()
    centres = np.array([mesh.face_points(k).mean(axis=0) for k in range(mesh.n_faces)])
    assert normals[1] @ [0, 1, 0] > 0.99 and centres[1][1] == pytest.approx(2)


def test_mirror_scope_keeps_the_geometry(program):
    state = _state(program, _l_mass())
    before = _world(state.shape)
    run(program, _operation("mirrorScope", True, False, True), state)
    assert np.allclose(_world(state.shape), before)
    assert np.allclose(state.shape.scope.rotation[:, 0], [-1, 0, 0])
    assert state.shape.world_mesh().volume() == pytest.approx(24.0)


@pytest.mark.parametrize("corner", range(8))
def test_set_pivot_axes_point_inside_at_every_corner(corner):
    frame = pivot_frame(np.eye(3), "xyz", corner)
    assert np.linalg.det(frame) == pytest.approx(1.0)
    corner_point = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]][
            corner
        ],
        float,
    )
    for axis in frame.T:
        assert np.all((corner_point + 0.5 * axis >= 0) & (corner_point + 0.5 * axis <= 1))
    assert abs(frame[1, 1]) == 1.0  # y along or against the old y (op_setPivot's picture)


def test_set_pivot_moves_the_scope_to_the_corner(program):
    state = _state(program, extrude_shape(lot_shape((4, 2))[0], 3, True))
    run(program, _operation("setPivot", "xyz", 2), state)
    assert np.allclose(state.shape.scope.origin, [4, 0, 2])
    assert np.allclose(state.shape.scope.size, [4, 3, 2])


def test_reverse_normals_cleanup_and_reset(program):
    mass = _l_mass()
    state = _state(program, mass)
    run(program, _operation("reverseNormals"), state)
    assert np.allclose(state.shape.mesh().face_normals(), -mass.mesh().face_normals())
    run(program, _operation("cleanupGeometry", "all", 0), state)
    assert state.shape.mesh().n_vertices == 12
    run(program, _operation("resetGeometry"), state)
    assert state.shape is not mass and state.shape.geometry is mass.geometry
    run(program, _operation("trim"), state)


def test_convexify_cuts_an_l_face_into_convex_pieces(program):
    start, _ = lot_shape(L_LOT)
    state = _state(program, start)
    run(program, _operation("convexify"), state)
    mesh = state.shape.mesh()
    assert mesh.n_faces == 2
    assert all(mesh.face(k).is_convex() for k in range(mesh.n_faces))
    assert mesh.area() == pytest.approx(12.0)


def test_comp_generic_selectors_and_merge(program):
    state = _state(program, _l_mass())
    _, leaves = run(
        program,
        _operation(
            "comp", "f", branches=[("world.north", False), ("vertical", True), ("all", False)]
        ),
        state,
    )
    kinds = [leaf.comp_total for leaf in leaves]
    # two faces look north (-z), the other four walls merge into one shape, then top and bottom
    assert kinds == [2, 2, 1, 2, 2]
    north = leaves[0].shape
    assert np.allclose(north.scope.rotation[:, 2], [0, 0, -1])


def test_comp_edges_and_vertices(program):
    box = extrude_shape(lot_shape((4, 2))[0], 3, True)
    state = _state(program, box)
    _, edges = run(program, _operation("comp", "e", branches=[("all", False)]), state)
    assert len(edges) == 12
    assert sorted(round(e.shape.scope.sx, 9) for e in edges) == [2] * 4 + [3] * 4 + [4] * 4
    first = edges[0].shape.scope  # the first edge of the bottom face
    assert np.allclose(first.rotation[:, 2], np.array([0, -1, 1]) / math.sqrt(2))
    state = _state(program, box)
    _, vertices = run(program, _operation("comp", "v", branches=[("all", False)]), state)
    assert len(vertices) == 8 and all(v.shape.scope.size.max() == 0 for v in vertices)


def test_bad_scope_op_arguments_are_one_line(program):
    with pytest.raises(GrammarError, match="the axis map is one of"):
        compiler_for("setPivot")(program, _operation("setPivot", "xzy", 0), {})
    with pytest.raises(GrammarError, match="takes 3 arguments"):
        compiler_for("mirror")(program, _operation("mirror", True), {})
    state = _state(program, _l_mass())
    with pytest.raises(GrammarError, match="corner index is a whole number"):
        run(program, _operation("setPivot", "xyz", 9), state)


def test_comp_face_vertices(program):
    box = extrude_shape(lot_shape((4, 2))[0], 3, True)
    state = _state(program, box)
    _, corners = run(program, _operation("comp", "fv", branches=[("all", False)]), state)
    assert len(corners) == 24  # six faces of four corners
    first = corners[0].shape.scope  # the bottom's first corner: (4, 0, 2), edge along -x
    assert np.allclose(first.origin, [4, 0, 2])
    # x halfway between the edge coming in (+z) and the edge leaving (-x), as CityEngine's
    # runtime gives a corner (tests/data/prt_comp_holes.json)
    half = np.sqrt(0.5)
    assert np.allclose(first.rotation[:, 0], [-half, 0, half])
    assert np.allclose(first.rotation[:, 1], [0, -1, 0])  # the bottom's normal
    assert np.allclose(first.rotation[:, 2], [half, 0, half])  # out of the face, in its plane


def test_comp_records_its_selector_for_comp_sel(program):
    state = _state(program, extrude_shape(lot_shape((4, 2))[0], 3, True))
    _, faces = run(
        program,
        _operation("comp", "f", branches=[("front", False), ("side", False), (1, False)]),
        state,
    )
    assert [f.comp_sel for f in faces] == ["front", "side", "side", "side", "1"]
    assert [f.comp_index for f in faces] == [0, 0, 1, 2, 0]


@pytest.mark.skipif(not SIMPLE_RULE_DATASET.exists(), reason="the CGA corpus test data is missing")
@pytest.mark.parametrize(
    "lot, setback_x, setback_z, edges",
    # PyPRT on the corpus package simpleRuleDataset with these lots: the reports of its
    # alignScopeToGeometry(yUp, any, longest) scope (sx, sz) and comp(e)'s scope.sx (sum,
    # min, max of "Parcel Edges Length (m)")
    [
        ([(0, 0), (6, 27), (33, 27), (42, 0)], 42.0, 27.0, (125.11913231339409, 27.0, 42.0)),
        ([(0, 0), (0, 30), (12, 30), (12, 12), (30, 12), (30, 0)], 30.0, 30.0, (120, 12, 30)),
        ([(0, 0), (0, 8), (12, 8), (12, 0)], 12.0, 8.0, (40, 8, 12)),
        ([(0, 0), (-6, 18), (15, 33), (39, 21), (36, -3)], 44.59542268145836, 34.13169221988713,
         None),
    ],
)  # fmt: skip
def test_align_scope_to_geometry_and_comp_edges_report_pyprts_figures(
    lot, setback_x, setback_z, edges
):
    model = shapegen.load_grammar(SIMPLE_RULE_DATASET).build(lot=lot)
    reports = model.metadata["reports"]
    assert reports["Max Setback X (m)"] == pytest.approx(setback_x, rel=1e-12)
    assert reports["Max Setback Z (m)"] == pytest.approx(setback_z, rel=1e-12)
    if edges is not None:
        lengths = reports["Parcel Edges Length (m)"]
        assert (sum(lengths), min(lengths), max(lengths)) == pytest.approx(edges, rel=1e-12)


@pytest.mark.skipif(not SIMPLE_RULE_DATASET.exists(), reason="the CGA corpus test data is missing")
@pytest.mark.parametrize(
    "lot, high",
    # PyPRT: the same L lot from three corners; its two 10 m edges tie for 'longest' and the
    # rule's innerRectangle then keeps the arm along the edge alignScopeToGeometry chose
    [
        ([(0, 0), (0, 10), (4, 10), (4, 4), (10, 4), (10, 0)], [4, 10]),
        ([(0, 10), (4, 10), (4, 4), (10, 4), (10, 0), (0, 0)], [10, 4]),
        ([(4, 4), (10, 4), (10, 0), (0, 0), (0, 10), (4, 10)], [10, 4]),
    ],
)
def test_align_scope_to_geometry_breaks_ties_as_pyprt(lot, high):
    model = shapegen.load_grammar(SIMPLE_RULE_DATASET).build(lot=lot)
    (surface,) = model.surfaces
    assert np.allclose(surface.vertices.min(axis=0)[[0, 2]], [0, 0])
    assert np.allclose(surface.vertices.max(axis=0)[[0, 2]], high)
