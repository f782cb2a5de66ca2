"""Model.validate checks a model once until something it looks at changes."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

from shapegen.errors import GeometryError
from shapegen.model.block import Block
from shapegen.model.model import Model, PointLoad


def _model() -> Model:
    blocks = [Block.box([0, k, 0], [1, k + 1, 1], id=f"b{k}") for k in range(3)]
    return Model(blocks, [PointLoad("b2", [0, -10, 0], [0.5, 3, 0.5])])


@pytest.fixture
def counted(monkeypatch):
    calls = []
    checks = Model._checks

    def counting(self):
        calls.append(self)
        checks(self)

    monkeypatch.setattr(Model, "_checks", counting)
    return calls


def test_an_unchanged_model_is_checked_once(counted):
    model = _model()
    model.validate()
    model.validate()
    assert len(counted) == 1


def _nan_vertex(model):
    model.blocks[1].vertices[0, 0] = np.nan


def _negative_density(model):
    model.blocks[1].density = -1.0


def _duplicate_id(model):
    model.blocks[2].id = "b0"


def _flat_block(model):
    model.blocks.append(Block.from_hull(np.eye(3).tolist() + [[0, 0, 0]], id="x"))
    model.blocks[-1].vertices[:, 2] = 0.0


def _bad_load(model):
    model.loads[0].force[1] = np.inf


def _unknown_load(model):
    model.loads.append(PointLoad("nowhere", [0, -1, 0], [0, 0, 0]))


def _reversed_faces(model):
    block = model.blocks[0]
    block.faces = tuple(tuple(reversed(face)) for face in block.faces)


@pytest.mark.parametrize(
    "change",
    [_nan_vertex, _negative_density, _duplicate_id, _flat_block, _bad_load, _unknown_load,
     _reversed_faces],
)  # fmt: skip
def test_a_change_after_validation_is_caught(change):
    model = _model()
    model.validate()
    change(model)
    with pytest.raises(GeometryError):
        model.validate()


def test_copies_and_pickles_carry_no_record(counted):
    model = _model()
    model.validate()
    assert "_validated" not in pickle.loads(pickle.dumps(model)).__dict__
    assert "_validated" not in copy.deepcopy(model).__dict__
