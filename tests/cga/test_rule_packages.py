"""CityEngine rule packages (.rpk, 7z archives): the start rule is the .cga whose compiled rule
has no '$' in its name; the package is unpacked once into the cache, where its imports and assets
resolve; a package that is not a 7z archive, that has no single start rule or whose members
would land outside its folder is refused with one line."""

from __future__ import annotations

import subprocess
import sys

import py7zr
import pytest

import shapegen
from shapegen.errors import GrammarError, ShapegenError

BOX = "".join(f"v {x} {y} {z}\n" for x in (0, 1) for y in (0, 2) for z in (0, 1)) + (
    "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n"
)
MAIN = (
    'import lib : "lib.cga"\n'
    'Lot --> extrude(lib.height) report("height", scope.sy) comp(f) { top : Roof | all : NIL }\n'
    'Roof --> report("size", assetInfo("assets/box.obj", sy)) NIL\n'
)


def _package(path, members: dict[str, str]):
    with py7zr.SevenZipFile(path, "w") as archive:
        for name, text in members.items():
            archive._writestr(text.encode(), name)  # unchecked: names a hostile package may hold
    return path


pytestmark = pytest.mark.usefixtures("package_cache")


def _building(tmp_path):
    return _package(
        tmp_path / "building.rpk",
        {
            "rules/building.cga": MAIN,
            "rules/lib.cga": "attr height = 7\n",
            "bin/building.cgb": "compiled",
            "bin/building$lib.cgb": "compiled import",
            "assets/box.obj": BOX,
        },
    )


def test_the_start_rule_loads_with_its_imports_and_assets(tmp_path):
    grammar = shapegen.load_grammar(_building(tmp_path))
    assert grammar.path.name == "building.cga"
    assert (tmp_path / "cache" / "packages").is_dir()
    model = grammar.build(lot=(4, 2))
    assert model.metadata["reports"]["size"] == 2.0  # the asset's height, found in the package
    assert model.metadata["reports"]["height"] == 7.0  # lib.height, imported from the package


def test_the_cli_builds_a_package(tmp_path):
    package = _building(tmp_path)
    out = tmp_path / "model.glb"
    done = subprocess.run(
        [sys.executable, "-m", "shapegen", "build", str(package), "--lot", "4,2", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    assert out.stat().st_size > 0


def test_a_package_without_one_start_rule_is_refused_naming_its_rules(tmp_path):
    package = _package(tmp_path / "p.rpk", {"rules/a.cga": "Lot --> X.", "rules/b.cga": "Y --> Z."})
    with pytest.raises(
        GrammarError, match=r"cannot tell its start rule .*rules/a.cga, rules/b.cga"
    ):
        shapegen.load_grammar(package)


@pytest.mark.parametrize(
    "name, message",
    [("../evil.cga", "outside the package"), ("/etc/evil", "outside the package"),
     ("..\\evil.cga", "outside the package")],
)  # fmt: skip
def test_members_outside_the_folder_are_refused(tmp_path, name, message):
    package = _package(tmp_path / "p.rpk", {"rules/a.cga": "Lot --> X.", name: "x"})
    with pytest.raises(ShapegenError, match=message):
        shapegen.load_grammar(package)
    assert not list((tmp_path / "cache" / "packages").iterdir())  # nothing half-unpacked


def test_a_file_that_is_not_a_package_is_one_line(tmp_path):
    fake = tmp_path / "fake.rpk"
    fake.write_text("Lot --> X.")
    with pytest.raises(ShapegenError, match="not a readable CityEngine rule package") as caught:
        shapegen.load_grammar(fake)
    assert "\n" not in str(caught.value)
