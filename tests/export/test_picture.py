"""Pictures: exact occlusion, a model that fills the frame, the tension legend, safe output.

The PNG files are decoded with Pillow and judged by their pixels.
"""

from __future__ import annotations

import io
import re
from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

from shapegen import Block, Model
from shapegen.errors import InputFormatError
from shapegen.export import picture
from shapegen.export.colors import TENSION_MAX
from shapegen.export.picture import TENSION_LEGEND, encode_picture, model_figure, render_model
from shapegen.export.render import render_blocks

RED = [220, 30, 30, 255]
BLUE = [30, 60, 220, 255]
GREY = [160, 160, 160, 255]


def pixels(content: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(content)).convert("RGB")).astype(int)


def reddish(rgb) -> bool:
    return rgb[0] > 120 and rgb[1] < 60 and rgb[2] < 60


def bluish(rgb) -> bool:
    return rgb[2] > 120 and rgb[0] < 60


def near_and_far() -> tuple[Block, Block]:
    """A small box at z in [0, 1] in front of a wide one at z in [-4, -3]; seen from +z they
    overlap around x = 0, y = 1."""
    near = Block.box([-0.5, 0.5, 0.0], [0.5, 1.5, 1.0], id="near")
    far = Block.box([-1.0, 0.0, -4.0], [1.0, 2.0, -3.0], id="far")
    return near, far


@pytest.mark.parametrize("near_first", [True, False])
@pytest.mark.parametrize("view", [(0.0, -90.0), (15.0, -80.0)])
def test_the_nearer_block_hides_the_farther_whatever_their_order(near_first, view):
    near, far = near_and_far()
    blocks, colors = ([near, far], [RED, BLUE]) if near_first else ([far, near], [BLUE, RED])
    elevation, azimuth = view
    rendering = render_blocks(
        Model(blocks, ground=None),
        np.array(colors),
        size_px=(200, 200),
        elevation=elevation,
        azimuth=azimuth,
    )
    rgb = rendering.rgb
    if view == (0.0, -90.0):  # straight on: the frame is the far box, 2 x 2 m, centred
        assert reddish(rgb[100, 100])  # x = 0, y = 1: both boxes; the near one shows
        assert bluish(rgb[100, 180])  # x = 0.8: only the far box
    # Whatever the view, the red box is drawn whole and the blue one only around it.
    red = np.array([reddish(p) for p in rgb.reshape(-1, 3)]).reshape(rgb.shape[:2])
    alone = render_blocks(
        Model([near], ground=None), np.array([RED]), size_px=(200, 200),
        elevation=elevation, azimuth=azimuth, bounds=_bounds(near, far),
    )  # fmt: skip
    red_alone = np.array([reddish(p) for p in alone.rgb.reshape(-1, 3)]).reshape(red.shape)
    assert red.sum() >= 0.97 * red_alone.sum()


def _bounds(*blocks: Block) -> np.ndarray:
    points = np.vstack([b.vertices for b in blocks])
    return np.array([points.min(axis=0), points.max(axis=0)])


def test_a_joint_behind_a_nearer_block_is_not_drawn_over_it():
    # Two grey blocks side by side meet at x = 0 (a joint, drawn as a dark line), behind a red
    # block that covers the joint's middle: the line stops at the red block.
    left = Block.box([-2.0, 0.0, -3.0], [0.0, 2.0, -2.0], id="left")
    right = Block.box([0.0, 0.0, -3.0], [2.0, 2.0, -2.0], id="right")
    near = Block.box([-0.5, 0.5, 0.0], [0.5, 1.5, 1.0], id="near")
    rgb = render_blocks(
        Model([left, right, near], ground=None),
        np.array([GREY, GREY, RED]),
        size_px=(200, 200),
        elevation=0.0,
        azimuth=-90.0,
    ).rgb
    # 44 px/m (the 4 m wall spans 88% of 200 px); y = 2 m at row 56, the red block's top and
    # bottom (y = 1.5 and 0.5 m) at rows 78 and 122; the joint x = 0 at the column 100.
    joint = rgb[:, 99:101].min(axis=1).max(axis=1)  # the brightest channel of the darker side
    plain = rgb[:, 60].max(axis=1)  # the wall away from the joint
    assert (joint[60:75] < 0.85 * plain[60:75]).all()  # the joint is drawn above the red block
    assert all(reddish(p) for p in rgb[82:118, 99:101].reshape(-1, 3))  # but not across it


