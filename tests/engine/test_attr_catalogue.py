"""The attribute catalogue (engine/attr_catalogue.py): an attr's facts read once, and the one
line for a name no attr has, said alike by the command line, the page, the search and PRT."""

import pytest

import shapegen
from shapegen.cli import main
from shapegen.editor.attrs import RequestError, checked_values
from shapegen.editor.history import reset_names
from shapegen.editor.inputs import checked_free
from shapegen.errors import GrammarError
from shapegen.prt.rule_package_info import NO_KEY, attributes_info_of
from shapegen.search.parameters import select_parameters

RULES = """\
version "2023.0"
import lib : "lib.cga"

@Group("Mass", 2) @Range(min=1, max=9, stepsize=0.5)
attr height = 3
@Color
attr tint = "#ff0000"
@Hidden
attr note = "x"
@Group
attr loose = true
@Group("Look", "Roof")
@File("obj")
attr roof = "roof.obj"
@Directory
attr textures = "tex"
@Enum(1, 2, restricted=false)
attr lanes = 1
attr sizes = [1, 2]

@StartRule
Lot --> extrude(height) Mass.
"""
LIB = """\
@Group("Inner")
attr depth = 2
attr width = 1
"""


@pytest.fixture
def catalogue(tmp_path):
    (tmp_path / "lib.cga").write_text(LIB, encoding="utf-8")
    path = tmp_path / "main.cga"
    path.write_text(RULES, encoding="utf-8")
    return shapegen.load_grammar(path).catalogue


@pytest.mark.parametrize(
    ("name", "kind"),
    [
        ("height", "number"),
        ("tint", "color"),
        ("note", "string"),
        ("loose", "bool"),
        ("roof", "file"),
        ("textures", "directory"),
        ("lanes", "number"),
        ("sizes", "array"),
        ("lib.depth", "number"),
    ],
)
def test_each_attr_has_its_kind(catalogue, name, kind):
    assert catalogue[name].kind == kind


def test_a_group_holds_for_the_attrs_after_it_in_its_own_file(catalogue):
    groups = {name: entry.group for name, entry in catalogue.items()}
    assert groups == {
        "height": ("Mass",),
        "tint": ("Mass",),  # carried from height
        "note": ("Mass",),
        "loose": (),  # a bare @Group leaves the group
        "roof": ("Look", "Roof"),
        "textures": ("Look", "Roof"),
        "lanes": ("Look", "Roof"),
        "sizes": ("Look", "Roof"),
        "lib.depth": ("lib", "Inner"),  # the import's section, its own group within it
        "lib.width": ("lib", "Inner"),
    }
    assert catalogue["tint"].group_order == 2.0 and catalogue["loose"].group_order is None


def test_the_range_choices_and_hidden_flag_are_read_from_the_annotations(catalogue):
    height = catalogue["height"]
    assert (height.ranged, height.step, height.restricted, height.default) == (True, 0.5, True, 3.0)
    assert catalogue["lanes"].choices == (1.0, 2.0) and not catalogue["lanes"].restricted
    assert catalogue["roof"].extensions == ("obj",)
    assert [n for n, e in catalogue.items() if e.hidden] == ["note"]
    assert set(catalogue.ranges()) == {"height"}
    assert catalogue.ranges({"height": 4})["height"] == {"value": 4.0, "min": 1.0, "max": 9.0}


def test_prt_lists_the_group_the_catalogue_carries_and_leaves_hidden_attrs_out(catalogue):
    info = attributes_info_of(catalogue)
    assert "note" not in info
    assert info["tint"]["annotations"] == [["@Color"], ["@Group", [NO_KEY, "Mass"], [NO_KEY, 2.0]]]
    assert info["lanes"]["annotations"][-1] == ["@Group", [NO_KEY, "Look"], [NO_KEY, "Roof"]]
    assert info["sizes"]["type"] == "float[]"


@pytest.mark.parametrize(
    ("name", "line"),
    [
        ("heigth", "the grammar has no attr 'heigth'; did you mean 'height'?"),
        (
            "zzz",
            "the grammar has no attr 'zzz' (its attrs: height, tint, note, loose, roof, textures,"
            " lanes, sizes, lib.depth, lib.width)",
        ),
    ],
)
def test_a_name_no_attr_has_is_one_line(catalogue, name, line):
    assert catalogue.no_attr(name) == line


def test_a_grammar_without_attrs_says_so():
    grammar = shapegen.parse_grammar("@StartRule\nLot --> extrude(1) Stone")
    assert grammar.catalogue.no_attr("x") == "the grammar has no attr 'x' (it has no attrs)"


STACK = """\
@Free @Range(0, 0.9)
attr offset = 0.2
attr courses = 2
@StartRule @Lot(1, 1)
Lot --> extrude(2) split(y) { 1 : Lower | 1 : Upper }
Lower --> i("box")
Upper --> t(offset, 0, 0) i("box")
"""
SAID = "the grammar has no attr 'ofset'; did you mean 'offset'?"


def _refusal(call) -> str:
    with pytest.raises((RequestError, GrammarError)) as caught:
        call()
    return str(caught.value)


def test_the_command_line_the_page_and_the_search_say_the_same_line(tmp_path, capsys):
    path = tmp_path / "stack.grammar"
    path.write_text(STACK, encoding="utf-8")
    grammar = shapegen.load_grammar(path)
    said = [
        _refusal(lambda: checked_values(grammar, {}, {"ofset": 0.1})),
        _refusal(lambda: checked_free(["ofset"], grammar, {"offset"})),
        _refusal(lambda: reset_names(grammar, {"attrs": ["ofset"]})),
        _refusal(lambda: select_parameters(grammar, free=["ofset"])),
        _refusal(lambda: grammar.build(attrs={"ofset": 0.1})),
    ]
    assert main(["build", str(path), "--set", "ofset=0.1", "-q"]) != 0
    said.append(capsys.readouterr().err)
    assert all(SAID in line for line in said), said
