"""The label colours, one palette for the page and the exports: each label of a model its own,
none like the tension red."""

import itertools
import json
import struct
import zlib

import numpy as np
import pytest

from shapegen import pipeline
from shapegen.city.outputs import _block_colors as _city_colors
from shapegen.cli import main
from shapegen.editor import EditorSession
from shapegen.export.colors import (
    LABEL_PALETTE,
    NON_STRUCTURAL,
    SUPPORT,
    TENSION_MAX,
    TENSION_ZERO,
    display_color,
    label_color,
    label_colors,
    model_label_colors,
)
from shapegen.export.picture import _label_colors as _picture_colors
from shapegen.export.picture import _label_entries
from shapegen.model import Block


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
    for a, b in itertools.combinations(LABEL_PALETTE, 2):
        assert delta_e(a, b) >= 20, (a, b)
    for colour in LABEL_PALETTE:
        assert min(delta_e(colour, red) for red in TENSION_REDS) >= 25, colour
        assert delta_e(colour, SUPPORT) >= 25 and delta_e(colour, NON_STRUCTURAL) >= 25, colour


def test_each_label_gets_its_own_colour():
    labels = [f"label {k}" for k in range(len(LABEL_PALETTE))]
    colours = label_colors(labels)
    assert len({tuple(c) for c in colours.values()}) == len(labels)
    # on its own a label always has the colour its text hashes to, in every model and run
    slot = zlib.crc32(b"wall") % len(LABEL_PALETTE)
    assert label_colors(["wall"])["wall"].tolist() == LABEL_PALETTE[slot].tolist()
    assert label_color("wall").tolist() == LABEL_PALETTE[slot].tolist()  # the exports' choice
    # more labels than colours: the colours repeat, but every label still has one
    many = label_colors([f"part {k}" for k in range(3 * len(LABEL_PALETTE))])
    assert len(many) == 3 * len(LABEL_PALETTE)


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


def cube(label: str, **options) -> Block:
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    return Block.from_hull(corners, tags=(label,), **options)


def test_the_page_shows_the_colours_the_exports_give():
    # 'aisle vault' and 'wall' hash to one colour: given the model's assignment, an export
    # colours them as the page does, each its own; a support stays blue
    blocks = [cube("aisle vault"), cube("wall"), cube("pier", fixed=True)]
    assert label_color("aisle vault").tolist() == label_color("wall").tolist()
    colours = model_label_colors(blocks)
    assert set(colours) == {"aisle vault", "wall"}  # a support's label colours nothing
    exported = [display_color(b, colours).tolist() for b in blocks]
    assert exported[0] != exported[1] and exported[2] == SUPPORT.tolist()
    assert exported[0] == colours["aisle vault"].tolist()
    # a label alone in its colour: the same with or without the model's assignment
    (alone,) = [cube("buttress")]
    assert (
        display_color(alone).tolist() == display_color(alone, model_label_colors([alone])).tolist()
    )


# three labels whose names hash to one colour (tests above: 'aisle vault' and 'wall')
SHARED_HUE = """\
@StartRule @Lot(1, 1)
Lot --> extrude(3) split(y) { 1 : Wall | 1 : Vault | 1 : Capital }
Wall --> label("wall") i("box")
Vault --> label("aisle vault") i("box")
Capital --> label("capital") i("box")
"""


def glb_node_colors(content: bytes) -> dict[str, list[int]]:
    """Node name -> RGBA 0..255 of its mesh's material, from a binary glTF."""
    (length,) = struct.unpack_from("<I", content, 12)
    tree = json.loads(content[20 : 20 + length])
    colours = {}
    for node in tree["nodes"]:
        if "mesh" in node:
            primitive = tree["meshes"][node["mesh"]]["primitives"][0]
            factor = tree["materials"][primitive["material"]]["pbrMetallicRoughness"]
            colours[node["name"]] = [round(255 * c) for c in factor["baseColorFactor"]]
    return colours


def test_labels_sharing_a_hue_have_the_pages_colours_in_every_export(tmp_path):
    assert len({tuple(label_color(n)) for n in ("wall", "aisle vault", "capital")}) == 1
    rule = tmp_path / "shared.grammar"
    rule.write_text(SHARED_HUE, encoding="utf-8")
    session = EditorSession(str(rule), scan=False)
    try:
        scene = session.scene()
    finally:
        session.close()
    page = {block["id"]: block["color"] for block in scene["blocks"]}
    assert len({tuple(c) for c in page.values()}) == 3  # each label its own on the page
    # shapegen build -o x.glb: the label colours of the page
    glb = tmp_path / "shared.glb"
    assert main(["build", str(rule), "-o", str(glb), "-q"]) == 0
    assert glb_node_colors(glb.read_bytes()) == page
    # the picture (its blocks and its legend) and a city's scene
    model = pipeline.design(pipeline.load(str(rule))).model
    ids = [b.id for b in model.blocks]
    assert dict(zip(ids, _picture_colors(model).tolist(), strict=True)) == page
    legend = dict((label, list(colour)) for label, colour in _label_entries(model))
    assert legend == {b.tags[0]: page[b.id] for b in model.blocks}
    city = _city_colors(model, stands=True).tolist()
    assert dict(zip(ids, city, strict=True)) == page
