"""Reading and writing block models as JSON and meshes (OBJ, glTF, PLY, STL)."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import ConvexHull

from shapegen import Block, GeometryError, InputFormatError, Model
from shapegen.export.meshes import block_triangles, encode_obj
from shapegen.export.model_io import write_model
from shapegen.readers.models import read_model

ROCK_POINTS = np.random.default_rng(7).normal(size=(40, 3)) + [6.0, 3.0, 0.0]


def stack_model() -> Model:
    """Three touching boxes of known sizes, a tetrahedron and a random hull (a fixed support)."""
    blocks = [
        Block.box([0, 0, 0], [2, 1, 1], id="base", tags=("plinth",)),
        Block.box([0, 1, 0], [1, 3, 1], id="column", tags=("column", "stone")),
        Block.box([0, 3, 0], [1.5, 3.5, 0.5], id="cap", density=1800.0, rule_path=("A", "B")),
        Block.from_hull([[4, 0, 0], [5, 0, 0], [4, 1, 0], [4, 0, 1]], id="tet", structural=False),
        Block.from_hull(ROCK_POINTS, id="rock", fixed=True),
    ]
    return Model(blocks)


# Closed-form volumes (m^3): boxes are products of their sides, the tetrahedron 1/6.
EXPECTED_VOLUMES = sorted([2.0, 2.0, 0.375, 1 / 6, ConvexHull(ROCK_POINTS).volume])


def test_json_round_trip_is_exact(tmp_path):
    model = stack_model()
    path = tmp_path / "model.json"
    write_model(model, path)
    back = read_model(path)
    assert [b.id for b in back.blocks] == [b.id for b in model.blocks]
    for a, b in zip(model.blocks, back.blocks, strict=True):
        np.testing.assert_array_equal(a.vertices, b.vertices)
        assert a.faces == b.faces
        assert (a.tags, a.density, a.fixed, a.structural, a.rule_path) == (
            b.tags,
            b.density,
            b.fixed,
            b.structural,
            b.rule_path,
        )


@pytest.mark.parametrize("suffix", [".glb", ".gltf", ".obj", ".ply"])
def test_mesh_round_trip_keeps_blocks_and_volumes(tmp_path, suffix):
    path = tmp_path / f"model{suffix}"
    write_model(stack_model(), path)
    back = read_model(path)
    assert len(back.blocks) == 5
    # glTF stores float32 coordinates: volumes agree to about 1e-7 relative.
    np.testing.assert_allclose(sorted(b.volume for b in back.blocks), EXPECTED_VOLUMES, rtol=1e-5)


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
def test_gltf_round_trip_keeps_block_properties(tmp_path, suffix):
    model = stack_model()
    model.friction = 0.55
    model.ground = -0.25
    path = tmp_path / f"model{suffix}"
    write_model(model, path)
    back = read_model(path)
    assert back.friction == 0.55 and back.ground == -0.25
    by_id = {b.id: b for b in back.blocks}
    assert set(by_id) == {b.id for b in model.blocks}
    for block in model.blocks:
        other = by_id[block.id]
        assert other.tags == block.tags
        assert other.density == block.density
        assert other.fixed == block.fixed
        assert other.structural == block.structural
        assert other.rule_path == block.rule_path


def test_obj_has_one_group_per_block_with_polygon_faces():
    model = stack_model()
    text = encode_obj(model).decode()
    groups = [line.split()[1] for line in text.splitlines() if line.startswith("g ")]
    assert groups == [b.id for b in model.blocks]
    faces = [line for line in text.splitlines() if line.startswith("f ")]
    assert len(faces) == sum(len(b.faces) for b in model.blocks)  # not triangulated
    assert sum(len(f.split()) - 1 == 4 for f in faces) == 3 * 6  # the boxes keep their quads


def test_obj_group_names_become_ids_and_tags(tmp_path):
    path = tmp_path / "model.obj"
    write_model(stack_model(), path)
    back = read_model(path)
    assert {b.id for b in back.blocks} == {"base", "column", "cap", "tet", "rock"}
    assert all(b.tags == (b.id,) for b in back.blocks)


def test_stl_holds_the_whole_mesh(tmp_path):
    model = stack_model()
    path = tmp_path / "model.stl"
    write_model(model, path)
    mesh = trimesh.load_mesh(path, process=False)
    assert len(mesh.faces) == sum(len(block_triangles(b)) for b in model.blocks)
    assert mesh.area == pytest.approx(
        sum(b.face_area(k) for b in model.blocks for k in range(len(b.faces))), rel=1e-5
    )


def test_ply_keeps_touching_blocks_apart(tmp_path):
    """Touching blocks share vertex positions but not vertex indices, so they stay separate."""
    model = Model([Block.box([0, k, 0], [1, k + 1, 1], id=f"b{k}") for k in range(4)])
    path = tmp_path / "stack.ply"
    write_model(model, path)
    back = read_model(path)
    assert len(back.blocks) == 4
    np.testing.assert_allclose([b.volume for b in back.blocks], 1.0)


def test_flat_shaded_gltf_node_is_one_block(tmp_path):
    """Exporters that duplicate vertices per face still give one block per node."""
    box = trimesh.creation.box(extents=[1.0, 2.0, 3.0])
    box.unmerge_vertices()
    scene = trimesh.Scene()
    scene.add_geometry(box, node_name="pier", geom_name="pier")
    path = tmp_path / "pier.glb"
    path.write_bytes(scene.export(file_type="glb"))
    back = read_model(path)
    assert [b.id for b in back.blocks] == ["pier"]
    assert back.blocks[0].tags == ("pier",)
    assert back.blocks[0].volume == pytest.approx(6.0, rel=1e-6)
    assert len(back.blocks[0].faces) == 6  # coplanar hull triangles merged


def test_one_node_with_two_pieces_gives_two_blocks(tmp_path):
    pieces = trimesh.util.concatenate(
        [trimesh.creation.box(), trimesh.creation.box().apply_translation([3, 0, 0])]
    )
    scene = trimesh.Scene()
    scene.add_geometry(pieces, node_name="pair", geom_name="pair")
    path = tmp_path / "pair.glb"
    path.write_bytes(scene.export(file_type="glb"))
    back = read_model(path)
    assert sorted(b.id for b in back.blocks) == ["pair.0", "pair.1"]


DENTED_BOX_OBJ = """\
g dented
v 0 0 0
v 1 0 0
v 1 0 1
v 0 0 1
v 0 1 0
v 1 1 0
v 1 1 1
v 0 1 1
v 0.5 0.4 0.5
f 1 2 3 4
f 1 5 6 2
f 4 3 7 8
f 1 4 8 5
f 2 6 7 3
f 5 9 6
f 6 9 7
f 7 9 8
f 8 9 5
"""


def test_non_convex_component_is_an_error_naming_it(tmp_path):
    path = tmp_path / "dented.obj"
    path.write_text(DENTED_BOX_OBJ)
    with pytest.raises(GeometryError, match=r"dented\.obj.*'dented'.*not convex"):
        read_model(path)


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("model.step", b"ISO-10303-21;", r"unknown model format '\.step'.*\.json, \.obj"),
        ("model", b"{}", r"unknown model format '\(no extension\)'"),
        ("broken.glb", b"glTF\x02\x00\x00\x00garbage", r"broken\.glb"),
        ("empty.obj", b"# nothing here\n", r"empty\.obj.*no mesh"),
    ],
)
def test_unreadable_files_are_input_errors(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(InputFormatError, match=message):
        read_model(path)


def test_missing_mesh_file_is_an_input_error(tmp_path):
    with pytest.raises(InputFormatError, match="no such file"):
        read_model(tmp_path / "absent.glb")


@pytest.mark.parametrize(
    "name, message",
    [("model.step", r"unknown output format '\.step'"), ("missing/model.glb", "does not exist")],
)
def test_bad_output_paths_are_input_errors(tmp_path, name, message):
    with pytest.raises(InputFormatError, match=message):
        write_model(stack_model(), tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_the_previous_file(tmp_path):
    path = tmp_path / "model.json"
    path.write_text("previous")
    model = stack_model()
    model.blocks[0].density = float("nan")  # every output refuses non-finite numbers
    with pytest.raises(GeometryError, match="not written: block 'base' has density nan"):
        write_model(model, path)
    assert path.read_text() == "previous"
    assert [p.name for p in tmp_path.iterdir()] == ["model.json"]


def test_gltf_node_transforms_are_applied(tmp_path):
    scene = trimesh.Scene()
    turn = trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0])  # about y
    turn[:3, 3] = [10.0, 2.0, 0.0]
    scene.add_geometry(
        trimesh.creation.box(extents=[1.0, 2.0, 3.0]),
        node_name="moved",
        geom_name="box",
        transform=turn,
    )
    path = tmp_path / "moved.glb"
    path.write_bytes(scene.export(file_type="glb"))
    (block,) = read_model(path).blocks
    # x and z extents swap under the quarter turn about y; the centre moves to (10, 2, 0).
    np.testing.assert_allclose(block.bounds, [[8.5, 1.0, -0.5], [11.5, 3.0, 0.5]], atol=1e-6)
