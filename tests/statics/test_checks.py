"""Model checks before the statics: overlaps, blocks below ground, support, degenerate blocks."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen.errors import GeometryError, StaticsError
from shapegen.model.block import Block
from shapegen.model.model import Model
from shapegen.statics.checks import check_model
from shapegen.statics.contacts import find_interfaces


def box(lo, hi, **kw) -> Block:
    return Block.box(lo, hi, **kw)


def check(model: Model) -> None:
    check_model(model, find_interfaces(model))


def turned(block: Block, angle: float, center) -> Block:
    c, s = np.cos(angle), np.sin(angle)
    r = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    center = np.asarray(center, float)
    return block.transformed(r, center - r @ center)


def test_a_sound_stack_passes():
    check(Model([box((0, 0, 0), (2, 1, 1), id="a"), box((0.5, 1, 0), (1.5, 2, 1), id="b")]))


def test_a_sound_running_bond_of_turned_blocks_passes():
    blocks = [box((0, 0, 0), (1, 1, 1), id="base")]
    blocks.append(turned(box((0, 1, 0), (1, 2, 1), id="top"), 0.7, (0.5, 1.5, 0.5)))
    check(Model(blocks))


@pytest.mark.parametrize(
    "second, overlap",
    [
        (((0.5, 0, 0), (1.5, 1, 1)), 0.5),  # half inside, side by side
        (((0, 0.9, 0), (1, 1.9, 1)), 0.1),  # sunk 0.1 into the lower block
        (((0.2, 0.2, 0.2), (0.4, 0.4, 0.4)), 0.008),  # wholly inside
    ],
)
def test_interpenetrating_boxes_name_both_blocks_and_the_volume(second, overlap):
    model = Model([box((0, 0, 0), (1, 1, 1), id="wall"), box(*second, id="lintel")])
    with pytest.raises(GeometryError) as error:
        check(model)
    message = str(error.value)
    assert "'wall'" in message and "'lintel'" in message and "interpenetrate" in message
    assert f"({overlap:.3g} m^3 overlap)" in message


def test_turned_block_sunk_into_another_is_found():
    # No face plane of either block separates them, so the volume decides.
    top = turned(box((0, 0.8, 0), (1, 1.8, 1), id="top"), np.pi / 4, (0.5, 1.3, 0.5))
    with pytest.raises(GeometryError, match="'base' and 'top' interpenetrate"):
        check(Model([box((0, 0, 0), (1, 1, 1), id="base"), top]))


def test_overlap_below_tolerance_is_accepted():
    sink = 1e-7  # overlap volume 1e-7 m^3, far below 1e-4 of the smaller block's 1 m^3
    check(Model([box((0, 0, 0), (1, 1, 1)), box((0, 1 - sink, 0), (1, 2 - sink, 1))]))


def test_free_block_below_ground_is_named():
    model = Model([box((0, -0.05, 0), (1, 1, 1), id="sunk")], ground=0.0)
    with pytest.raises(GeometryError, match=r"block 'sunk' reaches 0.05 m below the ground"):
        check(model)


def test_fixed_block_may_reach_below_ground():
    footing = box((0, -1, 0), (1, 0, 1), id="footing", fixed=True)
    check(Model([footing, box((0, 0, 0), (1, 1, 1))], ground=0.0))


def test_floating_block_is_named():
    model = Model([box((0, 0, 0), (1, 1, 1), id="pier"), box((0, 2, 0), (1, 3, 1), id="cloud")])
    with pytest.raises(StaticsError, match=r"block 'cloud' touches no support"):
        check(model)


def test_floating_group_is_named_with_its_size():
    blocks = [box((0, 0, 0), (1, 1, 1), id="pier")]
    blocks += [box((0, 2 + k, 0), (1, 3 + k, 1), id=f"f{k}") for k in range(7)]
    with pytest.raises(StaticsError) as error:
        check(Model(blocks))
    message = str(error.value)
    assert "'f0', 'f1', 'f2', 'f3', 'f4' and 2 more (7 blocks)" in message
    assert "no support through any chain of contacts" in message


def test_block_resting_only_on_a_non_structural_block_is_floating():
    blocks = [
        box((0, 0, 0), (1, 1, 1), id="roof", structural=False),
        box((0, 1, 0), (1, 2, 1), id="finial"),
    ]
    with pytest.raises(StaticsError, match="'finial'"):
        check(Model(blocks))


def test_floating_non_structural_block_is_ignored():
    check(Model([box((0, 0, 0), (1, 1, 1)), box((0, 5, 0), (1, 6, 1), structural=False)]))


def test_no_support_at_all():
    with pytest.raises(StaticsError, match="no support"):
        check(Model([box((0, 0, 0), (1, 1, 1))], ground=None))


def test_fixed_block_supports_without_ground():
    blocks = [box((0, 0, 0), (1, 1, 1), fixed=True), box((0, 1, 0), (1, 2, 1), id="on")]
    check(Model(blocks, ground=None))


def with_nan_corner() -> np.ndarray:
    vertices = box((0, 0, 0), (1, 1, 1)).vertices.copy()
    vertices[2, 1] = np.nan
    return vertices


@pytest.mark.parametrize(
    "vertices, problem",
    [
        (with_nan_corner(), "finite"),
        (box((0, 0, 0), (1, 0, 1)).vertices, "zero or negative volume"),
    ],
)
def test_degenerate_block_is_a_geometry_error(vertices, problem):
    bad = Block(vertices, box((0, 0, 0), (1, 1, 1)).faces, id="bad")
    with pytest.raises(GeometryError, match=rf"block 'bad'.*{problem}"):
        check_model(Model([box((2, 0, 0), (3, 1, 1)), bad]), [])


def test_non_convex_block_is_a_geometry_error():
    vertices = box((0, 0, 0), (1, 1, 1)).vertices.copy()
    vertices[6] = [0.6, 0.6, 0.6]  # pushes a corner inward: the top and sides no longer planar
    bad = Block(vertices, box((0, 0, 0), (1, 1, 1)).faces, id="dent")
    with pytest.raises(GeometryError, match="block 'dent'.*not convex"):
        check_model(Model([bad]), [])


def test_duplicate_ids_are_a_geometry_error():
    model = Model([box((0, 0, 0), (1, 1, 1), id="x"), box((0, 1, 0), (1, 2, 1), id="x")])
    with pytest.raises(GeometryError, match="'x'"):
        check_model(model, [])


@pytest.mark.parametrize("seed", [0, 1])
def test_face_plane_prefilter_never_dismisses_overlapping_blocks(seed):
    from manifold3d import Manifold

    from shapegen.model.packed import pack_blocks
    from shapegen.statics.checks import _separated_by_face, _separated_by_facing_face

    rng = np.random.default_rng(seed)
    blocks = [
        Block.from_hull(rng.normal(size=(12, 3)) * 0.6 + rng.uniform(0, 3, size=3))
        for _ in range(40)
    ]
    pack = pack_blocks(blocks)
    a, b = np.triu_indices(len(blocks), k=1)
    separated = _separated_by_face(pack, a, b, 1e-9) | _separated_by_face(pack, b, a, 1e-9)
    quick = _separated_by_facing_face(pack, a, b, 1e-9) | _separated_by_facing_face(
        pack, b, a, 1e-9
    )
    assert quick.any() and np.all(separated[quick])  # the quick pass tries a subset of planes
    volume = np.array(
        [
            (
                Manifold.hull_points(blocks[i].vertices) ^ Manifold.hull_points(blocks[j].vertices)
            ).volume()
            for i, j in zip(a, b, strict=True)
        ]
    )
    assert separated.any() and (volume > 1e-9).any()
    assert np.all(volume[separated] < 1e-9)
