"""The vectorised block checks give Block.validate's verdict and message, block by block."""

from __future__ import annotations

import numpy as np
import pytest
from rotations import about_y

import shapegen
from shapegen.errors import GeometryError
from shapegen.model import Block, Model, Scope
from shapegen.model.validation import first_invalid_block, validate_blocks
from shapegen.primitives.registry import Primitive
from shapegen.tolerances import DEFAULT, Tolerances

GRAMMARS = ("arch_columns", "cluny", "mosque")


def _verdict(block: Block, tol: Tolerances) -> str | None:
    try:
        block.validate(tol)
    except GeometryError as exc:
        return str(exc)
    return None


def _fresh(block: Block) -> Block:
    """A copy without the cached geometry of the original."""
    return Block(block.vertices.copy(), block.faces, density=block.density, id=block.id)


def _assert_agrees(blocks: list[Block], tol: Tolerances) -> None:
    """first_invalid_block on each block alone and on all of them matches Block.validate."""
    expected = [_verdict(_fresh(b), tol) for b in blocks]
    for block, message in zip(blocks, expected, strict=True):
        found = first_invalid_block([_fresh(block)], tol)
        assert (None if found is None else str(found[1])) == message
    bad = [k for k, message in enumerate(expected) if message is not None]
    found = first_invalid_block([_fresh(b) for b in blocks], tol)
    if not bad:
        assert found is None
    else:
        assert found is not None
        assert (found[0], str(found[1])) == (bad[0], expected[bad[0]])


def _hulls(seed: int) -> list[Block]:
    rng = np.random.default_rng(seed)
    blocks = []
    for count in (4, 5, 8, 12, 30, 100, 300):
        for scale, offset in ((1.0, 0.0), (0.01, 5.0), (40.0, -200.0), (1.0, 1e4)):
            points = rng.normal(size=(count, 3)) * scale * rng.uniform(0.2, 1.0, 3) + offset
            blocks.append(Block.from_hull(points, id=f"hull{len(blocks)}"))
    return blocks


def _boxes() -> list[Block]:
    corners = [
        ([0, 0, 0], [1, 1, 1]),
        ([-5, 1, 2], [-4.5, 1.1, 9]),
        ([1e3, 1e3, 1e3], [1e3 + 1, 1e3 + 1, 1e3 + 1]),
        ([1e5, 0, -1e5], [1e5 + 0.3, 0.2, -1e5 + 0.5]),
        ([0, 0, 0], [1e-3, 2e-3, 1e-3]),
        ([0, 0, 0], [200, 0.05, 300]),
    ]
    return [Block.box(lo, hi, id=f"box{k}") for k, (lo, hi) in enumerate(corners)]


@pytest.fixture(scope="module")
def grammar_blocks() -> dict[str, list[Block]]:
    return {name: shapegen.load_grammar(f"{name}.grammar").build().blocks for name in GRAMMARS}


@pytest.mark.parametrize("size", [1.0, 10.0, 150.0])
def test_boxes_and_hulls_agree_with_block_validate(size):
    tol = DEFAULT.for_size(size)
    _assert_agrees(_boxes() + _hulls(seed=0), tol)


def test_turned_and_mirrored_blocks_agree(grammar_blocks):
    turn = about_y(23.0)
    mirror = np.diag([-1.0, 1.0, 1.0])
    blocks = grammar_blocks["mosque"][:40]
    moved = [b.transformed(turn, [3.0, 0.0, -7.0]) for b in blocks]
    moved += [b.transformed(mirror, [0.0, 0.0, 0.0]) for b in blocks]
    _assert_agrees(moved, DEFAULT.for_size(60.0))


@pytest.mark.parametrize("name", GRAMMARS)
def test_grammar_blocks_agree_with_block_validate(grammar_blocks, name):
    model = Model(blocks=grammar_blocks[name])
    for tol in (model.tolerances(), DEFAULT):
        _assert_agrees(model.blocks, tol)


def _nan_vertex() -> Block:
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.vertices[5, 1] = np.nan
    return block


def _face_out_of_range() -> Block:
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.faces = (*block.faces[:-1], (1, 5, 6, 8))
    return block


def _negative_face_index() -> Block:
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.faces = ((0, 1, -2, 3), *block.faces[1:])
    return block


def _two_corner_face() -> Block:
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.faces = (*block.faces, (0, 1))
    return block


def _non_convex() -> Block:
    # A box with one top corner pushed down: the top face is no longer a plane.
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.vertices[6, 1] = 0.7
    return block


def _inside_out() -> Block:
    block = Block.box([0, 0, 0], [1, 1, 1])
    block.faces = tuple(tuple(reversed(f)) for f in block.faces)
    return block


def _three_faces() -> Block:
    return Block(np.eye(4, 3), ((0, 1, 2), (0, 3, 1), (1, 3, 2)))


