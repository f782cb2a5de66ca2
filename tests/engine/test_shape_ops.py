"""Scope operations: extrude, split, comp face frames, t / r / s / center."""

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.engine.operations.cga.topology import face_components
from shapegen.engine.shapes.shape import (
    FACE_ORDER,
    center,
    extrude,
    face_scopes,
    lot_scope,
    lot_shape,
    resize,
    rotate,
    rotation_matrix,
    split_scope,
    translate,
)
from shapegen.model.scope import Scope

BOX = Scope(np.array([1.0, 2.0, 3.0]), np.eye(3), np.array([4.0, 5.0, 6.0]))


def box_corners(scope):
    unit = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], float)
    return scope.to_world(unit * scope.size)


def test_lot_is_flat_in_x_z_with_world_axes():
    lot = lot_scope(12, 3)
    assert np.allclose(lot.origin, 0)
    assert np.allclose(lot.rotation, np.eye(3))
    assert np.allclose(lot.size, [12, 0, 3])


@pytest.mark.parametrize("height", [2.5, -2.5])
def test_extrude_grows_along_the_face_normal(height):
    mass = extrude(lot_scope(12, 3), 1, height)
    lo, hi = box_corners(mass).min(axis=0), box_corners(mass).max(axis=0)
    assert np.allclose(lo, [0, min(0, height), 0])
    assert np.allclose(hi, [12, max(0, height), 3])


def test_split_scope_slices_along_the_scope_axis():
    turned = Scope(np.zeros(3), rotation_matrix([0, 90, 0]), np.array([4.0, 1.0, 1.0]))
    piece = split_scope(turned, 0, 1.0, 2.0)
    assert np.allclose(piece.size, [2, 1, 1])
    assert np.allclose(piece.origin, turned.rotation[:, 0] * 1.0)


# Expected outward normal (world) and the world direction of the face's x axis for BOX (world
# axes): x along the face's first edge as PyPRT gives it on an extruded 12 x 8 m lot (a side's
# bottom edge left to right seen from outside; the bottom's first edge runs along -x).
FACES = {
    "front": ([0, 0, 1], [1, 0, 0], (4, 5)),
    "right": ([1, 0, 0], [0, 0, -1], (6, 5)),
    "back": ([0, 0, -1], [-1, 0, 0], (4, 5)),
    "left": ([-1, 0, 0], [0, 0, 1], (6, 5)),
    "top": ([0, 1, 0], [1, 0, 0], (4, 6)),
    "bottom": ([0, -1, 0], [-1, 0, 0], (4, 6)),
}


@pytest.mark.parametrize("name", FACE_ORDER)
def test_comp_face_frames(name):
    faces = dict(face_scopes(BOX))
    face = faces[name]
    normal, x_axis, size = FACES[name]
    rotation = face.rotation
    assert np.allclose(rotation.T @ rotation, np.eye(3))
    assert np.linalg.det(rotation) == pytest.approx(1.0)  # right-handed
    assert np.allclose(rotation[:, 2], normal)  # z = outward normal
    assert np.allclose(rotation[:, 0], x_axis)
    assert np.allclose(face.size, [*size, 0])
    if name not in ("top", "bottom"):
        assert np.allclose(rotation[:, 1], [0, 1, 0])  # facades keep y up
    # The face rectangle lies on the box's face plane, inside the box.
    corners = box_corners(face)
    lo, hi = BOX.origin, BOX.origin + BOX.size
    assert np.all(corners >= lo - 1e-12) and np.all(corners <= hi + 1e-12)
    plane = np.where(np.asarray(normal) != 0)[0][0]
    expected = hi[plane] if sum(normal) > 0 else lo[plane]
    assert np.allclose(corners[:, plane], expected)


def test_comp_faces_of_a_rotated_box_turn_with_it():
    turn = rotation_matrix([0, 30, 0])
    box = Scope(np.zeros(3), turn, np.array([2.0, 1.0, 1.0]))
    for (name, face), (_, reference) in zip(face_scopes(box), face_scopes(BOX), strict=True):
        assert np.allclose(face.rotation, turn @ reference.rotation), name


def test_comp_f_of_the_lot_is_its_top():
    (face,) = face_components(lot_shape((4, 2))[0], None)
    assert np.allclose(face.shape.scope.rotation[:, 2], [0, 1, 0])
    assert np.allclose(face.shape.scope.size, [4, 2, 0])


@pytest.mark.parametrize(
    "branches, expected",
    [
        ("front : A | side : B | all : C", {"a": 0.0, "b": [0.0, 1.0, 2.0], "c": [0.0, 1.0]}),
        ("all : A | top : B", {"a": [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]}),
    ],
)
def test_comp_selectors_are_exclusive_left_to_right(branches, expected):
    # comp.index numbers the faces each branch receives: one front, the three other sides, and
    # bottom and top for `all`; nothing is left for a selector after `all`.
    grammar = parse_grammar(
        f"Lot --> extrude(5) comp(f) {{ {branches} }}\n"
        + "".join(f'{r} --> report("{r.lower()}", comp.index) X.\n' for r in "ABC"),
        "c.cga",
    )
    reports = grammar.build(lot=(4, 6)).metadata["reports"]
    assert reports == expected


def test_translate_moves_along_scope_axes():
    turned = Scope(np.zeros(3), rotation_matrix([0, 0, 90]), np.ones(3))
    moved = translate(turned, [1.0, 0.0, 0.0])
    assert np.allclose(moved.origin, [0, 1, 0])  # the scope's x axis points along world +y


@pytest.mark.parametrize(
    "angles, axis, expected",
    [
        ([90, 0, 0], 1, [0, 0, 1]),  # y -> z about x
        ([0, 90, 0], 2, [1, 0, 0]),  # z -> x about y
        ([0, 0, 90], 0, [0, 1, 0]),  # x -> y about z
    ],
)
def test_rotation_about_each_axis_is_right_handed(angles, axis, expected):
    turned = rotate(BOX, angles)
    assert np.allclose(turned.rotation[:, axis], expected)
    assert np.allclose(turned.origin, BOX.origin)  # about the scope origin


def test_rotation_order_is_x_then_y_then_z():
    # Turning about x by 90 then about (fixed) y by 90: the scope's y axis goes to z, then to x.
    turned = rotate(Scope.axis_aligned(), [90, 90, 0])
    assert np.allclose(turned.rotation[:, 1], [1, 0, 0])


def test_rotation_about_the_centre_keeps_the_centre():
    turned = rotate(BOX, [0, 37, 0], about_center=True)
    assert np.allclose(turned.to_world(turned.size / 2), BOX.to_world(BOX.size / 2))


def test_resize_keeps_origin_and_refuses_negative_sizes():
    smaller = resize(BOX, [1, 2, 3])
    assert np.allclose(smaller.origin, BOX.origin) and np.allclose(smaller.size, [1, 2, 3])
    with pytest.raises(ValueError):
        resize(BOX, [1, -2, 3])


@pytest.mark.parametrize("axes", ["x", "xz", "xyz"])
def test_center_aligns_centres_on_the_chosen_axes(axes):
    small = Scope(BOX.origin, BOX.rotation, np.array([1.0, 1.0, 1.0]))
    centred = center(small, BOX, axes)
    c_small = centred.to_world(centred.size / 2)
    c_box = BOX.to_world(BOX.size / 2)
    for k, name in enumerate("xyz"):
        if name in axes:
            assert c_small[k] == pytest.approx(c_box[k])
        else:
            assert centred.origin[k] == pytest.approx(BOX.origin[k])
