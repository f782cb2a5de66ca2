"""The functions that read a file of the rule's project (func_readTable, func_readTextFile,
func_assetInfo): a CSV table as a 2D array (delimiter detected, UTF-16 by its byte-order mark),
a text file as a string, an asset's bounding box. A file that is not found gives what
CityEngine's runtime gives (an empty table, as its log says "error, using empty table") and a
warning of the build, never a silent value."""

from __future__ import annotations

import pytest

import shapegen


def _project(tmp_path, rule: str, files: dict[str, bytes | str]):
    (tmp_path / "rules").mkdir()
    for name, content in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content, encoding="utf-8")
    rule_file = tmp_path / "rules" / "r.cga"
    rule_file.write_text(rule, encoding="utf-8")
    return shapegen.load_grammar(rule_file)


def _reports(grammar):
    model = grammar.build(lot=(4, 2))
    return model.metadata["reports"], model


TABLE = "name;height\noak;12.5\nbirch;9\n"


@pytest.mark.parametrize("encoding", ["utf-8", "utf-16"])
def test_a_table_reads_as_rows_and_columns(tmp_path, encoding):
    rule = (
        'const t = readStringTable("assets/trees.csv")\n'
        'const f = readFloatTable("assets/trees.csv")\n'
        'Lot --> report("rows", nRows(t)) report("columns", nColumns(t)) report("name", t[2, 0])'
        ' report("height", f[1, 1]) report("nan", isnan(f[1, 0])) X.\n'
    )
    grammar = _project(tmp_path, rule, {"assets/trees.csv": TABLE.encode(encoding)})
    reports, model = _reports(grammar)
    assert reports["rows"] == 3.0 and reports["columns"] == 2.0
    assert reports["name"] == "birch"
    assert reports["height"] == 12.5
    assert reports["nan"] is True
    assert not model.metadata.get("warnings")


def test_a_missing_table_is_empty_with_a_warning(tmp_path):
    rule = (
        'const t = readStringTable("assets/none.csv")\n'
        'Lot --> report("rows", nRows(t)) report("cell", t[1, 0] == "") X.\n'
    )
    reports, model = _reports(_project(tmp_path, rule, {}))
    assert reports["rows"] == 0.0
    assert reports["cell"] is True  # outside the table: the default string
    warnings = model.metadata["warnings"]
    assert any("readStringTable('assets/none.csv')" in w and "not found" in w for w in warnings)


def test_a_text_file_reads_whole(tmp_path):
    rule = 'Lot --> report("text", readTextFile("assets/notes.txt")) X.\n'
    reports, _ = _reports(_project(tmp_path, rule, {"assets/notes.txt": "a;b\nc"}))
    assert reports["text"] == "a;b\nc"


# a box from (-0.5, 0, 0.25) to (1.5, 3, 1.25): sizes 2, 3, 1
OBJ = "".join(f"v {x} {y} {z}\n" for x in (-0.5, 1.5) for y in (0, 3) for z in (0.25, 1.25)) + (
    "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n"
)


def test_asset_info_gives_the_bounding_box(tmp_path):
    axes = ("sx", "sy", "sz", "tx", "ty", "tz")
    rule = "Lot --> " + " ".join(f'report("{a}", assetInfo("assets/box.obj", {a}))' for a in axes)
    reports, _ = _reports(_project(tmp_path, rule + " X.\n", {"assets/box.obj": OBJ}))
    assert [reports[a] for a in axes] == [2.0, 3.0, 1.0, -0.5, 0.0, 0.25]


def test_asset_info_of_a_missing_asset_is_zero_with_a_warning(tmp_path):
    rule = 'Lot --> report("sx", assetInfo("assets/none.obj", sx)) X.\n'
    reports, model = _reports(_project(tmp_path, rule, {}))
    assert reports["sx"] == 0.0
    assert any("assetInfo('assets/none.obj', sx)" in w for w in model.metadata["warnings"])


def test_asset_info_needs_an_axis(tmp_path):
    grammar = _project(tmp_path, 'Lot --> report("a", assetInfo("x.obj", 1)) X.\n', {})
    with pytest.raises(shapegen.errors.GrammarError, match="one of sx, sy, sz, tx, ty, tz"):
        grammar.build(lot=(4, 2))


def test_image_info_gives_the_resolution(tmp_path):
    from PIL import Image

    (tmp_path / "assets").mkdir()
    Image.new("RGB", (64, 32)).save(tmp_path / "assets" / "tile.png")
    rule = (
        'Lot --> report("w", imageInfo("assets/tile.png", sx)) '
        'report("h", imageInfo("assets/tile.png", sy)) report("none", imageInfo("no.png", sx)) X.\n'
    )
    reports, model = _reports(_project(tmp_path, rule, {}))
    assert (reports["w"], reports["h"], reports["none"]) == (64.0, 32.0, 0.0)
    assert any("imageInfo('no.png', sx)" in w for w in model.metadata["warnings"])


def test_asset_metadata_of_an_obj_is_the_default(tmp_path):
    rule = 'Lot --> report("m", assetMetadata("assets/box.obj", "height", 2.5)) X.\n'
    reports, _ = _reports(_project(tmp_path, rule, {"assets/box.obj": OBJ}))
    assert reports["m"] == 2.5


def test_asset_metadata_of_a_gltf_is_refused_in_one_line(tmp_path):
    grammar = _project(
        tmp_path,
        'Lot --> report("m", assetMetadata("a.gltf", "k", 1)) X.\n',
        {"rules/a.gltf": "{}"},
    )
    with pytest.raises(shapegen.errors.GrammarError, match="metadata of .gltf assets"):
        grammar.build(lot=(4, 2))
