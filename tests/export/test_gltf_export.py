"""glTF output: node names, extras, colours and resultant arrows.

The files are decoded here with the standard library (GLB header and JSON chunk), not with the
library that wrote them.
"""

from __future__ import annotations

import json
import struct
from types import SimpleNamespace

import numpy as np
import pytest

from shapegen import Block, Model
from shapegen.export.colors import (
    NON_STRUCTURAL,
    RESULTANT,
    SUPPORT,
    TENSION_MAX,
    TENSION_ZERO,
    UNLABELLED,
    label_color,
)
from shapegen.export.gltf import (
    ARROW_LENGTH_BLOCKS,
    RESULTANTS_NODE,
    encode_glb,
    encode_gltf,
    resultant_arrows,
)
from shapegen.export.model_io import write_model
from shapegen.readers.models import read_model


def glb_json(content: bytes) -> dict:
    """The JSON chunk of a binary glTF (spec: 12-byte header, then chunks length/type/data)."""
    magic, version, length = struct.unpack_from("<4sII", content, 0)
    assert magic == b"glTF" and version == 2 and length == len(content)
    chunk_length, chunk_type = struct.unpack_from("<I4s", content, 12)
    assert chunk_type == b"JSON"
    return json.loads(content[20 : 20 + chunk_length])


def colonnade() -> Model:
    blocks = [
        Block.box([0, 0, 0], [4, 0.5, 1], id="footing", fixed=True),
        Block.box([0, 0.5, 0], [1, 3, 1], id="c0", tags=("column",), rule_path=("Lot", "Col")),
        Block.box([3, 0.5, 0], [4, 3, 1], id="c1", tags=("column",), rule_path=("Lot", "Col")),
        Block.box([0, 3, 0], [4, 3.5, 1], id="lintel", tags=("lintel",), density=2000.0),
        Block.box([0, 3.5, 0], [4, 4, 1], id="roof", structural=False),
        Block.box([1.5, 4, 0], [2.5, 4.5, 1], id="plain"),
    ]
    return Model(blocks)


def node_colors(tree: dict) -> dict[str, np.ndarray]:
    """Node name -> RGBA 0..255 of its mesh's material."""
    out = {}
    for node in tree["nodes"]:
        if "mesh" not in node:
            continue
        material = tree["materials"][tree["meshes"][node["mesh"]]["primitives"][0]["material"]]
        factor = material["pbrMetallicRoughness"]["baseColorFactor"]
        out[node["name"]] = np.round(np.array(factor) * 255).astype(int)
    return out


@pytest.mark.parametrize("encode", [encode_glb, encode_gltf])
def test_one_node_per_block_named_by_id_with_extras(encode):
    model = colonnade()
    content = encode(model)
    tree = glb_json(content) if encode is encode_glb else json.loads(content)
    nodes = {node["name"]: node for node in tree["nodes"]}
    assert set(nodes) == {b.id for b in model.blocks}
    for block in model.blocks:
        extras = nodes[block.id]["extras"]
        assert extras["role"] == "block"
        assert extras["labels"] == list(block.tags)
        assert extras["rule_path"] == list(block.rule_path)
        assert extras["density"] == block.density
        assert extras["fixed"] is block.fixed
        assert extras["structural"] is block.structural
    scene_extras = tree["scenes"][tree["scene"]]["extras"]
    assert scene_extras["format"] == "shapegen-blocks"
    assert scene_extras["ground"] == 0.0 and scene_extras["friction"] == 0.7


def test_gltf_file_is_self_contained(tmp_path):
    path = tmp_path / "model.gltf"
    write_model(colonnade(), path)
    tree = json.loads(path.read_text())
    assert all(buffer["uri"].startswith("data:") for buffer in tree["buffers"])
    assert [p.name for p in tmp_path.iterdir()] == ["model.gltf"]


def test_positions_are_the_block_vertices_unchanged():
    """glTF is y-up in metres like shapegen: the accessor bounds are the block's bounds."""
    model = colonnade()
    tree = glb_json(encode_glb(model))
    for node in tree["nodes"]:
        block = model.blocks[model.index_of(node["name"])]
        primitive = tree["meshes"][node["mesh"]]["primitives"][0]
        accessor = tree["accessors"][primitive["attributes"]["POSITION"]]
        np.testing.assert_allclose(accessor["min"], block.bounds[0], rtol=1e-6)
        np.testing.assert_allclose(accessor["max"], block.bounds[1], rtol=1e-6)
        assert "matrix" not in node


