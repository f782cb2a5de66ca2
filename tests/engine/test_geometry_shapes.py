"""Shapes with geometry: polygon lots, extrude, split, comp and the leaves they make.

The face order and vertices of an extruded L-shaped lot are PyPRT's (CityEngine's runtime, run on
the corpus package extrusion_rule with this lot: see tools/cga_reference.py for the set-up).
"""

import numpy as np
import pytest

import shapegen
from shapegen.engine.shapes.shape import (
    FACE,
    MASS,
    Shape,
    extrude_shape,
    lot_shape,
    shape_geometry_value,
    split_piece,
)
from shapegen.errors import LotError
from shapegen.geometry.mesh import Mesh
from shapegen.statics.standins import CUT, statics_model

L_LOT = [(0, 0), (4, 0), (4, -2), (2, -2), (2, -4), (0, -4)]

# PyPRT: the L lot above extruded (its rule extrudes 15.46 m; the vertices' y is scaled to 1 here)
PYPRT_L_FACES = [
    ((0, -1, 0), [(4, 0, 0), (0, 0, 0), (0, 0, -4), (2, 0, -4), (2, 0, -2), (4, 0, -2)]),
    ((0, 1, 0), [(0, 1, 0), (4, 1, 0), (4, 1, -2), (2, 1, -2), (2, 1, -4), (0, 1, -4)]),
    ((0, 0, 1), [(0, 0, 0), (4, 0, 0), (4, 1, 0), (0, 1, 0)]),
    ((1, 0, 0), [(4, 0, 0), (4, 0, -2), (4, 1, -2), (4, 1, 0)]),
    ((0, 0, -1), [(4, 0, -2), (2, 0, -2), (2, 1, -2), (4, 1, -2)]),
    ((1, 0, 0), [(2, 0, -2), (2, 0, -4), (2, 1, -4), (2, 1, -2)]),
    ((0, 0, -1), [(2, 0, -4), (0, 0, -4), (0, 1, -4), (2, 1, -4)]),
    ((-1, 0, 0), [(0, 0, -4), (0, 0, 0), (0, 1, 0), (0, 1, -4)]),
]


def _state(shape):
    class Run:
        object_rotation = None

    class State:
        pass

    state = State()
    state.shape = shape
    state.run = Run()
    return state


def test_extruded_l_lot_matches_pyprt_face_by_face():
    start, metadata = lot_shape(L_LOT)
    assert metadata["lot_polygon"] == [[float(x), float(z)] for x, z in L_LOT]
    mass = extrude_shape(start, 1.0, cityengine_scope=True)
    world = mass.world_mesh()
    assert world.n_faces == len(PYPRT_L_FACES)
    for k, (normal, points) in enumerate(PYPRT_L_FACES):
        assert np.allclose(world.face_normal(k), normal), k
        assert np.allclose(world.face_points(k), points), k
    assert np.allclose(mass.scope.origin, [0, 0, -4]) and np.allclose(mass.scope.size, [4, 1, 4])
    assert world.volume() == pytest.approx(12.0)


def test_a_box_keeps_pyprts_face_order_on_the_fast_path():
    # PyPRT on the 12 x 8 m lot: bottom, top, then +z, +x, -z, -x (the lot's first edge on +z)
    model = shapegen.parse_grammar(
        "@StartRule\nLot --> extrude(2) comp(f) { 0 : A | 1 : B | 2 : C | 3 : D | 4 : E | 5 : F }\n"
    ).build(lot=(12, 8))
    normals = [s.vertices for s in model.surfaces]
    centre = np.array([6, 1, 4])
    expected = [(0, -1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 0), (0, 0, -1), (-1, 0, 0)]
    for vertices, direction in zip(normals, expected, strict=True):
        offset = vertices.mean(axis=0) - centre
        assert np.allclose(offset / np.linalg.norm(offset), direction)


def test_rectangle_polygon_lot_is_the_fast_path():
    rectangle, meta = lot_shape([(0, 3), (5, 3), (5, 0), (0, 0)])
    assert rectangle.geometry is None
    assert np.allclose(rectangle.scope.size, [5, 0, 3]) and meta["lot"] == [5.0, 3.0]
    grammar = shapegen.parse_grammar("@StartRule\nLot --> extrude(2) split(x) { ~1 : S }*\n")
    a = grammar.build(lot=(5, 3))
    b = grammar.build(lot=[(0, 3), (5, 3), (5, 0), (0, 0)])
    assert [bl.vertices.tolist() for bl in a.blocks] == [bl.vertices.tolist() for bl in b.blocks]