def wall() -> Model:
    return Model([Block.box([x, 0.0, 0.0], [x + 1.0, 0.5, 0.4], id=f"s{x}") for x in range(8)])


def tower() -> Model:
    return Model([Block.box([0.0, y, 0.0], [1.0, y + 1.0, 1.0], id=f"t{y}") for y in range(12)])


@pytest.mark.parametrize("model", [wall(), tower()], ids=["wide", "tall"])
def test_the_model_fills_the_frame(model):
    model.ground = None  # what is not background is the model
    rgb = pixels(encode_picture(model, legend=False, size_px=(400, 300)))
    ys, xs = np.nonzero((rgb < 250).any(axis=2))
    width = (xs.max() - xs.min() + 1) / rgb.shape[1]
    height = (ys.max() - ys.min() + 1) / rgb.shape[0]
    assert max(width, height) >= 0.8
    assert max(width, height) <= 0.95  # and leaves a margin
    # With the ground, a title and a legend, the blocks still fill their part of the picture.
    model.ground = 0.0
    rendering = render_blocks(model, np.array([GREY] * len(model.blocks)), size_px=(320, 285))
    ys, xs = np.nonzero(rendering.coverage > 0)
    assert max((np.ptp(xs) + 1) / 320, (np.ptp(ys) + 1) / 285) >= 0.8


def test_the_ground_is_drawn_under_the_model():
    model = wall()
    with_ground = render_blocks(model, np.array([GREY] * 8), size_px=(200, 150))
    without = render_blocks(model, np.array([GREY] * 8), size_px=(200, 150), ground=False)
    changed = (with_ground.rgb != without.rgb).any(axis=2)
    assert changed.sum() > 0.05 * changed.size  # a patch of ground around the footprint
    assert (with_ground.coverage == without.coverage).all()  # it never covers a block


def stub_analysis(tension, feasible):
    return SimpleNamespace(
        block_tension=np.array(tension, float), feasible=feasible, total_weight=1e5
    )


def red_pixels(rgb: np.ndarray) -> int:
    return int((np.abs(rgb - TENSION_MAX[:3]).max(axis=2) < 12).sum())


def test_the_tension_legend_is_a_colour_bar_in_newtons():
    model = wall()
    # A standing model: no block is red, so red pixels can only be the colour bar's top.
    standing = stub_analysis([0.0] * 8, feasible=True)
    small = {"size_px": (400, 300)}
    assert red_pixels(pixels(encode_picture(model, standing, **small))) > 50
    assert red_pixels(pixels(encode_picture(model, **small))) == 0
    figure = model_figure(model, stub_analysis([0, 0, 0, 4e4, 2e4, 0, 0, 0], feasible=False))
    (bar,) = [axes for axes in figure.axes if axes.get_label() == TENSION_LEGEND]
    assert [t.get_text() for t in bar.get_yticklabels()] == ["0", "20 kN", "40 kN"]
    assert not [a for a in model_figure(model).axes if a.get_label() == TENSION_LEGEND]


def test_the_label_legend_names_the_labels():
    blocks = [
        Block.box([0, 0, 0], [1, 1, 1], id="a", tags=("pier",)),
        Block.box([0, 1, 0], [1, 2, 1], id="b", tags=("arch",)),
        Block.box([0, 2, 0], [1, 3, 1], id="c", tags=("pier",)),
    ]
    (legend,) = model_figure(Model(blocks)).legends
    assert [t.get_text() for t in legend.get_texts()] == ["pier", "arch"]


