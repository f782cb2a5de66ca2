"""The page's label colours: each label of a model its own, none like the tension red."""

import itertools
import zlib

import numpy as np
import pytest

from shapegen.editor import EditorSession
from shapegen.editor.scene import LABEL_COLOURS, label_colours
from shapegen.export.colors import NON_STRUCTURAL, SUPPORT, TENSION_MAX, TENSION_ZERO


def lab(rgb) -> np.ndarray:
    """CIE L*a*b* (D65) of sRGB colours given as 0-255 components."""
    c = np.asarray(rgb, float)[..., :3] / 255.0
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    to_xyz = np.array(
        [[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]
    )
    xyz = c @ to_xyz.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]),
                     200 * (f[..., 1] - f[..., 2])], axis=-1)  # fmt: skip


def delta_e(a, b) -> float:
    """CIE76 colour difference: about 2 is just noticeable, 20 clearly another colour."""
    return float(np.linalg.norm(lab(a) - lab(b)))


# the reddish part of the tension ramp: a quarter of the largest tension and more
TENSION_REDS = [TENSION_ZERO + t * (TENSION_MAX.astype(float) - TENSION_ZERO)
                for t in np.linspace(0.25, 1.0, 7)]  # fmt: skip


def test_the_label_colours_are_distinct_and_unlike_tension_and_supports():
    for a, b in itertools.combinations(LABEL_COLOURS, 2):
        assert delta_e(a, b) >= 20, (a, b)
    for colour in LABEL_COLOURS:
        assert min(delta_e(colour, red) for red in TENSION_REDS) >= 25, colour
        assert delta_e(colour, SUPPORT) >= 25 and delta_e(colour, NON_STRUCTURAL) >= 25, colour


def test_each_label_gets_its_own_colour():
    labels = [f"label {k}" for k in range(len(LABEL_COLOURS))]
    colours = label_colours(labels)
    assert len({tuple(c) for c in colours.values()}) == len(labels)
    # on its own a label always has the colour its text hashes to, in every model and run
    slot = zlib.crc32(b"wall") % len(LABEL_COLOURS)
    assert label_colours(["wall"])["wall"] == LABEL_COLOURS[slot].tolist()
    # more labels than colours: the colours repeat, but every label still has one
    many = label_colours([f"part {k}" for k in range(3 * len(LABEL_COLOURS))])
    assert len(many) == 3 * len(LABEL_COLOURS)


@pytest.mark.slow  # cluny: about 1 000 blocks, 3-5 s
def test_clunys_labels_each_have_their_own_colour():
    session = EditorSession("cluny.grammar", scan=False)
    try:
        scene = session.scene()
    finally:
        session.close()
    legend = dict((label, tuple(colour)) for label, colour in scene["legend"]["labels"])
    assert {"aisle vault", "wall", "nave vault"} <= set(legend)
    assert legend["aisle vault"] != legend["wall"]
    assert len(set(legend.values())) == len(legend)
    for block in scene["blocks"]:
        if block["label"] in legend and block["color"] != SUPPORT.tolist():
            assert tuple(block["color"]) == legend[block["label"]]
