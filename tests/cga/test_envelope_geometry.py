"""envelope2002 on the 12 x 8 m lot against CityEngine's runtime (``prt_envelope.json`` says
how it was measured): a split piece's first edge (the vertical greenery's images take their
scope from it), ``reverseNormals`` (the interior walls are laid from the turned floor's
bottom) and a ``comp`` that chooses nothing (the ground floor plan's vanished inside)."""

import json
from pathlib import Path

import numpy as np
import pytest

import shapegen.prt as prt

HERE = Path(__file__).resolve().parent
MEASURED = json.loads((HERE / "prt_envelope.json").read_text())
ENVELOPE = (
    HERE.parent / "data" / "cga-corpus" / "tests_data_envelope2002__3bb69433" / "rules"
    / "typology" / "envelope2002.cga"
)  # fmt: skip


def generated(seed: int, **attrs):
    (model,) = prt.ModelGenerator([prt.InitialShape(MEASURED["lot"])]).generate_model(
        [{"seed": seed, **attrs}], str(ENVELOPE)
    )
    return model


def faces_of(model):
    vertices = np.asarray(model.get_vertices()).reshape(-1, 3)
    indices, at = model.get_indices(), 0
    for count in model.get_faces():
        yield vertices[indices[at : at + count]]
        at += count


def test_greenery_images_begin_where_cityengine_begins_them():
    model = generated(0, report_but_not_display_green=True)
    images = sorted(
        (
            face
            for face in faces_of(model)
            if len(face) == 4 and np.ptp(face[:, 2]) < 1e-6 and abs(face[0, 2] - 6.62) < 0.03
        ),
        key=lambda face: face[0, 2],
    )
    assert len(images) == len(MEASURED["images"])
    for face, measured in zip(images, MEASURED["images"], strict=True):
        assert face[0, 2] == pytest.approx(measured["z"], abs=1e-4)
        # corner by corner in order: the first edge, and so the image's scope, as PyPRT's
        assert np.abs(face[:, :2] - np.array(measured["corners"])).max() < 1e-3


@pytest.mark.parametrize(
    "seed",
    [0, pytest.param(1, marks=pytest.mark.slow), pytest.param(2, marks=pytest.mark.slow)],
)
def test_counts_as_cityengine(seed):
    model = generated(seed)
    measured = MEASURED["counts"][str(seed)]
    assert len(model.get_vertices()) // 3 == measured["vertices"]
    assert len(model.get_faces()) == measured["faces"]