def test_label_colours():
    colors = node_colors(glb_json(encode_glb(colonnade())))
    np.testing.assert_array_equal(colors["c0"], colors["c1"])  # same label, same colour
    np.testing.assert_array_equal(colors["c0"], label_color("column"))
    assert not np.array_equal(colors["c0"], colors["lintel"])
    np.testing.assert_array_equal(colors["footing"], SUPPORT)
    np.testing.assert_array_equal(colors["roof"], NON_STRUCTURAL)
    np.testing.assert_array_equal(colors["plain"], UNLABELLED)


@pytest.mark.parametrize("label", ["column", "lintel", "voussoir", "r\u00e9sille"])
def test_label_colour_is_stable(label):
    """The palette index is a CRC-32 of the label, independent of process and model order."""
    import zlib

    from shapegen.export.colors import LABEL_PALETTE

    expected = LABEL_PALETTE[zlib.crc32(label.encode()) % len(LABEL_PALETTE)]
    np.testing.assert_array_equal(label_color(label), expected)


def stub_analysis(model: Model, tension: list[float]) -> SimpleNamespace:
    """The fields of an Analysis that the writer reads: two resultants of 10 kN and 5 kN."""
    return SimpleNamespace(
        block_tension=np.array(tension, dtype=float),
        resultant_forces=np.array([[0.0, -10e3, 0.0], [0.0, 5e3, 0.0], [0.0, 0.0, 0.0]]),
        resultant_points=np.array([[0.5, 0.5, 0.5], [3.5, 3.0, 0.5], [np.nan] * 3]),
        status="optimal",
        feasible=False,
        infeasibility=12.0,
        infeasibility_normalized=1e-3,
        max_tension=40.0,
        total_weight=1e5,
    )


def test_tension_colours_and_arrows(tmp_path):
    model = colonnade()
    analysis = stub_analysis(model, [0.0, 0.0, 40.0, 20.0, 0.0, float("nan")])
    tree = glb_json(encode_glb(model, analysis))
    colors = node_colors(tree)
    np.testing.assert_array_equal(colors["c1"], TENSION_MAX)  # the worst tension is red
    np.testing.assert_array_equal(colors["c0"], TENSION_ZERO)  # no tension is grey
    np.testing.assert_array_equal(colors["plain"], TENSION_ZERO)
    midway = colors["lintel"][:3].astype(float)  # half the worst: halfway along the ramp
    halfway = (TENSION_ZERO[:3].astype(float) + TENSION_MAX[:3]) / 2
    np.testing.assert_allclose(midway, halfway, atol=5)
    np.testing.assert_array_equal(colors["footing"], SUPPORT)
    np.testing.assert_array_equal(colors[RESULTANTS_NODE], RESULTANT)
    nodes = {node["name"]: node for node in tree["nodes"]}
    assert nodes["c1"]["extras"]["tension"] == 40.0
    arrows = nodes[RESULTANTS_NODE]["extras"]
    assert arrows["role"] == "resultants" and arrows["count"] == 2
    assert tree["scenes"][0]["extras"]["analysis"]["feasible"] is False

    # The longest arrow is ARROW_LENGTH_BLOCKS block sizes, along -y, centred on its point. The
    # structural blocks hold 2, 2.5, 2.5, 2 and 0.5 m^3: the median cube has an edge of 2^(1/3) m.
    accessor = tree["accessors"][
        tree["meshes"][nodes[RESULTANTS_NODE]["mesh"]]["primitives"][0]["attributes"]["POSITION"]
    ]
    length = ARROW_LENGTH_BLOCKS * 2.0 ** (1 / 3)
    assert arrows["newtons_per_metre"] == pytest.approx(10e3 / length)
    low, high = np.array(accessor["min"]), np.array(accessor["max"])
    assert low[1] == pytest.approx(0.5 - length / 2, rel=1e-5)  # the 10 kN arrow's far end
    assert high[1] == pytest.approx(3.0 + length / 4, rel=1e-5)  # the 5 kN arrow's far end

    # Reading the file back gives the blocks only, not the arrows.
    path = tmp_path / "analysed.glb"
    write_model(model, path, analysis)
    assert sorted(b.id for b in read_model(path).blocks) == sorted(b.id for b in model.blocks)


