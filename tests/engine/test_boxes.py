"""Boxes in closed form (shapegen.engine.shapes.boxes) against the general mesh path.

A comp face (a rectangle filling its scope) extruded either way, and ``comp(f)`` of the box it
makes, must give what the general path gives for the same rectangle given as a polygon mesh
(op_extrude's prism, its scope fitted to the points; each face's scope fitted to its corners):
the same scopes, meshes, face order, normals and first corners, to round-off. The face order of
an extruded rectangle is CityEngine's (tests/engine/test_geometry_shapes.py checks it on PyPRT's
output); a negative extrusion's faces are the same prism turned around.
"""

import numpy as np
import pytest

from shapegen.engine.operations.cga.topology import face_components, merged_shape
from shapegen.engine.shapes import boxes
from shapegen.engine.shapes.shape import FACE, MASS, Shape, extrude_shape, rotation_matrix
from shapegen.geometry.mesh import Mesh
from shapegen.model.scope import Scope

TOL = 1e-9


def _faces(seed: int):
    rng = np.random.default_rng(seed)
    for _ in range(40):
        rotation = rotation_matrix(rng.uniform(-180, 180, 3))
        origin = rng.uniform(-50, 50, 3)
        size = np.array([*rng.uniform(0.01, 20, 2), 0.0])
        height = float(rng.choice([-1, 1]) * rng.uniform(0.001, 15))
        yield Scope(origin, rotation, size), height


def _general(scope: Scope, height: float) -> Shape:
    """The mesh path: the same rectangle as a polygon (no closed form applies to it)."""
    face = Shape.with_geometry(scope, Mesh.rectangle(scope.size, 2), FACE, 2)
    return extrude_shape(face, height, True)


def _same_scope(a: Scope, b: Scope):
    assert np.abs(a.origin - b.origin).max() < TOL
    assert np.abs(a.rotation - b.rotation).max() < TOL
    assert np.abs(a.size - b.size).max() < TOL


@pytest.mark.parametrize("seed", [0, 1])
def test_an_extruded_rectangle_is_the_general_paths_box(seed):
    for scope, height in _faces(seed):
        fast = extrude_shape(Shape(scope, FACE, 2), height, True)
        slow = _general(scope, height)
        _same_scope(fast.scope, slow.scope)
        assert fast.kind == slow.kind == MASS
        if height > 0:  # both the box filling its scope
            assert fast.geometry is None and slow.geometry is None
        else:  # both the prism turned around; the closed form's is marked
            assert boxes.box_faces_of(fast) is boxes.BACKWARD
            assert boxes.box_faces_of(slow) is None
            assert fast.geometry.faces == slow.geometry.faces
            assert np.abs(fast.geometry.vertices - slow.geometry.vertices).max() < TOL


def _unmarked(shape: Shape) -> Shape:
    """The same box as a plain mesh: comp(f) then fits each face's scope to its corners (a
    backward one still marked so: its top is the face moved back, on either path)."""
    mesh = shape.mesh()
    plain = Mesh(mesh.vertices, mesh.faces)
    if boxes.extruded_backwards(shape):
        boxes.mark_extruded_backwards(plain)
    return Shape.with_geometry(shape.scope, plain, MASS)


@pytest.mark.parametrize("seed", [2, 3])
def test_comp_of_a_box_is_the_general_paths(seed):
    for scope, height in _faces(seed):
        box = extrude_shape(Shape(scope, FACE, 2), height, True)
        turned = rotation_matrix([0, 30, 0])
        fast = face_components(box, turned)
        slow = face_components(_unmarked(box), turned)
        assert len(fast) == len(slow) == 6
        for a, b in zip(fast, slow, strict=True):
            assert a.index == b.index and a.mesh_faces == b.mesh_faces
            assert a.border == b.border
            for name in ("normal", "world", "object", "first"):
                assert np.abs(getattr(a, name) - getattr(b, name)).max() < TOL, name
            _same_scope(a.shape.scope, b.shape.scope)
            assert a.shape.geometry is None and b.shape.geometry is None
            assert a.shape.kind == b.shape.kind == FACE


def test_a_negative_extrusion_keeps_the_face_first_and_facing_out():
    # face 0 of the backward box is the original face, still facing where it faced (+y of the
    # new scope, the face's normal); face 1 the face moved back
    face = Shape(Scope(np.zeros(3), np.eye(3), np.array([2.0, 3.0, 0.0])), FACE, 2)
    box = extrude_shape(face, -0.5, True)
    components = face_components(box, None)
    assert np.allclose(components[0].world, [0, 0, 1])
    assert np.allclose(components[1].world, [0, 0, -1])
    assert np.allclose(box.scope.origin, [0, 3, -0.5])
    assert np.allclose(box.scope.size, [2, 0.5, 3])
    assert box.mesh().volume() == pytest.approx(3.0)