def test_the_picture_is_written_atomically(tmp_path, monkeypatch):
    path = tmp_path / "wall.png"
    path.write_bytes(b"old")
    with pytest.raises(ValueError, match="block tensions"):
        render_model(wall(), path, stub_analysis([1.0], feasible=False))  # 1 tension, 8 blocks
    assert path.read_bytes() == b"old" and sorted(tmp_path.iterdir()) == [path]
    targets = []
    real = picture.atomic_write

    def spy(target, mode="w"):
        targets.append(target)
        return real(target, mode)

    monkeypatch.setattr(picture, "atomic_write", spy)
    render_model(wall(), path)
    assert targets == [path] and path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(tmp_path.iterdir()) == [path]


@pytest.mark.parametrize("where", ["missing/wall.png", "."])
def test_a_bad_path_is_a_clean_error(tmp_path, where):
    with pytest.raises(InputFormatError, match="folder"):
        render_model(wall(), tmp_path / where)


def test_an_empty_model_gives_a_blank_picture():
    rgb = pixels(encode_picture(Model([])))
    assert (rgb == 255).all()


def test_two_triangles_sharing_an_edge_leave_no_crack():
    from shapegen.export.render import _rasterize

    # A square cut along its diagonal x + y = 600, which passes through sample centres.
    square = np.array(
        [[[168.0, 432.0], [432.0, 432.0], [432.0, 168.0]],
         [[168.0, 432.0], [432.0, 168.0], [168.0, 168.0]]]
    )  # fmt: skip
    depth, seen = _rasterize(square, np.zeros((2, 3)), 600, 600)
    inside = seen[168:432, 168:432]
    assert (inside >= 0).all() and set(np.unique(inside)) == {0, 1}
    assert (seen[:168] == -1).all() and (seen[:, 432:] == -1).all()


def test_the_example_in_the_formats_page_runs(tmp_path, monkeypatch):
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "formats.md").read_text()
    section = text[text.index("## Pictures") :]
    start = section.index("```python\n") + len("```python\n")
    example = section[start : section.index("```\n", start)]
    monkeypatch.chdir(tmp_path)
    exec(compile(example, "formats.md", "exec"), {})
    assert Image.open(tmp_path / "arch.png").size == (800, 600)
    assert Image.open(tmp_path / "arch_tension.png").size == (1000, 700)


def test_a_picture_too_large_for_memory_is_refused_before_any_work():
    with pytest.raises(ValueError, match="million pixels"):
        render_blocks(wall(), np.array([GREY] * 8), size_px=(10_000, 10_000))


def test_build_writes_a_picture_coloured_by_tension(tmp_path, capsys):
    from shapegen.cli import main

    path = tmp_path / "arch.png"
    # The file's arch on narrow columns needs tension: red blocks and the colour bar.
    assert main(["build", "arch_columns.grammar", "--analyze", "--picture", str(path), "-q"]) == 0
    rgb = np.asarray(Image.open(path).convert("RGB")).astype(int)
    view = rgb[:, :600]  # left of the legend strip (the right 160 of 800 pixels)
    red = (view[:, :, 0] > 120) & (view[:, :, 1] < 60) & (view[:, :, 2] < 60)
    assert red.sum() > 2000


@pytest.mark.parametrize(
    "where, message",
    [("arch.jpg", "--picture .*arch.jpg: a picture is written as .png"),
     ("missing/arch.png", "--picture .*missing/arch.png: folder .* does not exist")],
)  # fmt: skip
def test_build_refuses_a_bad_picture_path_in_one_line(tmp_path, capsys, where, message):
    from shapegen.cli import main

    assert main(["build", "arch_columns.grammar", "--picture", str(tmp_path / where)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and re.search(message, err)
    assert list(tmp_path.iterdir()) == []
