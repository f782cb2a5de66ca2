"""The batched hulls of many small point sets are the hulls qhull gives one block at a time."""

from __future__ import annotations

import json

import numpy as np
import pytest

from shapegen.errors import GeometryError, InputFormatError
from shapegen.model.block import Block
from shapegen.model.hulls import batched_hulls, blocks_from_hulls
from shapegen.readers.block_entries import entry_block, read_block_entries
from shapegen.readers.blocks_json import model_from_dict

RNG = np.random.default_rng(7)


def _cycles(faces) -> set[tuple[int, ...]]:
    """Faces as cycles starting at their smallest corner: the same polygon, same orientation."""
    out = set()
    for face in faces:
        face = list(face)
        i = face.index(min(face))
        out.add(tuple(face[i:] + face[:i]))
    return out


def _box(lo, hi):
    return Block.box(lo, hi).vertices


def _rotation(seed: int) -> np.ndarray:
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def _prism(sides: int, radius: float, height: float) -> np.ndarray:
    angles = np.linspace(0, 2 * np.pi, sides, endpoint=False)
    ring = np.stack([radius * np.cos(angles), np.zeros(sides), radius * np.sin(angles)], axis=1)
    return np.concatenate([ring, ring + [0.0, height, 0.0]])


def _sphere_points(k: int, seed: int) -> np.ndarray:
    p = np.random.default_rng(seed).normal(size=(k, 3))
    return p / np.linalg.norm(p, axis=1)[:, None]


WEDGE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 2], [1, 0, 2], [0, 1, 2]], float)
SOUND = {
    "box": _box((0, 0, 0), (0.24, 0.07, 0.115)),
    "box, vertices shuffled": _box((1, 2, 3), (2, 2.5, 3.2))[RNG.permutation(8)],
    "box far from the origin": _box((1e6, 0, -3e5), (1e6 + 0.3, 0.2, -3e5 + 0.1)),
    "box turned": _box((0, 0, 0), (1, 2, 3)) @ _rotation(3).T,
    "tetrahedron": np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
    "wedge": WEDGE,
    "wedge turned and moved": WEDGE @ _rotation(5).T + 40.0,
    "triangular prism": _prism(3, 0.5, 1.0),
    "pentagonal prism": _prism(5, 2.0, 0.3),
    "hexagonal prism": _prism(6, 1.0, 1.0),
    "octahedron": np.concatenate([np.eye(3), -np.eye(3)]),
    "tiny box": _box((0, 0, 0), (1e-4, 2e-4, 3e-4)),
    **{f"irregular, {k} points": _sphere_points(k, k) * 3 + k for k in range(4, 13)},
}  # fmt: skip
LEFT_TO_QHULL = {
    "a point inside": np.vstack([_box((0, 0, 0), (1, 1, 1)), [[0.5, 0.5, 0.5]]]),
    "a point on a face": np.vstack([_box((0, 0, 0), (1, 1, 1)), [[0.5, 0.0, 0.5]]]),
    "a point on an edge": np.vstack([_box((0, 0, 0), (1, 1, 1)), [[0.5, 0.0, 0.0]]]),
    "a repeated point": np.vstack([_box((0, 0, 0), (1, 1, 1)), [[1.0, 1.0, 1.0]]]),
    "a face bent by 1e-9": np.vstack([WEDGE[:5], WEDGE[5] + [2e-9, 0, 0]]),
    "13 points": _sphere_points(13, 13),
}


@pytest.mark.parametrize("name", list(SOUND) + list(LEFT_TO_QHULL))
def test_batched_hull_is_qhulls_hull(name):
    points = {**SOUND, **LEFT_TO_QHULL}[name]
    hull = batched_hulls([points])[0]
    if name in LEFT_TO_QHULL:
        assert hull is None
        return
    assert hull is not None
    vertices, faces = hull
    reference = Block.from_hull(points)
    assert np.array_equal(vertices, reference.vertices)
    assert _cycles(faces) == _cycles(reference.faces)


