"""celib's asset and image choosers (assetBestSize, assetApproxSize, assetFitSize,
assetBestRatio, assetApproxRatio, imageBestRatio, imageApproxRatio) and the sorting functions
under them (assetsSortSize, assetsSortRatio, imagesSortRatio): the reference names the axes
compared, not the measure; shapegen's (the log of the scale factors) is checked here on assets
whose sizes make the order plain, and said in a warning."""

from __future__ import annotations

import pytest
import trimesh
from PIL import Image

from shapegen import load_grammar

COVERS = {
    "test_the_best_size_along_the_axes_named": ("func:assetBestSize", "func:assetsSortSize"),
    "test_approximate_and_fit_choices_draw_among_the_best": (
        "func:assetApproxSize",
        "func:assetFitSize",
    ),
    "test_ratios_of_assets_and_images": (
        "func:assetBestRatio",
        "func:assetApproxRatio",
        "func:assetsSortRatio",
        "func:imageBestRatio",
        "func:imageApproxRatio",
        "func:imagesSortRatio",
    ),
}

SIZES = {"small": (1, 1, 1), "mid": (4, 1, 4), "big": (10, 1, 10), "long": (8, 1, 3)}


@pytest.fixture
def project(tmp_path):
    (tmp_path / "rules").mkdir()
    (tmp_path / "assets" / "images").mkdir(parents=True)
    for name, size in SIZES.items():
        trimesh.creation.box(extents=size).export(tmp_path / "assets" / f"box_{name}.obj")
    for name, size in {"wide": (200, 100), "square": (100, 100)}.items():
        Image.new("RGB", size).save(tmp_path / "assets" / "images" / f"{name}.png")
    return tmp_path


def _value(project, expression: str, lot=(5.0, 5.0)) -> tuple[str, list[str]]:
    """The string ``expression`` gives on the lot, read back from a report."""
    path = project / "rules" / "pick.cga"
    path.write_text(f'@StartRule\nLot --> report("pick", {expression}) X.\n')
    model = load_grammar(path).build(lot=lot)
    return model.metadata["reports"]["pick"], model.metadata["warnings"]


def _names(listing: str) -> list[str]:
    return [item.rsplit("_", 1)[1].split(".")[0] for item in listing.split(";") if item]


def test_the_best_size_along_the_axes_named(project):
    # a 5 x 5 lot: the 4 x 4 box is scaled least in x and z; the long one in x alone
    best, warnings = _value(project, 'assetBestSize("assets/box_*.obj", "xz")')
    assert best.endswith("box_mid.obj")
    assert any("shapegen's is the sum over the axes" in w for w in warnings)
    assert _value(project, 'assetBestSize("assets/box_*.obj", "x")')[0].endswith("box_mid.obj")
    long, _ = _value(project, 'assetBestSize("assets/box_*.obj", "x")', lot=(8.0, 1.0))
    assert long.endswith("box_long.obj")
    listing, _ = _value(project, 'assetsSortSize(fileSearch("assets/box_*.obj"), xz, 0)')
    assert _names(listing) == ["mid", "long", "big", "small"]
    # at most 30 % of scaling: only the 4 x 4 box (5 / 4 = 1.25) is kept
    listing, _ = _value(project, 'assetsSortSize(fileSearch("assets/box_*.obj"), xz, 0.3)')
    assert _names(listing) == ["mid"]


def test_approximate_and_fit_choices_draw_among_the_best(project):
    seen = set()
    # seeds apart: CityEngine's generator gives consecutive seeds close first draws
    for seed in range(0, 1200, 100):
        path = project / "rules" / "pick.cga"
        path.write_text('@StartRule\nLot --> report("pick", '
                        'assetApproxSize("assets/box_*.obj", "xz", 2)) X.\n')  # fmt: skip
        model = load_grammar(path).build(lot=(5.0, 5.0), seed=seed)
        seen.add(_names(model.metadata["reports"]["pick"] + ";")[0])
    assert seen == {"mid", "long"}  # the two best, drawn by the seed
    assert _names(_value(project, 'assetFitSize("assets/box_*.obj", "xz", 0.3)')[0] + ";") == [
        "mid"
    ]
    # nothing matches: the empty name (i("") inserts the box of an asset not found)
    assert _value(project, 'assetBestSize("assets/none_*.obj", "xz")')[0] == ""


def test_ratios_of_assets_and_images(project):
    lot = (8.0, 2.0)  # x : z = 4
    best, _ = _value(project, 'assetBestRatio("assets/box_*.obj", "xz")', lot=lot)
    assert best.endswith("box_long.obj")
    listing, _ = _value(project, 'assetsSortRatio(fileSearch("assets/box_*.obj"), xz)', lot=lot)
    assert _names(listing)[0] == "long" and set(_names(listing)) == set(SIZES)
    approx, _ = _value(project, 'assetApproxRatio("assets/box_*.obj", "xz", 1)', lot=lot)
    assert approx == best
    # a 10 x 5 lot (x : z = 2) takes the 200 x 100 image; z : x (0.5) neither better than square
    wide, warnings = _value(project, 'imageBestRatio("assets/images/*.png", "xz")', lot=(10, 5))
    assert wide.endswith("wide.png")
    assert any(w.startswith("imageBestRatio(): the reference does not give") for w in warnings)
    listing, _ = _value(project, 'imagesSortRatio(fileSearch("assets/images/*.png"), zx)',
                        lot=(10, 5))  # fmt: skip
    assert [p.rsplit("/", 1)[1] for p in listing.split(";") if p] == ["square.png", "wide.png"]
    same, _ = _value(project, 'imageApproxRatio("assets/images/*.png", "xz", 1)', lot=(10, 5))
    assert same == wide


def test_bad_axes_are_one_line_errors(project):
    with pytest.raises(Exception, match="the axes are one of x, y, z, xy"):
        _value(project, 'assetBestSize("assets/box_*.obj", "w")')
