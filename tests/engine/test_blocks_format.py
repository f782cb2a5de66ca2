"""The shapegen-blocks v1 reader: required keys, defaults, orientation, and its error messages."""

import json

import numpy as np
import pytest

from shapegen.errors import GeometryError, InputFormatError
from shapegen.export.blocks_json import write_blocks_json
from shapegen.model import Block, Model, PointLoad
from shapegen.readers.blocks_json import model_from_dict, read_blocks_json

CUBE = [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1], [0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]]


def _document(**changes):
    doc = {"format": "shapegen-blocks", "version": 1, "blocks": [{"id": "b0", "vertices": CUBE}]}
    doc.update(changes)
    return doc


def test_defaults_and_hull_when_faces_are_missing():
    model = model_from_dict(_document())
    assert model.ground == 0.0 and model.friction == 0.7
    np.testing.assert_allclose(model.gravity, [0, -9.81, 0])
    assert model.blocks[0].volume == pytest.approx(1.0)
    assert model.blocks[0].density == 2400.0


def test_inward_faces_are_turned_outward():
    faces = [list(reversed(f)) for f in Block.box([0, 0, 0], [1, 1, 1]).faces]
    model = model_from_dict(_document(blocks=[{"id": "c", "vertices": CUBE, "faces": faces}]))
    assert model.blocks[0].volume == pytest.approx(1.0)


def test_unknown_keys_are_ignored_and_ground_may_be_null():
    model = model_from_dict(_document(ground=None, colour="red"))
    assert model.ground is None


def test_round_trip_keeps_everything(tmp_path):
    block = Block.box([0, 0, 0], [2, 1, 1], id="w", tags=("wall",), density=1800.0)
    support = Block.box([0, -1, 0], [2, 0, 1], id="s", fixed=True)
    model = Model([block, support], [PointLoad("w", [0, -10, 0], [1, 1, 0.5])], ground=None)
    path = tmp_path / "m.json"
    write_blocks_json(model, path)
    again = read_blocks_json(path)
    assert [b.id for b in again.blocks] == ["w", "s"]
    assert again.blocks[0].tags == ("wall",) and again.blocks[1].fixed
    assert again.blocks[0].volume == pytest.approx(2.0)
    np.testing.assert_allclose(again.loads[0].force, [0, -10, 0])
    assert json.loads(path.read_text())["format"] == "shapegen-blocks"


@pytest.mark.parametrize(
    ("message", "document"),
    [
        ('"format" must be', {"version": 1, "blocks": []}),
        ('unsupported "version"', _document(version=2)),
        ('missing required key "blocks"', {"format": "shapegen-blocks", "version": 1}),
        ('missing required key "vertices"', _document(blocks=[{"id": "x"}])),
        (
            "block 'x': \"density\" must be a finite number",
            _document(blocks=[{"id": "x", "vertices": CUBE, "density": "heavy"}]),
        ),
        ('"friction": friction must be a finite number >= 0; got -1.0', _document(friction=-1)),
        (
            "face \\[0, 1, 99\\]",
            _document(blocks=[{"id": "x", "vertices": CUBE, "faces": [[0, 1, 99]]}]),
        ),
        ("list of 3 numbers", _document(blocks=[{"id": "x", "vertices": [[0, 0]]}])),
        (
            'loads\\[0\\]: missing required key "force"',
            _document(loads=[{"block": "b0", "point": [0, 0, 0]}]),
        ),
    ],
)
def test_format_errors_name_the_place(message, document):
    with pytest.raises(InputFormatError, match=message):
        model_from_dict(document)


def test_load_on_missing_block_is_a_geometry_error():
    doc = _document(loads=[{"block": "nope", "force": [0, -1, 0], "point": [0, 0, 0]}])
    with pytest.raises(GeometryError, match="'nope'"):
        model_from_dict(doc)


def test_unreadable_and_invalid_files(tmp_path):
    with pytest.raises(InputFormatError, match="cannot read"):
        read_blocks_json(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": ')
    with pytest.raises(InputFormatError, match=r"bad.json:1:\d+: invalid JSON"):
        read_blocks_json(bad)


def test_binary_file_is_a_format_error(tmp_path):
    binary = tmp_path / "model.json"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(InputFormatError, match="not a text file"):
        read_blocks_json(binary)