def test_many_blocks_at_once_are_each_their_own_hull():
    sets = [points for points in SOUND.values() for _ in range(3)]
    sets += [_box((x, 0, 0), (x + 0.2, 0.1, 0.1)) for x in range(50)]
    sets += list(LEFT_TO_QHULL.values())
    order = RNG.permutation(len(sets))
    sets = [sets[k] for k in order]
    fields = [{"id": f"b{k}", "density": 1000.0 + k} for k in range(len(sets))]
    blocks = blocks_from_hulls(sets, fields)
    for points, block, given in zip(sets, blocks, fields, strict=True):
        reference = Block.from_hull(points, **given)
        assert block.id == reference.id and block.density == reference.density
        assert np.array_equal(block.vertices, reference.vertices)
        assert _cycles(block.faces) == _cycles(reference.faces)
        assert block.volume == pytest.approx(reference.volume, rel=1e-12)


DEGENERATE = [
    ("flat or collinear", [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.5, 0.5, 0]]),
    ("flat or collinear", [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]),
    ("must be finite numbers", [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, float("nan")]]),
    ("needs at least 4 vertices", [[0, 0, 0], [1, 0, 0], [0, 1, 0]]),
]


@pytest.mark.parametrize(("message", "points"), DEGENERATE)
def test_degenerate_point_sets_are_refused_in_one_line(message, points):
    sets = [_box((0, 0, 0), (1, 1, 1)), np.array(points, float), _box((2, 0, 0), (3, 1, 1))]
    with pytest.raises(GeometryError, match=message) as caught:
        blocks_from_hulls(sets, [{"id": "ok"}, {"id": "bad"}, {"id": "after"}])
    assert "'bad'" in str(caught.value) and "\n" not in str(caught.value)


def _document(entries):
    return {"format": "shapegen-blocks", "version": 1, "blocks": entries}


def test_a_file_of_vertices_reads_as_the_blocks_read_one_by_one():
    entries = [
        {"id": name, "vertices": points.tolist(), "density": 2000.0 + k}
        for k, (name, points) in enumerate({**SOUND, **LEFT_TO_QHULL}.items())
    ]
    box = Block.box((0, 0, 0), (1, 1, 1), id="faced")
    entry = box.to_dict()
    entry["faces"] = [list(reversed(f)) if k % 2 else f for k, f in enumerate(entry["faces"])]
    entries.append(entry)
    entries.append({"id": "ints", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]})
    entries = json.loads(json.dumps(entries))
    blocks = read_block_entries(entries)
    for k, (entry, block) in enumerate(zip(entries, blocks, strict=True)):
        reference = entry_block(entry, k)
        assert block.id == reference.id and block.density == reference.density
        assert np.array_equal(block.vertices, reference.vertices)
        assert _cycles(block.faces) == _cycles(reference.faces)
    assert blocks[-2].faces == box.faces


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        ({"id": "x", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, True]]}, "finite number"),
        ({"id": "x", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, "1"]]}, "finite number"),
        ({"id": "x", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1], [0, 0, 1]]}, "3 numbers"),
        ({"id": "x", "vertices": []}, "non-empty list"),
        ({"id": "x", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.5, 0.5, 0]]}, "flat"),
        ({"id": "x", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "density": -1},
         "must be >= 0"),
    ],
)  # fmt: skip
def test_the_first_bad_entry_is_named_as_when_read_one_by_one(bad, message):
    good = {"id": "g", "vertices": _box((0, 0, 0), (1, 1, 1)).tolist()}
    later = {"id": "later", "vertices": [[0, 0, 0]], "density": "heavy"}
    document = _document([good, bad, good | {"id": "g2"}, later])
    with pytest.raises((InputFormatError, GeometryError), match=message) as caught:
        model_from_dict(document)
    with pytest.raises(type(caught.value)) as one_by_one:
        [entry_block(entry, k) for k, entry in enumerate(document["blocks"])]
    assert str(caught.value) == str(one_by_one.value)
    assert "'x'" in str(caught.value)