def test_no_arrows_without_forces():
    model = colonnade()
    analysis = stub_analysis(model, [0.0] * 6)
    analysis.resultant_forces = np.zeros((3, 3))
    tree = glb_json(encode_glb(model, analysis))
    assert RESULTANTS_NODE not in {node["name"] for node in tree["nodes"]}
    allowed = [TENSION_ZERO, SUPPORT, NON_STRUCTURAL]
    for color in node_colors(tree).values():
        assert any(np.array_equal(color, a) for a in allowed)


@pytest.mark.parametrize("rules", ["suspension_bridge.grammar", "wall_windows.grammar"])
def test_the_longest_arrow_is_the_size_of_a_block_not_of_the_model(rules):
    import shapegen
    from shapegen.statics import analyze

    model = shapegen.load_grammar(rules).build()
    analysis = analyze(model)
    mesh, _, count = resultant_arrows(model, analysis)
    assert count > 0
    # Each arrow's extent along its own force is its length (the arrows come in force order).
    forces = np.asarray(analysis.resultant_forces, float).reshape(-1, 3)
    magnitude = np.linalg.norm(forces, axis=1)
    drawn = forces[magnitude > 1e-9 * magnitude.max()]
    assert len(drawn) == count
    direction = drawn / np.linalg.norm(drawn, axis=1, keepdims=True)
    vertices = np.asarray(mesh.vertices).reshape(count, -1, 3)
    along = np.einsum("amk,ak->am", vertices, direction)
    longest = float((along.max(axis=1) - along.min(axis=1)).max())

    structural = [b for b in model.blocks if b.structural]
    cube_edges = np.cbrt([b.volume for b in structural])
    diagonals = [
        np.linalg.norm(b.vertices.max(axis=0) - b.vertices.min(axis=0)) for b in structural
    ]
    assert longest == pytest.approx(ARROW_LENGTH_BLOCKS * np.median(cube_edges), rel=1e-6)
    assert longest <= np.median(diagonals)  # no longer than a typical block
    # Scaled to the model, the longest was 15% of its diagonal: 300 m on the 2 km bridge.
    assert longest < 0.05 * model.size


def test_glb_layout_follows_the_specification():
    """The rules of glTF 2.0 a reader relies on: the binary chunk holds every view, each view
    at a 4-byte boundary, POSITION accessors carry min and max equal to their data's, indices
    stay below the vertex count, and identical arrays (the boxes' indices) are stored once."""
    content = encode_glb(colonnade())
    tree = glb_json(content)
    json_length = struct.unpack_from("<I", content, 12)[0]
    bin_length, bin_type = struct.unpack_from("<I4s", content, 20 + json_length)
    assert bin_type == b"BIN\x00" and tree["buffers"][0]["byteLength"] == bin_length
    body = content[28 + json_length : 28 + json_length + bin_length]
    for view in tree["bufferViews"]:
        assert view["byteOffset"] % 4 == 0
        assert view["byteOffset"] + view["byteLength"] <= bin_length
    for mesh in tree["meshes"]:
        primitive = mesh["primitives"][0]
        positions = tree["accessors"][primitive["attributes"]["POSITION"]]
        view = tree["bufferViews"][positions["bufferView"]]
        start = view["byteOffset"]
        points = np.frombuffer(body[start : start + view["byteLength"]], np.float32)
        points = points.reshape(-1, 3)
        assert len(points) == positions["count"]
        assert positions["min"] == points.min(axis=0).tolist()
        assert positions["max"] == points.max(axis=0).tolist()
        indices = tree["accessors"][primitive["indices"]]
        assert indices["count"] % 3 == 0 and indices["max"][0] < positions["count"]
    # six boxes: one index array and five distinct corner sets would do; none is written twice
    views = [body[v["byteOffset"] : v["byteOffset"] + v["byteLength"]] for v in tree["bufferViews"]]
    assert len(views) == len(set(views)) and len(views) < 2 * len(tree["meshes"])