LOT = [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize(
    "face",
    ["", "shapeL(3, 3){shape: ", "offset(-1) comp(f){border: "],
    ids=["rectangle", "L", "border"],
)
def test_top_of_a_negative_extrusion_is_the_face_moved_back(tmp_path, face):
    # CityEngine's runtime scopes extrude(-d) with scope.sy = -d (PyPRT 1.12: extrude(-3) of a
    # lot gives sy -3, axes kept), so comp(f)'s top is the face moved back: envelope2002's
    # balcony slabs (a bottom face, extrude(-0.3), comp(f){top: greenery}) have their
    # greenery on the slab's upper face in PyPRT's model, and its trees grow from there
    import shapegen.prt as prt

    close = "}" if face else ""
    rule = tmp_path / "backward.cga"
    rule.write_text(
        "Lot --> extrude(2) alignScopeToAxes(y) comp(f){bottom: " + face + "extrude(-0.3) "
        'comp(f){top: report("top", scope.elevation) T | bottom: report("bottom", '
        "scope.elevation) B | side: S}" + close + "}\n"
    )
    (model,) = prt.ModelGenerator([prt.InitialShape(LOT)]).generate_model([{}], str(rule))
    report = model.get_report()
    assert report["top_min"] == pytest.approx(0.3) and report["top_max"] == pytest.approx(0.3)
    assert report["bottom_max"] == pytest.approx(0.0, abs=1e-12)


def test_degenerate_boxes_take_the_general_path():
    scope = Scope(np.zeros(3), np.eye(3), np.array([2.0, 0.0, 0.0]))
    assert boxes.extruded_rectangle(scope, -1.0) is None
    assert boxes.extruded_rectangle(Scope(np.zeros(3), np.eye(3), [2.0, 1.0, 0.0]), 0.0) is None
    mirrored = Scope(np.zeros(3), np.diag([1.0, 1.0, -1.0]), np.array([2.0, 1.0, 0.0]))
    assert boxes.extruded_rectangle(mirrored, 1.0) is None


@pytest.mark.parametrize("chosen", [[2, 3, 4, 5], [0], [3, 1], [1, 5, 0]])
def test_merged_faces_of_a_box_are_the_general_paths(chosen):
    for scope, height in _faces(4):
        box = extrude_shape(Shape(scope, FACE, 2), height, True)
        fast_components = face_components(box, None)
        slow_box = _unmarked(box)
        slow_components = face_components(slow_box, None)
        fast = merged_shape(box, [fast_components[k] for k in chosen])
        slow = merged_shape(slow_box, [slow_components[k] for k in chosen])
        _same_scope(fast.scope, slow.scope)
        assert fast.geometry.faces == slow.geometry.faces
        assert np.abs(fast.geometry.vertices - slow.geometry.vertices).max() < TOL


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_comp_of_a_rectangle_is_the_general_paths(axis):
    rng = np.random.default_rng(5 + axis)
    for _ in range(30):
        size = rng.uniform(0.01, 20, 3)
        size[axis] = 0.0
        scope = Scope(rng.uniform(-50, 50, 3), rotation_matrix(rng.uniform(-180, 180, 3)), size)
        face = Shape(scope, FACE, axis)
        plain = Shape.with_geometry(scope, Mesh.rectangle(size, axis), FACE, axis)
        assert boxes.box_faces_of(face) is boxes.RECTANGLES[axis]
        (fast,), (slow,) = face_components(face, None), face_components(plain, None)
        assert fast.border and slow.border
        for name in ("normal", "world", "object", "first"):
            assert np.abs(getattr(fast, name) - getattr(slow, name)).max() < TOL, name
        _same_scope(fast.shape.scope, slow.shape.scope)
        assert fast.shape.geometry is None and slow.shape.geometry is None
        merged_fast, merged_slow = merged_shape(face, [fast]), merged_shape(plain, [slow])
        _same_scope(merged_fast.scope, merged_slow.scope)
        assert np.abs(merged_fast.geometry.vertices - merged_slow.geometry.vertices).max() < TOL


def test_a_split_piece_keeps_its_parents_face_order():
    # a box whose mesh lists its sides from another one than the fast path's (an extruded
    # polygon: envelope2002's floors on the L lot, x = 6 first); PyPRT's comp(f) of a split
    # piece of it lists the sides in the parent's order, each begun at the same corner (the
    # vertical greenery of those floors is PyPRT's wall for wall only so)
    from shapegen.engine.shapes.shape import split_piece

    size = np.array([6.0, 12.2, 1.0])
    corners = np.array([[1, 0, 1], [1, 0, 0], [0, 0, 0], [0, 0, 1], [1, 1, 1], [1, 1, 0],
                        [0, 1, 0], [0, 1, 1]], dtype=float)  # fmt: skip
    faces = ((1, 0, 3, 2), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
    rotation = rotation_matrix([0, 180, 0])
    volume = Shape.with_geometry(Scope([12, 0.13, 3], rotation, size), Mesh(corners * size, faces))
    piece = split_piece(volume, 1, 4.7, 3.45)
    assert np.allclose(piece.scope.size, [6.0, 3.45, 1.0])
    assert np.allclose(piece.scope.origin, volume.scope.to_world(np.array([0.0, 4.7, 0.0])))
    whole, part = face_components(volume, None), face_components(piece, None)
    for a, b in zip(whole, part, strict=True):
        assert np.allclose(a.world, b.world)  # the same faces in the same order
        assert np.allclose(a.shape.scope.rotation, b.shape.scope.rotation)  # same first edges
    # the fast path's order starts the sides elsewhere: what the piece used to be
    fast = face_components(Shape(piece.scope, MASS), None)
    assert not np.allclose(fast[2].world, part[2].world)
