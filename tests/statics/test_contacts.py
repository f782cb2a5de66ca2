"""Contact interfaces, checked against closed-form overlap areas and normals."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics.contacts import candidate_pairs, find_interfaces
from shapegen.statics.interface import GROUND


def box(lo, hi, **kw) -> Block:
    return Block.box(lo, hi, **kw)


def rotation(axis, angle) -> np.ndarray:
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def assert_ccw_about_normal(interface):
    """Every turn of the polygon is counter-clockwise about the interface normal."""
    p = interface.vertices
    turns = np.cross(np.roll(p, -1, axis=0) - p, np.roll(p, -2, axis=0) - np.roll(p, -1, axis=0))
    assert np.all(turns @ interface.normal > 0)


def test_two_stacked_boxes_one_interface_from_lower_index_to_higher():
    model = Model([box((0, 0, 0), (1, 1, 2)), box((0, 1, 0), (1, 2, 2))], ground=None)
    (interface,) = find_interfaces(model)
    assert (interface.first, interface.second) == (0, 1)
    np.testing.assert_allclose(interface.normal, [0, 1, 0], atol=1e-12)
    assert interface.area == pytest.approx(2.0)
    np.testing.assert_allclose(interface.vertices[:, 1], 1.0)
    np.testing.assert_allclose(np.cross(interface.tangent1, interface.tangent2), interface.normal)
    assert_ccw_about_normal(interface)


def test_upper_block_first_gets_downward_normal():
    model = Model([box((0, 1, 0), (1, 2, 1)), box((0, 0, 0), (1, 1, 1))], ground=None)
    (interface,) = find_interfaces(model)
    assert (interface.first, interface.second) == (0, 1)
    np.testing.assert_allclose(interface.normal, [0, -1, 0], atol=1e-12)
    assert_ccw_about_normal(interface)


@pytest.mark.parametrize(
    "dx, dz, width, depth",
    [(0.0, 0.0, 2.0, 1.5), (0.5, 0.2, 1.3, 0.7), (-0.4, 1.0, 1.0, 1.0), (1.5, -0.3, 2.0, 0.5)],
)
def test_offset_boxes_overlap_is_the_rectangle_intersection(dx, dz, width, depth):
    lower = box((0, 0, 0), (2, 1, 1.5))
    upper = box((dx, 1, dz), (dx + width, 1.8, dz + depth))
    (interface,) = find_interfaces(Model([lower, upper], ground=None))
    overlap_x = min(2, dx + width) - max(0, dx)
    overlap_z = min(1.5, dz + depth) - max(0, dz)
    assert interface.area == pytest.approx(overlap_x * overlap_z, rel=1e-12)
    assert len(interface.vertices) == 4
    expected_centroid = [max(0, dx) + overlap_x / 2, 1.0, max(0, dz) + overlap_z / 2]
    np.testing.assert_allclose(interface.centroid, expected_centroid)


def test_side_by_side_boxes_touch_on_a_vertical_face():
    model = Model([box((0, 0, 0), (1, 2, 1)), box((1, 0.5, 0), (3, 1.5, 1))], ground=None)
    (interface,) = find_interfaces(model)
    np.testing.assert_allclose(interface.normal, [1, 0, 0], atol=1e-12)
    assert interface.area == pytest.approx(1.0)


@pytest.mark.parametrize("axis, angle", [((1, 0, 0), 0.3), ((1, 2, 3), 1.1), ((0, 0, 1), np.pi)])
def test_rotated_stack_keeps_area_and_turns_the_normal(axis, angle):
    r = rotation(axis, angle)
    blocks = [box((0, 0, 0), (2, 1, 1.5)), box((0.5, 1, 0.2), (1.8, 1.8, 0.9))]
    model = Model([b.transformed(r, np.array([3.0, 4.0, -2.0])) for b in blocks], ground=None)
    (interface,) = find_interfaces(model)
    assert interface.area == pytest.approx(1.3 * 0.7, rel=1e-9)
    np.testing.assert_allclose(interface.normal, r @ [0, 1, 0], atol=1e-9)
    assert_ccw_about_normal(interface)


@pytest.mark.parametrize("slope", [0.2, 1.0, -0.7])
def test_tilted_joint_area_and_normal(slope):
    base = [(x, 0.0, z) for x in (0, 1) for z in (0, 1)]
    joint = [(x, 1.0 + slope * x, z) for x in (0, 1) for z in (0, 1)]
    top = [(x, 3.0, z) for x in (0, 1) for z in (0, 1)]
    model = Model([Block.from_hull(base + joint), Block.from_hull(joint + top)], ground=None)
    (interface,) = find_interfaces(model)
    assert interface.area == pytest.approx(np.hypot(1.0, slope))
    np.testing.assert_allclose(interface.normal, np.array([-slope, 1, 0]) / np.hypot(1, slope))


def test_square_on_square_turned_45_degrees_is_a_regular_octagon():
    lower = box((-0.5, 0, -0.5), (0.5, 1, 0.5))
    upper = box((-0.5, 0, -0.5), (0.5, 1, 0.5)).transformed(
        rotation((0, 1, 0), np.pi / 4), np.array([0, 1.0, 0])
    )
    (interface,) = find_interfaces(Model([lower, upper], ground=None))
    assert len(interface.vertices) == 8
    assert interface.area == pytest.approx(2 * (np.sqrt(2) - 1))


def test_box_on_ground_has_its_footprint_as_contact():
    model = Model([box((1, 0, 2), (3, 1, 2.5))], ground=0.0)
    (interface,) = find_interfaces(model)
    assert (interface.first, interface.second) == (0, GROUND)
    np.testing.assert_allclose(interface.normal, [0, -1, 0])
    assert interface.area == pytest.approx(1.0)
    np.testing.assert_allclose(interface.vertices[:, 1], 0.0)
    assert_ccw_about_normal(interface)


@pytest.mark.parametrize("ground, expected", [(0.0, 1), (-0.1, 0), (None, 0), (0.5, 0)])
def test_ground_contact_only_on_the_ground_plane(ground, expected):
    assert len(find_interfaces(Model([box((0, 0, 0), (1, 1, 1))], ground=ground))) == expected


def test_fixed_block_is_second_and_fixed_pairs_are_skipped():
    model = Model(
        [
            box((0, -1, 0), (1, 0, 1), fixed=True),  # foundation, on nothing
            box((0, -2, 0), (1, -1, 1), fixed=True),  # under the foundation
            box((0, 0, 0), (1, 1, 1)),
        ],
        ground=-2.0,
    )
    (interface,) = find_interfaces(model)  # fixed-fixed and fixed-ground are not contacts
    assert (interface.first, interface.second) == (2, 0)
    np.testing.assert_allclose(interface.normal, [0, -1, 0])
    assert interface.area == pytest.approx(1.0)


def test_non_structural_blocks_are_ignored():
    model = Model(
        [
            box((0, 0, 0), (1, 1, 1)),
            box((0, 1, 0), (1, 2, 1), structural=False),
            box((0, 2, 0), (1, 3, 1)),
        ],
        ground=None,
    )
    assert find_interfaces(model) == []


@pytest.mark.parametrize(
    "upper",
    [
        ((1, 1, 0), (2, 2, 1)),  # shares only an edge with the lower box
        ((1, 1, 1), (2, 2, 2)),  # shares only a corner
        ((1.5, 1, 0), (2, 2, 1)),  # coplanar faces that do not overlap
        ((0, 1.1, 0), (1, 2, 1)),  # a gap between the faces
    ],
)
def test_no_contact_without_area(upper):
    model = Model([box((0, 0, 0), (1, 1, 1)), box(*upper)], ground=None)
    assert find_interfaces(model) == []


def test_coplanar_same_facing_faces_are_no_contact():
    # Both bottoms lie on y = 0 facing down; both left sides on x = 0 facing -x.
    model = Model([box((0, 0, 0), (1, 1, 1)), box((0, 0, 0.2), (0.5, 0.5, 0.8))], ground=None)
    assert find_interfaces(model) == []


def test_triangulated_faces_give_one_merged_contact():
    lower = box((0, 0, 0), (2, 1, 2))
    quads = lower.faces
    triangles = tuple(t for f in quads for t in ((f[0], f[1], f[2]), (f[0], f[2], f[3])))
    lower = Block(lower.vertices, triangles)
    upper = box((0.5, 1, 0.5), (3, 2, 3))
    (interface,) = find_interfaces(Model([lower, upper], ground=None))
    assert interface.area == pytest.approx(1.5 * 1.5)
    assert_ccw_about_normal(interface)


def tower() -> Model:
    r = rotation((0, 1, 0), 0.4)
    return Model(
        [
            box((0, 0, 0), (4, 1, 1)),
            box((0.5, 1, 0.2), (2, 2, 0.8)),
            box((2, 1, 0), (3.5, 2, 1)),
            box((-1, -1, -1), (1, 0, 1), fixed=True),
            box((0.25, 2, 0.25), (0.75, 2.5, 0.75)).transformed(r, np.array([1.0, 0, 0.2])),
        ],
        ground=0.0,
    )


@pytest.mark.parametrize("scale", [1e-2, 1e3])
def test_scaled_model_has_the_same_interfaces(scale):
    reference = find_interfaces(tower())
    model = tower()
    model.blocks = [b.transformed(np.eye(3) * scale, np.zeros(3)) for b in model.blocks]
    model.ground = 0.0
    scaled = find_interfaces(model)
    assert [(i.first, i.second) for i in scaled] == [(i.first, i.second) for i in reference]
    for a, b in zip(reference, scaled, strict=True):
        assert b.area == pytest.approx(a.area * scale**2, rel=1e-9)
        np.testing.assert_allclose(b.normal, a.normal, atol=1e-12)


def test_interfaces_are_sorted_by_first_then_second():
    keys = [(i.first, i.second) for i in find_interfaces(tower())]
    # 0 stands on the ground and on the fixed 3; 1 and 2 on 0, side by side; 4 on 1 only.
    assert keys == [(0, GROUND), (0, 1), (0, 2), (0, 3), (1, 2), (1, 4)]


interval = st.tuples(
    st.floats(-2, 2, allow_nan=False), st.floats(0.1, 2, allow_nan=False)
)  # (start, length)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(interval, interval), min_size=2, max_size=6))
def test_random_box_stacks_contact_area_is_the_exact_overlap(extents):
    blocks = [
        box((x, k, z), (x + lx, k + 1, z + lz), id=f"s{k}")
        for k, ((x, lx), (z, lz)) in enumerate(extents)
    ]
    expected = {}
    for k in range(len(blocks) - 1):
        (x0, lx0), (z0, lz0) = extents[k]
        (x1, lx1), (z1, lz1) = extents[k + 1]
        ox = min(x0 + lx0, x1 + lx1) - max(x0, x1)
        oz = min(z0 + lz0, z1 + lz1) - max(z0, z1)
        assume(abs(ox) > 1e-3 and abs(oz) > 1e-3)  # stay clear of the tolerance boundary
        # Edges closer than the contact tolerance are (rightly) merged: keep them equal or apart.
        for lower, upper in (((x0, x0 + lx0), (x1, x1 + lx1)), ((z0, z0 + lz0), (z1, z1 + lz1))):
            assume(all(a == b or abs(a - b) > 1e-3 for a in lower for b in upper))
        if ox > 0 and oz > 0:
            expected[(k, k + 1)] = ox * oz
    found = {(i.first, i.second): i.area for i in find_interfaces(Model(blocks, ground=None))}
    assert found.keys() == expected.keys()
    for key, area in expected.items():
        assert found[key] == pytest.approx(area, rel=1e-9)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_candidate_pairs_match_the_brute_force_box_overlaps(seed):
    rng = np.random.default_rng(seed)
    lower = rng.uniform(0, 10, size=(300, 3)) * [1, 1, 0.1]
    upper = lower + rng.uniform(0.1, 1.5, size=(300, 3))
    pairs = candidate_pairs(lower, upper, padding=0.05)
    overlap = np.all(
        (lower[:, None] <= upper[None] + 0.05) & (lower[None] <= upper[:, None] + 0.05), axis=2
    )
    expected = np.argwhere(np.triu(overlap, k=1))
    np.testing.assert_array_equal(pairs, expected)


def test_vertex_in_the_middle_of_an_edge_is_dropped_from_the_contact():
    cube = box((0, 0, 0), (2, 1, 1))
    vertices = np.vstack([cube.vertices, [[1.0, 0.0, 0.0]]])  # 8: midpoint of edge 0-1
    faces = list(cube.faces)
    faces[0] = (0, 8, 1, 2, 3)  # bottom
    faces[2] = (0, 4, 5, 1, 8)  # z = 0 side
    (interface,) = find_interfaces(Model([Block(vertices, tuple(faces))], ground=0.0))
    assert len(interface.vertices) == 4
    assert interface.area == pytest.approx(2.0)


def fine_arch(n: int, radius=1.0, thickness=0.1, depth=0.3) -> Model:
    angles = np.linspace(0.0, np.pi, n + 1)
    blocks = []
    for k in range(n):
        corners = [
            (r * np.cos(a), r * np.sin(a), z)
            for a in angles[k : k + 2]
            for r in (radius - thickness / 2, radius + thickness / 2)
            for z in (0.0, depth)
        ]
        blocks.append(Block.from_hull(corners))
    return Model(blocks, ground=0.0)


def test_every_radial_joint_of_a_fine_arch_is_found():
    n = 400
    interfaces = find_interfaces(fine_arch(n))
    joints = [i for i in interfaces if i.second != GROUND]
    assert [(i.first, i.second) for i in joints] == [(k, k + 1) for k in range(n - 1)]
    np.testing.assert_allclose([i.area for i in joints], 0.1 * 0.3, rtol=1e-9)
    angle = np.pi * np.arange(1, n) / n  # the joint k/k+1 lies on the radius at this angle
    tangent = np.stack([-np.sin(angle), np.cos(angle), np.zeros(n - 1)], axis=1)
    np.testing.assert_allclose([i.normal for i in joints], tangent, atol=1e-9)
    springers = [i for i in interfaces if i.second == GROUND]
    assert [i.first for i in springers] == [0, n - 1]


def test_facing_face_pairs_keep_every_exactly_touching_pair():
    from shapegen.model.packed import pack_blocks
    from shapegen.statics.face_pairs import facing_face_pairs

    model = fine_arch(60)
    model.blocks += tower().blocks
    tol = model.tolerances()
    pack = pack_blocks(model.blocks)
    f, g = np.triu_indices(len(pack.face_normal), k=1)
    n_f, n_g = pack.face_normal[f], pack.face_normal[g]
    opposite = np.einsum("ij,ij->i", n_f, n_g) < -tol.normal_cos
    on_f = np.abs(np.einsum("ij,ij->i", n_f, pack.face_center[g]) - pack.face_offset[f])
    on_g = np.abs(np.einsum("ij,ij->i", n_g, pack.face_center[f]) - pack.face_offset[g])
    # Faces that can overlap: centres closer than the sum of the faces' radii.
    radius = np.array(
        [
            np.linalg.norm(
                b.vertices[list(face)] - b.vertices[list(face)].mean(axis=0), axis=1
            ).max()
            for b in model.blocks
            for face in b.faces
        ]
    )
    distance = np.linalg.norm(pack.face_center[f] - pack.face_center[g], axis=1)
    near = distance <= radius[f] + radius[g]
    wanted = opposite & (on_f <= tol.planar) & (on_g <= tol.planar) & near
    assert wanted.sum() >= 59 + 5  # the arch's joints and the tower's contacts
    found = set(zip(*facing_face_pairs(pack, tol), strict=True))
    assert set(zip(f[wanted], g[wanted], strict=True)) <= found


def test_running_bond_wall_joint_areas():
    # Three courses of 4 bricks (l x h x d), the middle one offset by half a brick with half
    # bricks at its ends: 3 + 4 + 3 head joints, 2 bed joints over the whole length, one footing.
    length, height, depth = 0.24, 0.07, 0.115
    blocks = []
    for course in range(3):
        edges = np.arange(5) * length
        if course == 1:
            edges = np.concatenate([[0.0], (np.arange(4) + 0.5) * length, [4 * length]])
        for x0, x1 in zip(edges[:-1], edges[1:], strict=True):
            blocks.append(box((x0, course * height, 0), (x1, (course + 1) * height, depth)))
    interfaces = find_interfaces(Model(blocks, ground=0.0))
    vertical = [i for i in interfaces if abs(i.normal[1]) < 0.5]
    horizontal = [i for i in interfaces if abs(i.normal[1]) > 0.5 and i.second != GROUND]
    footing = [i for i in interfaces if i.second == GROUND]
    assert len(vertical) == 3 + 4 + 3
    assert sum(i.area for i in vertical) == pytest.approx(10 * height * depth)
    assert len(horizontal) == 2 * 8  # each middle-course piece bears on 1 (ends) or 2 bricks
    assert sum(i.area for i in horizontal) == pytest.approx(2 * 4 * length * depth)
    assert sum(i.area for i in footing) == pytest.approx(4 * length * depth)


@pytest.mark.parametrize(
    "faces, problem",
    [
        (((0, 1, 9), (0, 1, 2), (1, 2, 3), (0, 2, 3)), r"face \[0, 1, 9\]"),
        (((0, 1),), r"face \[0, 1\]"),
        (None, "finite"),
    ],
)
def test_malformed_block_is_a_geometry_error_naming_it(faces, problem):
    from shapegen.errors import GeometryError

    bad = box((0, 0, 0), (1, 1, 1), id="bad")
    if faces is None:
        bad.vertices[2, 1] = np.nan
    else:
        bad.faces = faces
    with pytest.raises(GeometryError, match=rf"block 'bad'.*{problem}"):
        find_interfaces(Model([box((2, 0, 0), (3, 1, 1)), bad]))


def test_contacts_found_in_bands_of_pairs_are_the_same(monkeypatch):
    # numbers fuzz seed 544607, input 1930: 300-sided cylinder caps among 400 000 candidate
    # face pairs padded to one array of 2.7 GiB; the pairs are now clipped in bands
    from statics_cases import running_bond_wall

    from shapegen.statics import contacts

    model = running_bond_wall(courses=4, per_course=5)
    whole = contacts.find_interfaces(model)
    monkeypatch.setattr(contacts, "_BAND_BYTES", 1)  # one pair a band
    banded = contacts.find_interfaces(model)
    assert len(banded) == len(whole) > 20
    for a, b in zip(whole, banded, strict=True):
        assert (a.first, a.second) == (b.first, b.second)
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.normal, b.normal)


def test_finding_contacts_stops_at_the_work_clock():
    from statics_cases import running_bond_wall

    from shapegen.errors import WorkLimitError
    from shapegen.limits import work_clock, work_limits
    from shapegen.statics.contacts import find_interfaces

    with work_limits(max_seconds=1e-9), work_clock("judging the model"):
        with pytest.raises(WorkLimitError, match="judging the model ran for more than"):
            find_interfaces(running_bond_wall(courses=2, per_course=2))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_near_pairs_are_the_brute_force_pairs_within_one_in_the_max_norm(seed):
    # points on a few shared values (as faces of a wall share normals and planes) and spread
    # ones, some exactly 1 apart along a coordinate (the window is closed)
    from shapegen.statics.face_pairs import near_pairs

    rng = np.random.default_rng(seed)
    a = np.round(rng.uniform(-6, 6, size=(400, 7)), 1)
    a[:200, 3:6] = rng.choice([-3.0, 0.0, 3.0], size=(200, 3))
    b = a[rng.permutation(400)] + rng.choice([0.0, 1.0, -1.0, 0.4], size=(400, 7))
    b[::3] = rng.uniform(-6, 6, size=(134, 7))
    got = set(zip(*(x.tolist() for x in near_pairs(a, b)), strict=True))
    distance = np.abs(a[:, None, :] - b[None, :, :]).max(axis=2)
    expected = set(zip(*(x.tolist() for x in np.nonzero(distance <= 1.0)), strict=True))
    assert len(expected) > 100
    assert got == expected


def test_near_pairs_in_bands_are_the_same(monkeypatch):
    from shapegen.statics import face_pairs

    rng = np.random.default_rng(5)
    a, b = rng.uniform(-3, 3, size=(300, 7)), rng.uniform(-3, 3, size=(300, 7))
    whole = set(zip(*(x.tolist() for x in face_pairs.near_pairs(a, b)), strict=True))
    monkeypatch.setattr(face_pairs, "_CANDIDATE_BAND", 7)
    banded = set(zip(*(x.tolist() for x in face_pairs.near_pairs(a, b)), strict=True))
    assert banded == whole and len(whole) > 10


def test_near_pairs_of_no_points_are_none():
    from shapegen.statics.face_pairs import near_pairs

    some = np.zeros((3, 7))
    for a, b in ((some, some[:0]), (some[:0], some)):
        found_a, found_b = near_pairs(a, b)
        assert len(found_a) == len(found_b) == 0