@pytest.mark.parametrize(
    "axis, start, size, volume",
    [(0, 0, 1, 4), (0, 1, 2, 6), (0, 2.5, 1.5, 3), (1, 0.25, 0.5, 6), (2, 0, 2, 4)],
)
def test_split_of_an_l_prism_has_the_closed_form_volume(axis, start, size, volume):
    start_shape, _ = lot_shape(L_LOT)
    mass = extrude_shape(start_shape, 1.0, True)
    piece = split_piece(mass, axis, start, size)
    mesh = piece.mesh()
    assert mesh.is_closed
    assert mesh.volume() == pytest.approx(volume)
    low, high = mesh.bounds()
    assert np.allclose(low, 0) and np.allclose(high, piece.scope.size)


def test_split_drops_pieces_without_geometry():
    # a U: its two arms (z < -1) have the gap 2 < x < 4 between them; the gap piece of a split
    # of the arms has no geometry and is dropped, and split.total counts the pieces made
    u_lot = [(0, 0), (6, 0), (6, -4), (4, -4), (4, -1), (2, -1), (2, -4), (0, -4)]
    grammar = shapegen.parse_grammar(
        "@StartRule\nLot --> extrude(1) split(z) { 3 : Arms | ~1 : NIL }\n"
        "Arms --> split(x) { 2 : A | 2 : Gap | ~1 : A }\n"
        'A --> report("total", split.total) Stone\nGap --> report("gap", 1)\n'
    )
    model = grammar.build(lot=u_lot)
    assert "gap" not in model.metadata["reports"]
    assert model.metadata["reports"]["total"] == [2.0, 2.0]
    assert [b.volume for b in model.blocks] == pytest.approx([6.0, 6.0])


def test_leaves_become_blocks_or_surfaces_with_a_reason():
    # the L prism stays as derived, one solid; the statics cut it into convex parts of one
    # body by the plane of one of its inner walls, with the leaf's own density
    grammar = shapegen.parse_grammar("attr density = 1000\n@StartRule\nLot --> extrude(2) Mass\n")
    model = grammar.build(lot=L_LOT)
    assert model.blocks == []
    (solid,) = model.surfaces
    assert solid.reason == "not convex" and solid.solid.density == 1000.0
    assert Mesh(solid.vertices, solid.faces).signed_volume() == pytest.approx(24.0)
    judged = statics_model(model)
    assert judged.stand_ins.by_reason == {CUT: 1}
    assert sorted(b.volume for b in judged.blocks) == pytest.approx([8.0, 16.0])
    assert sum(b.mass for b in judged.blocks) == pytest.approx(24.0 * 1000.0)
    assert len({b.body for b in judged.blocks}) == 1 and judged.blocks[0].body
    for block in judged.blocks:
        block.validate()
    # a lot never extruded is a surface
    model = shapegen.parse_grammar("@StartRule\nLot --> Flat\n").build(lot=L_LOT)
    assert [s.reason for s in model.surfaces] == ["a face (no volume)"]


def test_comp_merge_makes_one_shape_of_the_selected_faces():
    model = shapegen.parse_grammar(
        "@StartRule\nLot --> extrude(2) comp(f) { side = Walls | all : NIL }\n"
    ).build(lot=L_LOT)
    (walls,) = model.surfaces
    assert len(walls.faces) == 6
    area = sum(
        0.5
        * np.linalg.norm(np.cross(*(walls.vertices[list(f)][1:3] - walls.vertices[list(f)][0])))
        * 2
        for f in walls.faces
    )
    assert area == pytest.approx(2 * 16)  # perimeter 16 m, height 2 m


def test_bad_polygon_lots_are_one_line():
    grammar = shapegen.parse_grammar("@StartRule\nLot --> extrude(1) S\n")
    with pytest.raises(LotError, match=r"^the polygon has no area \(its corners are in a line\)$"):
        grammar.build(lot=[(0, 0), (1, 0), (2, 0)])
    with pytest.raises(LotError, match=r"^the polygon crosses itself \(self-intersection at"):
        grammar.build(lot=[(0, 0), (4, 0), (4, -4), (2, 2), (0, -4)])


def test_a_clockwise_lot_is_the_same_lot_counter_clockwise_from_its_first_corner():
    grammar = shapegen.parse_grammar("@StartRule\nLot --> extrude(1) S\n")
    clockwise = [L_LOT[0], *reversed(L_LOT[1:])]
    model = grammar.build(lot=clockwise)
    assert model.metadata["lot_polygon"] == grammar.build(lot=L_LOT).metadata["lot_polygon"]


