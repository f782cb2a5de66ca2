"""CityEngine's import (import.html): prefixed names, attr propagation, protection and
overrides, extension rules, paths, cycles and errors; and the corpus's rule files that import.

Small made-up rule files are written into ``tmp_path``; the corpus files are read from
``tests/data/cga-corpus`` (the packages' layout) and checked against PyPRT's reference figures
in ``tools/cga_reference``.
"""

import json
import re
from pathlib import Path

import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.errors import GrammarError
from shapegen.grammar import ast, load

ROOT = Path(__file__).resolve().parents[2]
CORPUS = ROOT / "tests" / "data" / "cga-corpus"
REFERENCE = ROOT / "tools" / "cga_reference"
LOT = (12.0, 8.0)

IMP = """
attr height = 10
const half = height / 2
double(x) = 2 * x
@StartRule
Lot --> extrude(height) report("height", scope.sy) report("half", half) Mass.
Twice --> extrude(double(height)) report("height", scope.sy) Mass.
Bump --> set(height, height + 1) Tall
Tall --> extrude(height) report("height", scope.sy) Mass.
"""


def _files(folder: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def _height(folder: Path, main: str, imported: str = IMP, key: str = "height") -> object:
    _files(folder, {"main.cga": main, "imp.cga": imported})
    return load_grammar(folder / "main.cga").build(lot=LOT).metadata["reports"][key]


# Names ----------------------------------------------------------------------------------------


def test_prefixed_rules_attrs_consts_and_functions(tmp_path):
    main = 'import imp : "imp.cga"\nattr top = imp.height * 3\nLot --> [ imp.Lot ] imp.Twice\n'
    _files(tmp_path, {"imp.cga": IMP, "main.cga": main})
    grammar = load_grammar(tmp_path / "main.cga")
    names = {d.name for d in grammar.ast.definitions}
    assert {"top", "imp.height", "imp.half", "imp.double", "imp.Lot", "imp.Twice"} <= names
    assert grammar.attrs["top"] == 30.0
    assert grammar.attrs["imp.height"] == 10.0
    reports = grammar.build(lot=LOT).metadata["reports"]
    assert reports == {"height": [10.0, 20.0], "half": 5.0}
    # references inside the imported file follow the rename: double(height) is imp.double(...)
    rule = next(d for d in grammar.ast.rules if d.name == "imp.Twice")
    call = rule.body.items[0].height
    assert isinstance(call, ast.Call) and call.name == "imp.double"
    assert call.args[0] == ast.Name("imp.height")
    # what nothing reaches is left out (after the checks), the imported attrs stay
    assert "imp.Bump" not in names and "imp.Tall" not in names


def test_a_selector_named_like_an_imported_attr_stays_a_selector(tmp_path):
    # shapeL's `shape` beside an `attr shape` of the imported file: the selector, as it is
    # when the file derives on its own (not the renamed attr `lu.shape`)
    lib = 'attr shape = "auto"\n@StartRule\nLot --> shapeL(3, 3) { shape : L. | remainder : R. }\n'
    _files(tmp_path, {"lib.cga": lib, "main.cga": 'import lu : "lib.cga"\nStart --> lu.Lot\n'})
    alone = load_grammar(tmp_path / "lib.cga").build(lot=LOT)
    imported = load_grammar(tmp_path / "main.cga").build(lot=LOT)
    assert imported.metadata["leaves"] == alone.metadata["leaves"] == 2
    assert load_grammar(tmp_path / "main.cga").attrs["lu.shape"] == "auto"


def test_set_of_a_prefixed_attr_reaches_the_imported_rules(tmp_path):
    main = 'import imp : "imp.cga"\nLot --> set(imp.height, 4) imp.Lot\n'
    assert _height(tmp_path, main) == 4.0
    main = 'import imp : "imp.cga"\nLot --> imp.Bump\n'  # the imported file's own set()
    assert _height(tmp_path, main) == 11.0


def test_imported_start_rule_is_ignored(tmp_path):
    _files(tmp_path, {"imp.cga": IMP, "main.cga": 'import imp : "imp.cga"\nInit --> imp.Lot\n'})
    grammar = load_grammar(tmp_path / "main.cga")
    assert grammar.ast.start_rule.name == "Init"
    assert not any(r.start for r in grammar.ast.rules)


# Attribute propagation (import.html: "Attribute redefinition by propagation") ----------------


@pytest.mark.parametrize(
    "main, height",
    [
        ('import imp : "imp.cga"\nattr height = 20\nLot --> imp.Lot', 20.0),  # propagated
        ('import imp : "imp.cga" (height)\nattr height = 20\nLot --> imp.Lot', 10.0),  # protected
        ('import imp : "imp.cga" ()\nattr height = 20\nLot --> imp.Lot', 10.0),  # all protected
        ('import imp : "imp.cga" (height = 20)\nLot --> imp.Lot', 20.0),  # overridden
        ('import imp : "imp.cga" (height = h + 1)\nattr h = 6\nLot --> imp.Lot', 7.0),
        # the override is evaluated in the importing file, with the imported attr's own value
        ('import imp : "imp.cga" (height = imp.height * 3)\nLot --> imp.Lot', 30.0),
        # CityEngine's special case: an importing attr may read the attr it propagates to
        ('import imp : "imp.cga"\nattr height = imp.height + 1\nLot --> imp.Lot', 11.0),
        ('import imp : "imp.cga"\nattr other = 20\nLot --> imp.Lot', 10.0),  # no such attr
    ],
)
def test_attr_propagation_protection_and_overrides(tmp_path, main, height):
    assert _height(tmp_path, main) == height


def test_propagated_attr_follows_set_attrs(tmp_path):
    _files(
        tmp_path,
        {"imp.cga": IMP, "main.cga": 'import imp : "imp.cga"\nattr height = 20\nLot --> imp.Lot'},
    )
    grammar = load_grammar(tmp_path / "main.cga")
    model = grammar.build(attrs={"height": 7}, lot=LOT)
    assert model.metadata["reports"]["height"] == 7.0
    assert grammar.build(attrs={"imp.height": 3}, lot=LOT).metadata["reports"]["height"] == 3.0


def test_imports_of_imports_propagate_one_level_at_a_time(tmp_path):
    _files(
        tmp_path,
        {
            "leaf.cga": "attr height = 1\nattr width = 1\n"
            'Box --> extrude(height) report("h", scope.sy) report("w", width) Mass.',
            "middle.cga": 'import leaf : "leaf.cga"\nattr height = 2\nGo --> leaf.Box',
            "main.cga": 'import mid : "middle.cga"\nattr height = 3\nattr width = 9\n'
            "Lot --> mid.Go",
        },
    )
    grammar = load_grammar(tmp_path / "main.cga")
    assert {"mid.leaf.Box", "mid.leaf.height", "mid.height"} <= set(grammar.attrs) | {
        r.name for r in grammar.ast.rules
    }
    reports = grammar.build(lot=LOT).metadata["reports"]
    # height: 3 -> mid.height -> mid.leaf.height; width is not defined in middle.cga, so the
    # main file's width does not reach leaf.cga (CityEngine's changelog, 2nd-level imports)
    assert reports == {"h": 3.0, "w": 1.0}


def test_import_without_prefix_merges_names_and_the_importer_wins(tmp_path):
    main = 'import "imp.cga"\nattr height = 3\nInit --> Lot'
    assert _height(tmp_path, main) == 3.0


def test_importer_defines_the_imported_files_missing_rule(tmp_path):
    imported = "Lot --> extrude(2) Slab\n"
    main = 'import imp : "imp.cga"\nInit --> imp.Lot\nimp.Slab --> report("slab", scope.sy) X.'
    assert _height(tmp_path, main, imported, key="slab") == 2.0


def test_extension_rule_redefined_in_the_import(tmp_path):
    imported = 'attr height = 10\nLot --> extrude(height) Roof\nextension Roof --> report("r", 1)'
    main = 'import imp : "imp.cga" (Roof --> report("r", 2) Mine)\nInit --> imp.Lot'
    assert _height(tmp_path, main, imported, key="r") == 2.0
    with pytest.raises(GrammarError, match="'Lot' of \"imp.cga\" is not an extension rule"):
        _height(tmp_path, 'import imp : "imp.cga" (Lot --> X)\nInit --> imp.Lot', imported)


# Paths ----------------------------------------------------------------------------------------


def test_paths_relative_to_the_file_its_project_and_the_workspace(tmp_path):
    project = tmp_path / "workspace" / "city"
    _files(
        project,
        {
            "rules/lib/imp.cga": IMP,
            "rules/main/a.cga": 'import imp : "../lib/imp.cga"\nInit --> imp.Lot',
            "rules/main/b.cga": 'import imp : "rules/lib/imp.cga"\nInit --> imp.Lot',
            "rules/main/c.cga": 'import imp : "/city/rules/lib/imp.cga"\nInit --> imp.Lot',
            "rules/main/d.cga": 'import t : "/shared.lib/rules/t.cga"\nInit --> t.Lot',
        },
    )
    _files(tmp_path / "workspace" / "shared.lib", {"rules/t.cga": IMP})
    for name in "abcd":
        grammar = load_grammar(project / "rules" / "main" / f"{name}.cga")
        assert grammar.build(lot=LOT).metadata["reports"]["height"] == 10.0


def test_a_package_keeps_other_projects_under_ws(tmp_path):
    _files(
        tmp_path,
        {
            ".ws/ESRI.lib/rules/t.cga": IMP,
            "rules/main.cga": 'import t : "/ESRI.lib/rules/t.cga"\nInit --> t.Lot',
        },
    )
    assert load_grammar(tmp_path / "rules" / "main.cga").build(lot=LOT).metadata["reports"]


def test_text_imports_resolve_against_the_working_directory(tmp_path, monkeypatch):
    _files(tmp_path, {"imp.cga": IMP})
    monkeypatch.chdir(tmp_path)
    grammar = parse_grammar('import imp : "imp.cga"\nInit --> imp.Lot', "text.cga")
    assert grammar.build(lot=LOT).metadata["reports"]["height"] == 10.0


# Errors ---------------------------------------------------------------------------------------


def test_missing_file_names_the_import_line_and_the_paths_tried(tmp_path):
    _files(tmp_path, {"main.cga": 'attr a = 1\nimport imp : "nowhere.cga"\nInit --> imp.Lot'})
    with pytest.raises(GrammarError) as caught:
        load_grammar(tmp_path / "main.cga")
    first = str(caught.value).splitlines()[0]
    assert first.startswith(f"{tmp_path / 'main.cga'}:2:8: ")
    assert 'import of "nowhere.cga": no such file (tried ' in first
    assert str(tmp_path / "nowhere.cga") in first
    # one problem: the names the missing file would have defined are not listed after it
    assert len(caught.value.problems) == 1


def test_cycles_are_one_error_at_the_import_line(tmp_path):
    _files(
        tmp_path,
        {
            "a.cga": 'import b : "b.cga"\nInit --> b.Lot',
            "b.cga": 'import a : "a.cga"\nLot --> X',
        },
    )
    with pytest.raises(
        GrammarError,
        match=r"b.cga:1:8: import of \"a.cga\" makes a cycle: "
        r"a.cga -> b.cga -> a.cga",
    ):
        load_grammar(tmp_path / "a.cga")
    _files(tmp_path, {"self.cga": 'import me : "self.cga"\nInit --> X'})
    with pytest.raises(GrammarError, match="self.cga -> self.cga"):
        load_grammar(tmp_path / "self.cga")


def test_errors_inside_an_imported_file_name_that_file_line_and_caret(tmp_path):
    _files(
        tmp_path,
        {
            "imp.cga": "attr a = 1\nLot --> extrude(b) X",
            "main.cga": 'import imp : "imp.cga"\nInit --> imp.Lot',
        },
    )
    with pytest.raises(GrammarError) as caught:
        load_grammar(tmp_path / "main.cga")
    text = str(caught.value)
    assert text.splitlines()[0] == f"{tmp_path / 'imp.cga'}:2:17: undefined name 'b'"
    assert text.splitlines()[1].strip() == "Lot --> extrude(b) X"  # the imported file's line
    _files(tmp_path, {"imp.cga": "Lot --> extrude(2 X"})
    with pytest.raises(GrammarError, match=r"imp.cga:1:"):
        load_grammar(tmp_path / "main.cga")


@pytest.mark.parametrize(
    "arguments, message",
    [
        ("(nothing = 2)", "\"imp.cga\" has no attr 'nothing'"),
        ("(nothing)", "\"imp.cga\" has no attr 'nothing'"),
        ("(height, height = 2)", "the attr 'height' is both protected and overridden"),
        ("(Missing --> X)", "\"imp.cga\" has no rule 'Missing'"),
    ],
)
def test_unknown_names_in_the_import_arguments(tmp_path, arguments, message):
    with pytest.raises(GrammarError, match=message):
        _height(tmp_path, f'import imp : "imp.cga" {arguments}\nInit --> imp.Lot')


def test_other_styles_and_repeated_prefixes_are_refused(tmp_path):
    with pytest.raises(GrammarError, match='style.s. Blue of "imp.cga" is not supported'):
        _height(tmp_path, 'import imp (Blue) : "imp.cga"\nInit --> imp.Lot')
    with pytest.raises(GrammarError, match="the import prefix 'imp' is used twice"):
        _height(tmp_path, 'import imp : "imp.cga"\nimport imp : "imp.cga"\nInit --> imp.Lot')


# The corpus -----------------------------------------------------------------------------------


def _reference(package: str) -> dict:
    return json.loads((REFERENCE / f"{package}.json").read_text())


@pytest.mark.parametrize("package", ["tests_data_dynamic_imports__686c1323"])
def test_corpus_rule_a_imports_rule_b_as_pyprt_builds_it(package):
    """ruleA imports "rules/prt3_dynamic_imports/ruleB.cga" (project-relative) overriding
    h = 10; PyPRT reports myHeight 10 and a 12 x 10 x 8 box (volume 960)."""
    reference = _reference(package)
    rule = CORPUS / package / "rules" / "prt3_dynamic_imports" / "ruleA.cga"
    model = load_grammar(rule).build(lot=LOT)
    assert model.metadata["reports"]["myHeight"] == reference["reports"]["myHeight_sum"]
    assert sum(b.volume for b in model.blocks) == pytest.approx(reference["volume"])


def test_corpus_footprint_building_imports_esri_lib_through_its_resolve_map():
    package = CORPUS / "data_Building_From_FootprintSMALL__fc6ce924"
    grammar = load_grammar(package / "rules" / "Building_From_FootprintSMALL.cga")
    assert "Facade_Textures.BuildingHeight" in grammar.attrs
    model = grammar.build(lot=LOT)
    assert model.blocks or model.surfaces


@pytest.mark.parametrize(
    "package", sorted(p.name for p in CORPUS.glob("tests_data_envelope2002__*"))
)
def test_corpus_envelope_merges_its_four_imports_and_esri_lib(package):
    rule = CORPUS / package / "rules" / "typology" / "envelope2002.cga"
    grammar = load(rule.read_text(), str(rule), rule)
    rules = {r.name for r in grammar.rules}
    attrs = {a.name: a for a in grammar.attrs}
    # envelope2002.cga defines volume.Slab, which volume0110.cga calls without defining it
    assert {"volume.ASSIGN_VOLUME", "volume.Slab", "facade.Slab"} <= rules
    # propagated: volume0110's shape_of_building takes envelope2002's
    assert attrs["volume.shape_of_building"].value == ast.Name("shape_of_building")
    assert "plant_distributor.Plant.Name" in attrs  # a second-level import of ESRI.lib
    # that the merged file derives on the 12 x 8 lot is tests/cga/test_corpus.py's test_derives
    # (envelope2002_*.cga are among its files): building it here again cost 1.2 s a package


def test_the_docs_example_prints_what_it_says(capsys):
    page = (ROOT / "docs" / "grammar.md").read_text()
    (example,) = [b for b in re.findall(r"```python\n(.*?)```", page, re.S) if "import tower" in b]
    exec(compile(example, "docs/grammar.md", "exec"), {})
    printed = capsys.readouterr().out.splitlines()
    expected = [line.split("# ", 1)[1] for line in example.splitlines() if "print(" in line]
    assert printed == expected


def test_dynamic_imports_reinitialise_the_imported_attrs(tmp_path):
    """import.html's dynamic import examples: imp(height = 5).Lot re-evaluates angle with the
    new height; imp().Lot starts again from the static import (a set() before it is lost)."""
    imported = (
        "attr height = 10\nattr angle = case height > 10 : 0 else : 30\n"
        'Lot --> extrude(height) report("h", scope.sy) report("a", angle) X.'
    )
    main = (
        'import imp : "imp.cga" (height = 20)\n'
        "Init --> split(x) { ~1 : imp(height = 5).Lot | ~1 : imp.Lot "
        "| ~1 : set(imp.height, 1) imp().Lot }"
    )
    _files(tmp_path, {"imp.cga": imported, "main.cga": main})
    reports = load_grammar(tmp_path / "main.cga").build(lot=LOT).metadata["reports"]
    assert reports == {"h": [5.0, 20.0, 20.0], "a": [30.0, 0.0, 0.0]}
    with pytest.raises(GrammarError, match="'width' is not an attr of the import 'imp'"):
        _height(tmp_path, 'import imp : "imp.cga"\nInit --> imp(width = 2).Lot', imported)
    with pytest.raises(GrammarError, match="dynamic import of 'other', which is not imported"):
        _height(tmp_path, 'import imp : "imp.cga"\nInit --> other(h = 2).Lot', imported)


def test_a_dynamic_import_reevaluates_an_attr_with_local_variables(tmp_path):
    """with.html: an attr's local variables (each reading those before it) are evaluated again
    when a dynamic import re-initialises the attr."""
    imported = 'attr a = 1\nattr b with (w := 2 + a  v := w * 2) = v\nS --> report("b", b) X.'
    main = 'import lib : "lib.cga"\nInit --> split(x) { ~1 : lib(a = 3).S | ~1 : lib.S }'
    _files(tmp_path, {"lib.cga": imported, "main.cga": main})
    reports = load_grammar(tmp_path / "main.cga").build(lot=LOT).metadata["reports"]
    assert reports == {"b": [10.0, 6.0]}


def test_attr_only_library_with_consts_functions_and_a_style(tmp_path):
    library = (
        "attr height = 4\nconst width = height / 2\narea(d) = width * d\n"
        "style Tall\nattr height = 40\n"
    )
    main = (
        'import lib : "imp.cga"\n'
        'Lot --> extrude(lib.height) report("w", lib.width) report("a", lib.area(3)) X.'
    )
    reports = _height(tmp_path, main, library, key="w")
    assert reports == 2.0  # the Default style's height: Tall's definitions are left out
    grammar = load_grammar(tmp_path / "main.cga")
    assert grammar.build(lot=LOT).metadata["reports"] == {"w": 2.0, "a": 6.0}
    assert grammar.attrs == {"lib.height": 4.0}
