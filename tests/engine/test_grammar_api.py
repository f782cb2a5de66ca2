"""load_grammar, Grammar, bundled rules, and wall_windows.grammar (seed paper, Figure 3)."""

import math
from pathlib import Path

import pytest

import shapegen
from shapegen.engine.project.rules_path import find_bundled_rule
from shapegen.errors import GrammarError
from shapegen.primitives import available

SMALL = "@StartRule @Lot(2, 1)\nLot --> extrude(1) Box.\n"


def test_parse_text_and_load_a_file(tmp_path):
    path = tmp_path / "small.grammar"
    path.write_text(SMALL)
    grammars = [shapegen.parse_grammar(SMALL), *map(shapegen.load_grammar, (str(path), path))]
    for grammar in grammars:
        assert len(grammar.build().blocks) == 1
    assert shapegen.load_grammar(path).name == str(path)
    assert shapegen.parse_grammar(SMALL).name == "<string>"


def test_errors_name_the_file(tmp_path):
    path = tmp_path / "broken.grammar"
    path.write_text("Lot --> extrude(1 / 0)\n")
    with pytest.raises(GrammarError, match=r"broken\.grammar:1:"):
        shapegen.load_grammar(str(path)).build()


def test_bare_name_falls_back_to_the_bundled_rules(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    grammar = shapegen.load_grammar("wall_windows.grammar")
    assert grammar.path == find_bundled_rule("wall_windows.grammar")
    # A file of that name in the working directory wins.
    (tmp_path / "wall_windows.grammar").write_text(SMALL)
    assert len(shapegen.load_grammar("wall_windows.grammar").build().blocks) == 1


def test_missing_file_lists_the_bundled_rules(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(GrammarError, match="wall_windows.grammar"):
        shapegen.load_grammar("no_such_file.grammar")
    with pytest.raises(GrammarError, match="no grammar file"):
        shapegen.load_grammar(str(tmp_path / "sub" / "x.grammar"))


def test_bundled_rules_lists_the_files():
    names = shapegen.bundled_rules()
    assert "wall_windows.grammar" in names
    assert names == sorted(names)
    assert all(find_bundled_rule(name).is_file() for name in names)


# ---------------------------------------------------------------------------- wall_windows
WALL = "wall_windows.grammar"


def wall_volume(length, height, thickness, abutment, windows, pier, column_height, segments):
    """Closed form: the wall less its openings (a rectangle below the springing and half of a
    regular polygon inscribed in the intrados circle above it), columns at full depth."""
    bay = (length - 2 * abutment) / windows
    radius = bay / 2 - pier
    rectangle = (bay - 2 * pier) * column_height
    half_polygon = segments * 0.5 * radius**2 * math.sin(math.pi / segments)
    return (length * height - windows * (rectangle + half_polygon)) * thickness


@pytest.mark.skipif("capped_arch" not in available(), reason="capped_arch not registered")
@pytest.mark.parametrize(
    "attrs, windows, pier, segments",
    [
        ({}, 4, 0.5, 9),
        ({"pier_width": 0.3, "arch_segments": 12}, 4, 0.3, 12),
        ({"windows": 3}, 3, 0.5, 9),
    ],
)
def test_wall_windows_volume_and_parts(attrs, windows, pier, segments):
    grammar = shapegen.load_grammar(WALL)
    model = grammar.build(attrs=attrs)
    model.validate()
    expected = wall_volume(12, 6, 0.6, 1.0, windows, pier, 2.5, segments)
    assert model.volume == pytest.approx(expected, rel=1e-9)
    tags = [b.tags[0] for b in model.blocks]
    assert tags.count("column") == 2 * windows
    assert tags.count("base") == tags.count("top") == windows
    assert tags.count("abutment") == 2
    assert sum("voussoir" in b.tags for b in model.blocks) == segments * windows
    assert model.metadata["reports"]["bays"] == windows
    # Every block stands inside the 12 x 6 x 0.6 wall.
    for block in model.blocks:
        lo, hi = block.bounds
        assert lo.min() >= -1e-9 and hi[0] <= 12 + 1e-9 and hi[1] <= 6 + 1e-9
        assert hi[2] <= 0.6 + 1e-9


def test_wall_windows_free_parameters():
    grammar = shapegen.load_grammar(WALL)
    free = grammar.free_parameters
    assert set(free) == {"pier_width", "column_depth"}
    for entry in free.values():
        assert entry["min"] <= entry["value"] <= entry["max"]
    assert grammar.lot == (12.0, 0.6)


@pytest.mark.skipif("capped_arch" not in available(), reason="capped_arch not registered")
def test_wall_windows_columns_are_scaled_in_depth_and_centred():
    model = shapegen.load_grammar(WALL).build(attrs={"column_depth": 0.5})
    columns = [b for b in model.blocks if "column" in b.tags]
    for block in columns:
        lo, hi = block.bounds
        assert (lo[2], hi[2]) == pytest.approx((0.15, 0.45))


def test_bundled_rules_all_load():
    for name in shapegen.bundled_rules():
        grammar = shapegen.load_grammar(name)
        assert isinstance(grammar.attrs, dict)


def test_rules_directory_is_the_top_level_one():
    path = find_bundled_rule("wall_windows")
    assert path is not None and path.parent.name == "rules"
    assert (Path(shapegen.__file__).resolve().parent.parent / "rules").is_dir()


def test_a_bundled_rule_package_resolves_by_its_bare_name(tmp_path, monkeypatch):
    from shapegen.engine.project.rule_packages import package_named

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("SHAPEGEN_CACHE", str(tmp_path / "cache"))
    assert "parthenon.rpk" in shapegen.bundled_rules()
    package = find_bundled_rule("parthenon.rpk")
    assert package is not None and package.parent.name == "rules"
    assert find_bundled_rule("parthenon") == package  # no .grammar of that name: the package
    grammar = shapegen.load_grammar("parthenon.rpk")
    assert grammar.path.name == "parthenon.cga"  # the package's start rule, unpacked
    assert grammar.attrs["Diameter"] == pytest.approx(1.92)
    assert package_named("parthenon.rpk") == package.resolve()
    assert package_named("elsewhere/parthenon.rpk") is None  # a path names no bundled file


def test_every_bundled_package_has_its_provenance_and_licence():
    from shapegen.cli.rules import description

    packages = [name for name in shapegen.bundled_rules() if name.endswith(".rpk")]
    assert packages
    for name in packages:
        path = find_bundled_rule(name)
        assert description(path).endswith("."), name
        assert (path.parent / "LICENSE-pyprt").read_text().lstrip().startswith("Apache License")
