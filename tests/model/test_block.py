"""Block geometry against closed forms: exact volume and centroid, convexity, hull faces."""

import numpy as np
import pytest
from rotations import about_y
from scipy.spatial import ConvexHull

from shapegen.errors import GeometryError
from shapegen.model import Block, Model


def _tetrahedron(a, b, c, d):
    return Block.from_hull(np.array([a, b, c, d], dtype=float))


@pytest.mark.parametrize(
    ("lo", "hi"),
    [
        ([0, 0, 0], [1, 2, 3]),
        ([-5, 1, 2], [-4.5, 1.1, 9]),
        ([1e3, 1e3, 1e3], [1e3 + 1, 1e3 + 1, 1e3 + 1]),
    ],
)
def test_box_volume_and_centroid_are_exact(lo, hi):
    block = Block.box(lo, hi)
    lo, hi = np.array(lo, float), np.array(hi, float)
    assert block.volume == pytest.approx(np.prod(hi - lo), rel=1e-12)
    np.testing.assert_allclose(block.centroid, (lo + hi) / 2, rtol=1e-12)


def test_tetrahedron_centroid_is_vertex_mean():
    pts = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0], [0, 0, 4]], float)
    block = _tetrahedron(*pts)
    assert block.volume == pytest.approx(2 * 3 * 4 / 6)
    np.testing.assert_allclose(block.centroid, pts.mean(axis=0), atol=1e-12)


def test_hull_merges_coplanar_triangles_into_quads():
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    block = Block.from_hull(corners)
    assert len(block.faces) == 6
    assert all(len(face) == 4 for face in block.faces)
    # Outward: every face normal points away from the centre.
    centers = np.array([block.vertices[list(f)].mean(axis=0) for f in block.faces])
    assert np.all(np.einsum("ij,ij->i", block.face_normals, centers - block.centroid) > 0)


def test_triangular_prism_matches_closed_form():
    # Right triangle legs 3 and 4 in x-y, extruded 2 along z: volume 12, centroid (1, 4/3, 1).
    pts = [[0, 0, 0], [3, 0, 0], [0, 4, 0], [0, 0, 2], [3, 0, 2], [0, 4, 2]]
    block = Block.from_hull(pts)
    assert block.volume == pytest.approx(12.0)
    np.testing.assert_allclose(block.centroid, [1.0, 4.0 / 3.0, 1.0], atol=1e-12)


def test_rotation_keeps_volume_and_moves_centroid():
    block = Block.box([0, 0, 0], [1, 2, 3])
    rot = about_y(37.0)
    moved = block.transformed(rot, [1, 2, 3])
    assert moved.volume == pytest.approx(6.0)
    np.testing.assert_allclose(moved.centroid, rot @ block.centroid + [1, 2, 3], atol=1e-12)
    moved.validate()


def test_mirror_keeps_faces_outward():
    block = Block.box([0, 0, 0], [1, 1, 1]).transformed(np.diag([-1.0, 1, 1]), [0, 0, 0])
    assert block.volume == pytest.approx(1.0)
    block.validate()


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "flat"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "at least 4"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, float("nan")]], "finite"),
    ],
)
def test_degenerate_hulls_are_refused(points, message):
    with pytest.raises(GeometryError, match=message):
        Block.from_hull(points, id="bad")


def test_non_convex_block_is_refused():
    # An L-shaped prism given with explicit faces is not convex.
    block = Block.box([0, 0, 0], [1, 1, 1], id="dented")
    vertices = block.vertices.copy()
    vertices[6] = [0.4, 0.4, 0.4]  # push a corner inside
    dented = Block(vertices, block.faces, id="dented")
    with pytest.raises(GeometryError, match="dented"):
        dented.validate()


def test_model_refuses_duplicate_ids_and_bad_friction():
    a = Block.box([0, 0, 0], [1, 1, 1], id="a")
    b = Block.box([0, 1, 0], [1, 2, 1], id="a")
    with pytest.raises(GeometryError, match="two blocks are named 'a'"):
        Model([a, b]).validate()
    with pytest.raises(GeometryError, match="friction"):
        Model([a], friction=float("nan")).validate()


def test_model_total_weight_counts_free_structural_blocks():
    free = Block.box([0, 0, 0], [1, 1, 1], density=1000)
    support = Block.box([0, -1, 0], [1, 0, 1], density=1000, fixed=True)
    roof = Block.box([0, 1, 0], [1, 2, 1], density=1000, structural=False)
    model = Model([free, support, roof])
    assert model.total_weight == pytest.approx(9.81 * 1000)
    assert [b.id for b in model.blocks] == ["b0", "b1", "b2"]


@pytest.mark.parametrize("offset", [0.0, 1e3, 1e5])
def test_random_hulls_are_convex_far_from_the_origin(offset):
    # Round-off must not make a hull look non-convex, wherever the model sits.
    rng = np.random.default_rng(1)
    for _ in range(200):
        points = rng.random((8, 3)) + offset
        block = Block.from_hull(points, id="hull")
        block.validate()
        assert block.volume == pytest.approx(ConvexHull(points).volume, rel=1e-9)


@pytest.mark.parametrize("offset", [1e6, 1e10])
def test_a_unit_cube_far_from_the_origin_is_valid_and_stands(offset):
    """Face normals are taken about each face's centre: far from the origin the cross products
    of raw coordinates would cancel (a cube at x = 1e10 was once rejected as non-convex)."""
    from shapegen.statics import analyze

    cube = Block.box((offset, 0, 0), (offset + 1, 1, 1))
    cube.validate()
    expected = Block.box((0, 0, 0), (1, 1, 1)).face_normals
    np.testing.assert_allclose(cube.face_normals, expected, atol=1e-12)
    assert analyze(Model([cube])).feasible


def test_mass_properties_in_bulk_equal_one_at_a_time():
    from shapegen.model.block import compute_mass_properties

    rng = np.random.default_rng(3)
    boxes = [Block.box(rng.uniform(-5, 5, 3), rng.uniform(-5, 5, 3) + 6) for _ in range(20)]
    hulls = [Block.from_hull(rng.normal(size=(12, 3)) + k) for k in range(5)]
    tilted = [b.transformed(np.eye(3)[[1, 2, 0]], np.array([1.0, 2.0, 3.0])) for b in boxes[:4]]
    bulk = boxes + hulls + tilted
    alone = [Block(b.vertices.copy(), b.faces) for b in bulk]
    compute_mass_properties(bulk)
    assert all("_mass_properties" in b.__dict__ for b in boxes)  # done in bulk, not on reading
    for a, b in zip(bulk, alone, strict=True):
        assert a.volume == pytest.approx(b.volume, rel=1e-14)
        assert np.allclose(a.centroid, b.centroid, rtol=0, atol=1e-12)
    # the closed forms: a box's volume and centre
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([2.0, 3.0, 4.0])
    box, other = Block.box(lo, hi), Block.box(lo + 1, hi + 1)
    compute_mass_properties([box, other])
    assert box.volume == pytest.approx(24.0) and np.allclose(box.centroid, [1.0, 1.5, 2.0])