def test_cityengine_extrude_of_a_comp_face_turns_the_scope(tmp_path):
    # op_extrude: y along the extrusion. In a .cga file split(y) of an extruded wall cuts its
    # thickness; a .grammar file keeps shapegen's scope (y up the wall), so it cuts its height.
    text = (
        "@StartRule\nLot --> extrude(3) comp(f) { front : Wall }\n"
        "Wall --> extrude(0.5) split(y) { 0.2 : A | ~1 : B }\n"
    )
    extents = {}
    for suffix in ("cga", "grammar"):
        path = tmp_path / f"wall.{suffix}"
        path.write_text(text)
        model = shapegen.load_grammar(str(path)).build(lot=(4, 2))
        first = model.blocks[0]
        extents[suffix] = (first.vertices.max(axis=0) - first.vertices.min(axis=0)).round(9)
        assert sum(b.volume for b in model.blocks) == pytest.approx(4 * 3 * 0.5)
    assert extents["cga"].tolist() == [4, 3, 0.2]
    assert extents["grammar"].tolist() == [4, 0.2, 0.5]
    face = Shape(shapegen.engine.shapes.shape.lot_scope(4, 3), FACE, 1)
    box = extrude_shape(face, 3, True)
    assert box.kind == MASS and box.geometry is None


def test_geometry_queries():
    start, _ = lot_shape(L_LOT)
    mass = extrude_shape(start, 2.0, True)
    state = _state(mass)
    assert shape_geometry_value(state, "volume") == pytest.approx(24.0)
    assert shape_geometry_value(state, "area") == pytest.approx(2 * 12 + 16 * 2)
    assert shape_geometry_value(state, "area", "top") == pytest.approx(12.0)
    assert shape_geometry_value(state, "area", "world.north") == pytest.approx(2 * 4)
    assert shape_geometry_value(state, "nVertices") == 12.0
    assert shape_geometry_value(state, "nFaces") == 8.0
    assert shape_geometry_value(state, "nEdges") == 18.0
    assert shape_geometry_value(state, "height") == pytest.approx(2.0)
    assert shape_geometry_value(state, "isClosedSurface") is True
    assert shape_geometry_value(state, "isConcave") is True
    assert shape_geometry_value(_state(start), "isRectangular", 0) is False
    assert shape_geometry_value(state, "angle", "maxSlope") == pytest.approx(90.0)
    with pytest.raises(ValueError, match="not supported"):
        shape_geometry_value(state, "nonsense")


def test_s_scales_the_geometry_with_the_scope():
    model = shapegen.parse_grammar("@StartRule\nLot --> extrude(1) s('0.5, '2, '1) Mass\n").build(
        lot=L_LOT
    )
    model = statics_model(model)  # the L solid's convex parts
    points = np.vstack([b.vertices for b in model.blocks])
    assert np.allclose(points.min(axis=0), [0, 0, -4]) and np.allclose(
        points.max(axis=0), [2, 2, 0]
    )
    assert sum(b.volume for b in model.blocks) == pytest.approx(12 * 0.5 * 2)


def test_extrude_world_up_of_a_wall_and_flat_top_of_a_slope():
    # a wall face (normal +z) extruded along world y sweeps no volume sideways: a 4 x 3 face
    # moved up 1 m gives a prism of zero volume, its scope y is world y
    start, _ = lot_shape((4, 2))
    box = extrude_shape(start, 3, True)
    from shapegen.engine.operations.cga.topology import face_components

    front = face_components(box, None)[2].shape
    up = extrude_shape(front, 1.0, True, "world.up")
    assert np.allclose(up.scope.rotation[:, 1], [0, 1, 0])
    assert up.mesh().volume() == pytest.approx(0.0, abs=1e-9)
    # a slope 4 m long rising 1 m along x: flatTop 2 m puts the top at 2 m above its low edge
    slope = Shape.with_geometry(
        start.scope,
        shapegen.geometry.mesh.Mesh.polygon([(0, 0, 2), (4, 1, 2), (4, 1, 0), (0, 0, 0)]),
        FACE,
        1,
    )
    flat = extrude_shape(slope, 2.0, True, "world.up.flatTop")
    world = flat.world_mesh()
    assert world.is_closed
    assert world.vertices[:, 1].max() == pytest.approx(2.0)
    # volume: the cross-section is a trapezoid, heights 2 and 1 over 4 m, times 2 m deep
    assert world.volume() == pytest.approx((2 + 1) / 2 * 4 * 2)


def test_a_mass_turned_inside_out_is_a_surface():
    model = shapegen.parse_grammar("@StartRule\nLot --> extrude(2) reverseNormals() M\n").build(
        lot=(3, 2)
    )
    assert model.blocks == []
    assert [s.reason for s in model.surfaces] == ["faces turned inwards"]