BAD_BLOCKS = [
    ("vertex coordinates must be finite", _nan_vertex),
    ("density must be a number in [0, 1e+06]", lambda: Block.box([0] * 3, [1] * 3, density=-1)),
    ("density must be a number in [0, 1e+06]", lambda: Block.box([0] * 3, [1] * 3, density=np.nan)),
    ("face [1, 5, 6, 8] must list at least 3 of its 8 vertices", _face_out_of_range),
    ("face [0, 1, -2, 3] must list at least 3", _negative_face_index),
    ("face [0, 1] must list at least 3", _two_corner_face),
    ("zero or negative volume (0 m^3)", lambda: Block.box([0, 0, 0], [1, 0, 1])),
    (
        "volume 1e-13 m^3 is within the model's volume tolerance of zero, 1e-12 m^3",
        lambda: Block.box([0, 0, 0], [1, 1e-13, 1]),
    ),
    ("zero or negative volume (-1 m^3)", _inside_out),
    pytest.param(
        "zero or negative volume (0 m^3)",
        lambda: Block(np.zeros((0, 3)), ()),
        marks=pytest.mark.filterwarnings("ignore:Mean of empty slice", "ignore:invalid value"),
        id="no vertices, no faces",
    ),
    ("not convex (a vertex lies 0.0734 m outside a face plane)", _non_convex),
]


@pytest.mark.parametrize(("message", "make"), BAD_BLOCKS)
def test_first_bad_block_is_reported_with_its_own_message(message, make):
    good = _boxes()
    second_bad = Block.box([0, 0, 0], [1, 0, 1], id="later")
    blocks = [*good[:3], make(), *good[3:], second_bad]
    blocks[3].id = "culprit"
    expected = _verdict(_fresh(blocks[3]), DEFAULT)
    assert expected is not None and expected.startswith("block 'culprit': ")
    assert message in expected
    found = first_invalid_block(blocks, DEFAULT)
    assert found is not None
    assert (found[0], str(found[1])) == (3, expected)
    with pytest.raises(GeometryError) as caught:
        validate_blocks(blocks, DEFAULT)
    assert str(caught.value) == expected
    _assert_agrees(blocks, DEFAULT)


def test_a_nearly_flat_block_above_the_volume_tolerance_is_sound():
    tol = DEFAULT.for_size(1.0)
    flat = Block.box([0, 0, 0], [1, 1e-11, 1])  # 1e-11 m^3 > tol.volume = 1e-12 m^3
    assert first_invalid_block([flat], tol) is None
    _assert_agrees([flat, Block.box([0, 0, 0], [1, 1e-13, 1])], tol)


def test_three_faces_with_a_volume_are_judged_as_block_validate_does():
    # The vectorised pass cannot take fewer than 4 faces; Block.validate still decides.
    _assert_agrees([_three_faces()], DEFAULT)


def _at_threshold(block: Block) -> list[Tolerances]:
    """Tolerances whose volume and convexity bounds fall exactly on the block's own figures and
    one step either side, where a different rounding would flip the verdict."""
    volume = block.volume
    worst = float((block.vertices @ block.face_normals.T - block.face_offsets).max())
    tols = []
    for v in (np.nextafter(volume, 0), volume, np.nextafter(volume, np.inf)):
        tols.append(Tolerances(volume_rel=float(v), convex_rel=1.0, size=1.0))
    for w in (np.nextafter(worst, -np.inf), worst, np.nextafter(worst, np.inf)):
        tols.append(Tolerances(volume_rel=0.0, convex_rel=float(w), size=1.0))
    return tols


@pytest.mark.parametrize(
    "make",
    [_non_convex, lambda: _hulls(seed=3)[9], lambda: _boxes()[3]],
    ids=["non-convex box", "hull", "box far from the origin"],
)
def test_verdicts_on_the_tolerance_boundaries_are_block_validates(make):
    block = make()
    for tol in _at_threshold(_fresh(block)):
        _assert_agrees([block], tol)


def test_model_reports_whichever_comes_first_of_a_bad_block_and_a_duplicate_id():
    a, b, c = (Block.box([k, 0, 0], [k + 1, 1, 1], id=f"b{k}") for k in range(3))
    flat = Block.box([5, 0, 0], [6, 0, 1], id="flat")
    twin = Block.box([7, 0, 0], [8, 1, 1], id="b0")
    with pytest.raises(GeometryError, match="'flat': zero or negative volume"):
        Model(blocks=[a, b, flat, twin, c]).validate()
    with pytest.raises(GeometryError, match="two blocks are named 'b0'"):
        Model(blocks=[a, b, twin, flat, c]).validate()
    Model(blocks=[a, b, c]).validate()


def _primitive(pieces) -> Primitive:
    return Primitive("pieces", lambda scope: pieces, {}, "")


def test_primitive_names_the_first_bad_piece():
    scope = Scope.axis_aligned((0, 0, 0), (3, 1, 1))
    good = [Block.box([k, 0, 0], [k + 1, 1, 1]) for k in range(3)]
    flat = Block.box([0, 0, 0], [1, 0, 1], id="flat")
    assert len(_primitive(good)(scope)) == 3
    with pytest.raises(GeometryError, match=r"^primitive 'pieces', piece 2: block 'flat': zero"):
        _primitive([*good[:2], flat, "not a block", good[2]])(scope)
    with pytest.raises(GeometryError, match=r"^primitive 'pieces' returned str, not a Block$"):
        _primitive([good[0], "not a block", flat])(scope)


def test_sound_blocks_are_cleared_without_the_per_block_check(grammar_blocks, monkeypatch):
    # The speed comes from settling sound blocks on the packed arrays alone.
    def refuse(self, tol=DEFAULT):
        raise AssertionError(f"Block.validate called for sound block {self.id!r}")

    monkeypatch.setattr(Block, "validate", refuse)
    for blocks in grammar_blocks.values():
        assert first_invalid_block(blocks, Model(blocks=blocks).tolerances()) is None
    assert first_invalid_block(_boxes() + _hulls(seed=1), DEFAULT.for_size(10.0)) is None
