"""CityEngine's leniency in .cga files: where its compiler or runtime warns and carries on, the
file loads, the model derives and the warning reaches ``metadata["warnings"]``; ``.grammar``
files keep refusing the same text."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.errors import GrammarError
from shapegen.grammar import ast, load

LOT = (12.0, 8.0)


def _derived(text: str, **build):
    """The model a .cga text derives on the 12 x 8 m lot."""
    return parse_grammar(text, "r.cga").build(lot=LOT, **build)


def _cga(tmp_path, text: str, name: str = "rule.cga"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return load_grammar(path)


# (text, what the warning says): each derives in .cga and is refused in .grammar
WARNED = [
    ("@Range(0, 10)\nattr h = 12\n@StartRule\nLot --> extrude(h) A.", "outside its @Range"),
    ("@StartRule\nLot --> extrude(2) Roof\nRoof(n) --> X.", "takes 1 argument, got 0"),
    ("@StartRule\nLot --> extrude(2) roofs(3)", "neither a CGA operation nor a rule"),
    ('@Group("a")\n@Group("b")\nattr h = 2\n@StartRule\nLot --> extrude(h)', "given twice"),
    ("@Order(1, 2)\nattr h = 2\n@StartRule\nLot --> extrude(h)", "@Order takes"),
    ("@Range(min=1, max=2, step=1)\nattr h = 2\n@StartRule\nLot --> extrude(h)", "no argument"),
    ("@StartRule\nA --> extrude(1)\n@StartRule\nB --> extrude(2)", "more than one @StartRule"),
]


@pytest.mark.parametrize(("text", "warning"), WARNED)
def test_cityengine_warnings_derive_in_cga_and_are_refused_in_grammar(tmp_path, text, warning):
    model = _cga(tmp_path, text).build(lot=LOT)
    assert any(warning in w for w in model.metadata["warnings"]), model.metadata["warnings"]
    assert all(w.startswith(str(tmp_path / "rule.cga") + ":") for w in model.metadata["warnings"])
    with pytest.raises(GrammarError, match=warning.replace("(", r"\(")):
        parse_grammar(text, "rule.grammar")


def test_undefined_rule_of_another_arity_is_a_leaf():
    # Roof(n) exists, Roof with no argument does not: CityEngine's undefined rule, a leaf
    grammar = parse_grammar("@StartRule\nLot --> extrude(2) Roof\nRoof(n) --> NIL", "r.cga")
    model = grammar.build(lot=LOT)
    assert len(model.blocks) == 1  # the mass, not deleted by Roof(n)'s NIL


def test_explicit_leaf_never_calls_a_rule_of_any_arity():
    text = "@StartRule\nLot --> extrude(2) Roof.\nRoof(n) --> NIL"
    for name in ("r.cga", "r.grammar"):
        model = parse_grammar(text, name).build(lot=LOT)
        assert len(model.blocks) == 1 and not model.metadata["warnings"]


@pytest.mark.parametrize("comment", ["/* a comment */", "// a comment", "/**/"])
def test_a_leaf_followed_by_a_comment(comment):
    model = parse_grammar(f"@StartRule\nLot --> extrude(2) Mass.{comment}\n", "r.cga").build(
        lot=LOT
    )
    assert len(model.blocks) == 1


def test_element_wise_division_still_lexes():
    grammar = parse_grammar("attr v = [4, 6] ./ 2\n@StartRule\nLot --> extrude(v[1]) A.", "r.cga")
    assert grammar.build(lot=LOT).volume == pytest.approx(12 * 8 * 3.0)  # extrude(v[1]), v = [2, 3]


def test_setpivot_axis_permutations_load():
    # op_setPivot: axisMap is xyz, yzx or zxy
    for axes in ("xyz", "yzx", "zxy"):
        text = f"@StartRule\nLot --> extrude(2) setPivot({axes}, 2) A."
        assert len(_derived(text).blocks) == 1


def test_windows_1252_source_is_read_with_a_warning(tmp_path):
    path = tmp_path / "old.cga"
    path.write_bytes(b"// H\xf6he in m, 90\xb0\nattr h = 3\n@StartRule\nLot --> extrude(h) A.\n")
    model = load_grammar(path).build(lot=LOT)
    assert len(model.blocks) == 1
    assert model.metadata["warnings"] == [f"{path}: not UTF-8: read as Windows-1252 (cp1252)"]


def test_utf8_with_a_byte_order_mark_is_utf8(tmp_path):
    path = tmp_path / "bom.cga"
    path.write_bytes("\ufeff// Höhe\n@StartRule\nLot --> extrude(3) A.\n".encode())
    model = load_grammar(path).build(lot=LOT)
    assert len(model.blocks) == 1 and model.metadata["warnings"] == []


def test_an_imported_file_in_windows_1252_is_named_in_the_warning(tmp_path):
    (tmp_path / "lib.cga").write_bytes(b"// Stra\xdfe\nHouse --> extrude(4) A.\n")
    main = tmp_path / "main.cga"
    main.write_text('import lib : "lib.cga"\n@StartRule\nLot --> lib.House\n')
    model = load_grammar(main).build(lot=LOT)
    assert model.metadata["warnings"] == [
        f"{tmp_path / 'lib.cga'}: not UTF-8: read as Windows-1252 (cp1252)"
    ]


def test_a_binary_file_is_one_clear_error(tmp_path):
    path = tmp_path / "x.cga"
    path.write_bytes(b"\x00\x01\x02\xff")
    with pytest.raises(GrammarError, match="not text"):
        load_grammar(path)


def test_the_start_keyword_marks_the_start_rule_and_start_calls_it(tmp_path):
    # start.html's example: start(20) is Init(20); an importing file's rule.start(10) is
    # rule.Init(10)
    (tmp_path / "rule.cga").write_text(
        "start Init --> start(20)\nstart Init(height) --> extrude(height) A.\n"
    )
    (tmp_path / "main.cga").write_text('import rule : "rule.cga"\nLot --> rule.start(10)\n')
    alone = load_grammar(tmp_path / "rule.cga").build(lot=LOT)
    imported = load_grammar(tmp_path / "main.cga").build(lot=LOT)
    assert alone.volume == pytest.approx(12 * 8 * 20)
    assert imported.volume == pytest.approx(12 * 8 * 10)
    assert alone.metadata["warnings"] == imported.metadata["warnings"] == []


def test_start_stays_a_name_elsewhere():
    text = "attr start = 2\n@StartRule\nLot --> extrude(start) start\nstart --> A."
    assert _derived(text).volume == pytest.approx(12 * 8 * 2)


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        ("(case a > 1: 5 else: 1)", 5.0),
        ("(case a > 3: 5 case a > 1: 4 else: 1)", 4.0),
        ("(100%: 7 else: 1)", 7.0),
        ("2 * (case a > 1: 3 else: 1)", 6.0),
    ],
)
def test_case_and_stochastic_values_in_parentheses(value, expected):
    text = f"attr a = 2\nattr b = {value}\n@StartRule\nLot --> extrude((case b > 0: b else: 1))"
    model = _derived(text)
    assert model.metadata["attrs"]["b"] == expected
    assert model.volume == pytest.approx(12 * 8 * expected)


def test_an_import_override_may_be_a_case_value(tmp_path):
    (tmp_path / "lib.cga").write_text("attr h = 1\nHouse --> extrude(h) A.\n")
    (tmp_path / "main.cga").write_text(
        'attr tall = true\nimport lib : "lib.cga" (h = case tall: 9 else: 3)\n'
        "@StartRule\nLot --> lib.House\n"
    )
    assert load_grammar(tmp_path / "main.cga").build(lot=LOT).volume == pytest.approx(12 * 8 * 9)


def test_identifiers_in_any_script():
    text = "attr Höhe = 3\nconst façade_β = 2\n@StartRule\nLot --> extrude(Höhe * façade_β) Façade."
    model = _derived(text)
    assert model.volume == pytest.approx(12 * 8 * 6)


def _long_rule_file(count: int) -> str:
    rules = "".join(f"R{k} --> split(x) {{ 1 : R{k + 1} | ~1 : A{k}. }}\n" for k in range(count))
    return "@StartRule\nLot --> extrude(1) R0\n" + rules


@pytest.mark.slow  # 5 s; test_a_5_mb_rule_file_loads below is the larger case of the same
def test_a_file_larger_than_the_largest_real_one_loads():
    # the largest real rule file seen is a 219 kB street rule; 100 000 characters refused it
    text = _long_rule_file(6_000)
    assert len(text) > 230_000
    assert len(parse_grammar(text, "long.cga").ast.rules) == 6_001


@pytest.mark.slow
def test_a_5_mb_rule_file_loads():
    text = _long_rule_file(125_000)
    assert len(text) > 5_000_000
    assert len(parse_grammar(text, "long.cga").ast.rules) == 125_001


def test_a_runaway_definition_is_refused_by_its_token_count():
    with pytest.raises(GrammarError, match="more than 100000 tokens.*max_definition_tokens"):
        parse_grammar("attr a = " + "1 + " * 60_000 + "1\nLot --> A.", "r.cga")


def test_a_cycle_that_no_evaluation_reaches_loads_and_a_reached_one_is_one_error():
    text = (
        "attr detailed = false\nattr a = case detailed: b else: 2\nattr b = a + 1\n"
        "@StartRule\nLot --> extrude(b) A."
    )
    model = _derived(text)
    assert model.metadata["attrs"] == {"detailed": False, "a": 2.0, "b": 3.0}
    with pytest.raises(GrammarError, match="refer to each other in a cycle: a -> b -> a"):
        _derived(text, attrs={"detailed": True})
    with pytest.raises(GrammarError, match="depends on itself"):
        parse_grammar(text, "r.grammar")


def test_uv_split_runs_along_the_scope_with_a_warning():
    # op_split's UV split on a facade (u along its width, v along its height): 12 x 6 m front,
    # two 3 m floors in unitSpace, each in four tiles of a quarter (uvSpace) of its width
    text = (
        "@StartRule\nLot --> extrude(6) comp(f) { front : Facade | all : NIL }\n"
        "Facade --> split(v, unitSpace, 0) { 3 : Floor }*\n"
        "Floor --> split(u, uvSpace, 0) { 0.25 : Tile }*\nTile --> T."
    )
    model = _derived(text)
    assert len(model.surfaces) == 8
    extents = {tuple(np.round(np.ptp(s.vertices, axis=0), 6)) for s in model.surfaces}
    assert extents == {(3.0, 3.0, 0.0)}  # the front face lies in z = 0
    warnings = model.metadata["warnings"]
    assert any("split(v, unitSpace) runs along the scope's y axis" in w for w in warnings)
    assert any("split(u, uvSpace)" in w and "0..1 over the scope" in w for w in warnings)


def test_a_builtin_without_arguments_may_drop_its_parentheses_in_cga():
    text = "@StartRule\nLot --> extrude(1 + rand) A."
    model = _derived(text, seed=3)
    same = _derived(text.replace("rand", "rand()"), seed=3)
    assert model.volume == pytest.approx(same.volume) and 96 < model.volume < 192
    with pytest.raises(GrammarError, match="'rand' is a builtin function: write rand"):
        parse_grammar(text, "r.grammar")


def _esri_lib_project(tmp_path):
    library = tmp_path / "lib" / "ESRI.lib" / "rules" / "Helpers"
    library.mkdir(parents=True)
    (library / "box.cga").write_text("attr h = 4\nBox --> extrude(h) A.\n")
    rules = tmp_path / "proj" / "rules"
    rules.mkdir(parents=True)
    main = rules / "main.cga"
    main.write_text('import b : "/ESRI.lib/rules/Helpers/box.cga"\n@StartRule\nLot --> b.Box\n')
    return main, tmp_path / "lib"


def test_imports_are_looked_up_in_the_rules_path(tmp_path, monkeypatch):
    main, library = _esri_lib_project(tmp_path)
    monkeypatch.setenv("SHAPEGEN_RULES_PATH", "")  # restored after the test, whatever the CLI sets
    with pytest.raises(GrammarError, match="no such file .tried .*--rules-path"):
        load_grammar(main)
    assert load_grammar(main, rules_path=[library]).build(lot=LOT).volume == pytest.approx(384)
    monkeypatch.setenv("SHAPEGEN_RULES_PATH", str(library))
    assert load_grammar(main).build(lot=LOT).volume == pytest.approx(384)


def test_a_rules_path_entry_that_is_no_folder_is_one_line(tmp_path):
    with pytest.raises(GrammarError, match="--rules-path '.*nowhere': not a folder nor a rule"):
        load_grammar(tmp_path / "x.cga", rules_path=[tmp_path / "nowhere"])


def test_the_cli_takes_rules_path(tmp_path, monkeypatch, capsys):
    from shapegen.cli import main as cli

    main, library = _esri_lib_project(tmp_path)
    monkeypatch.setenv("SHAPEGEN_RULES_PATH", "")  # restored after the test, whatever the CLI sets
    assert cli(["build", str(main), "--lot", "12,8"]) == 2
    assert "no such file" in capsys.readouterr().err
    assert cli(["build", str(main), "--lot", "12,8", "--rules-path", str(library)]) == 0


# the rules path, one type (engine.project.rule_packages.RulesPath; tests/engine/test_rules_path.py)
def test_the_command_line_refuses_a_missing_folder_in_one_line_before_any_work(tmp_path, capsys):
    rule, _ = _esri_lib_project(tmp_path)
    written = tmp_path / "m.json"
    missing = tmp_path / "nowhere"
    from shapegen.cli import main as cli

    status = cli(["build", str(rule), "--rules-path", str(missing), "-o", str(written)])
    assert status == 2 and not written.exists()
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"shapegen: error: --rules-path '{missing}': not a folder nor a rule package"
                   " (.rpk) to look imports up in"]  # fmt: skip


def test_loads_take_the_rules_path_made_once(tmp_path, monkeypatch):
    from shapegen.engine.project import rule_packages
    from shapegen.engine.project.rule_packages import RULES_PATH_VARIABLE, RulesPath

    rule, library = _esri_lib_project(tmp_path)
    monkeypatch.setenv(RULES_PATH_VARIABLE, str(library))
    rule_packages._checked_rules_path.cache_clear()
    for _ in range(3):  # the variable's entries are checked at its first read, not every load
        assert load_grammar(rule).build(lot=(12, 8)).volume == pytest.approx(384)
    info = rule_packages._checked_rules_path.cache_info()
    assert (info.misses, info.hits) == (1, 2)
    given = RulesPath.of([library])  # a RulesPath made at the edge is passed down as it is
    monkeypatch.setenv(RULES_PATH_VARIABLE, "")
    assert load_grammar(rule, rules_path=given).build(lot=(12, 8)).volume == pytest.approx(384)
    with pytest.raises(GrammarError, match="no such file"):
        load_grammar(rule)


def test_division_by_zero_follows_ieee_in_cga_and_is_an_error_in_grammar():
    text = "attr w = 0\nattr q = 3 / w\nattr r = 0 / w\nattr m = 5 % w\n@StartRule\nLot --> X."
    attrs = _derived(text).metadata["attrs"]
    assert attrs["q"] == float("inf") and np.isnan(attrs["r"]) and np.isnan(attrs["m"])
    with pytest.raises(GrammarError, match="division by zero"):
        parse_grammar(text, "r.grammar").build(lot=LOT)


def test_element_wise_division_by_zero_follows_ieee_in_cga_and_is_an_error_in_grammar():
    # arrayTypes.html's ./ and .% are the scalar operators element by element
    text = "attr q = [3, 0] ./ 0\nattr m = [5, 1] .% [0, 2]\n@StartRule\nLot --> X."
    attrs = _derived(text).metadata["attrs"]
    q, m = attrs["q"].values, attrs["m"].values
    assert q[0] == float("inf") and np.isnan(q[1]) and np.isnan(m[0]) and m[1] == 1.0
    with pytest.raises(GrammarError, match="division by zero"):
        parse_grammar(text, "r.grammar").build(lot=LOT)


def test_a_non_finite_operation_parameter_becomes_zero_with_a_warning():
    # cga_changelog 2013.1: the runtime's default for inf/nan float parameters is "replace
    # with zero"
    text = "attr w = 0\n@StartRule\nLot --> extrude(3) t(1 / w, 0, 0) A."
    model = _derived(text)
    assert model.volume == pytest.approx(12 * 8 * 3)
    low = np.min([b.vertices.min(axis=0) for b in model.blocks], axis=0)
    assert low.tolist() == pytest.approx([0.0, 0.0, 0.0])  # t(0, 0, 0)
    (warning,) = model.metadata["warnings"]
    assert "r.cga:3:20" in warning and "inf: replaced by 0" in warning
    with pytest.raises(GrammarError, match="division by zero"):
        parse_grammar(text, "r.grammar").build(lot=LOT)


def test_a_non_finite_material_value_becomes_zero_with_a_warning():
    # the same default for the float material attributes (a smoke rule fades by 1 / 0)
    text = "attr w = 0\n@StartRule\nLot --> extrude(3) set(material.opacity, 1 / w) A."
    model = _derived(text)
    assert model.blocks[0].appearance.opacity == 0.0
    (warning,) = model.metadata["warnings"]
    assert "material.opacity is inf: replaced by 0" in warning


def test_a_negative_size_mirrors_the_geometry_within_the_scope():
    # op_s: "Negative sizes result in mirroring along the corresponding axes"; a shed roof
    # rising along z, mirrored in z, rises the other way over the same footprint
    roof = "@StartRule\nLot --> roofShed(20) s('1, '1, {sz}) R."
    up = _derived(roof.format(sz="'1"))
    down = _derived(roof.format(sz="-scope.sz"))
    (a,), (b,) = up.blocks, down.blocks
    assert b.volume == pytest.approx(a.volume) and b.volume > 0  # still a solid, faces outward
    top_a = a.vertices[np.argmax(a.vertices[:, 1])]
    top_b = b.vertices[np.argmax(b.vertices[:, 1])]
    assert top_a[2] + top_b[2] == pytest.approx(8.0)  # the ridge moved to the other side


def test_viewport_hints_may_hold_cityengine_notation():
    # @Handle's arguments are CityEngine's viewport notation (a shape's 4th instance, a
    # translation vector); shapegen never reads them, and the rest keeps its places
    text = (
        '@Handle(shape=RightCurb^4, axis=x, translate={.1,0,0}, color="#FF11FF")\n'
        "@Handle(shape=Mass.)\nattr w = 2\n@StartRule\nLot --> extrude(w) A.\n"
    )
    assert _derived(text).volume == pytest.approx(12 * 8 * 2)
    # an error shows the line as written
    with pytest.raises(GrammarError, match=r"r.cga:1:32: undefined name 'v'\n.*Curb\^4"):
        parse_grammar("@Handle(shape=Curb^4) attr w = v\nLot --> X.", "r.cga")


def test_a_style_may_carry_annotations_and_a_string_may_span_lines():
    text = (
        '@Enum("a", "b",\n  "c")\nattr e = "a"\n@StartRule\nLot --> extrude(1) A.\n'
        '@Description("A variation\nin red")\nstyle Red\nLot --> extrude(2) A.\n'
    )
    grammar = parse_grammar(text, "r.cga")
    assert grammar.ast.styles == ("Red",)
    assert grammar.build(lot=LOT).volume == pytest.approx(12 * 8)  # the Default style


def test_a_file_of_attrs_only_is_named_a_library():
    with pytest.raises(GrammarError, match="no rules .a library of attrs and functions"):
        parse_grammar("attr a = 1\nf(x) = x * 2\n", "lib.cga")


def test_with_local_variables_as_the_reference_gives_them():
    # with.html: attr, const, function and rule forms; each variable may read those before it
    text = (
        'attr a with ( x := "example" ) = x\n'
        "const b with ( x := [0,1,2]  y := 1 ) = x[y]\n"
        "f(a) with ( x := a  y := x ) = y\n"
        "dist2d(x1, y1, x2, y2) with ( d1 := x2-x1\n  d2 := y2-y1 )\n= sqrt(d1*d1 + d2*d2)\n"
        "@StartRule\n"
        'Lot with ( x := f(2) + b ) --> extrude(x) report("d", dist2d(1, 1, 4, 5)) A.\n'
    )
    model = _derived(text)
    assert model.metadata["attrs"] == {"a": "example"}
    assert model.metadata["reports"] == {"d": 5.0}
    assert model.volume == pytest.approx(12 * 8 * 3)  # f(2) + b = 2 + 1


def test_a_rule_local_variable_keeps_its_value_once_evaluated():
    # with.html: "The value does not change despite the area of the shape is altered."
    text = (
        "@StartRule\nLot with ( area := geometry.area() ) --> s('2, 0, '2)\n"
        '  report("initial", area) report("altered", geometry.area()) X.'
    )
    reports = _derived(text).metadata["reports"]
    assert reports == {"initial": pytest.approx(96.0), "altered": pytest.approx(384.0)}


def test_with_in_an_imported_file_and_names_outside_their_definition(tmp_path):
    (tmp_path / "lib.cga").write_text(
        "attr h = 2\ng(k) with (m := k * h) = m\nHouse with (t := g(3)) --> extrude(t) A.\n"
    )
    main = tmp_path / "main.cga"
    main.write_text('import lib : "lib.cga"\n@StartRule\nLot --> lib.House\n')
    assert load_grammar(main).build(lot=LOT).volume == pytest.approx(12 * 8 * 6)
    with pytest.raises(GrammarError, match="undefined name 'm'"):
        parse_grammar("g(k) with (m := k) = m\n@StartRule\nLot --> extrude(m) A.", "r.cga")


def test_the_deprecated_street_side_selectors_still_compile():
    # cga_changelog: streetSide and noStreetSide are deprecated, not removed; without street
    # widths the street side is the front (the lot's first edge)
    text = "@StartRule\nLot --> setback(2) { noStreetSide : G. | remainder : C. }"
    model = _derived(text)
    names = sorted(s.rule_path[-1] for s in model.surfaces)
    # back, left and right strips, one U-shaped face as CityEngine joins the strips of a
    # branch that meet (tests/data/prt_setback.json); the front stays in C
    assert names == ["C", "G"]
    front = "@StartRule\nLot --> extrude(3) comp(f) { streetSide : F. | noStreetSide : N. }"
    faces = _derived(front).surfaces
    assert sorted(s.rule_path[-1] for s in faces) == ["F", "N", "N", "N"]


def test_a_leaf_may_be_named_like_an_operation():
    # Name. is a leaf whatever Name is: real files end rules with r. or t.
    model = _derived("@StartRule\nLot --> extrude(2) r.")
    assert len(model.blocks) == 1 and model.blocks[0].rule_path[-1] == "r"


def test_scatter_takes_center_as_the_gaussian_mean():
    # op_scatter: scatterMean is center (the default), front, back, left, right, top or bottom
    text = "@StartRule\nLot --> scatter(surface, 5, gaussian, center, 0.4) { primitiveCube() P. }"
    model = _derived(text, seed=2)
    assert len(model.blocks) + len(model.surfaces) == 5


@pytest.mark.parametrize(
    ("body", "operation"),
    [
        ("union { primitiveCube() | t(0.3, 0.3, 0.3) primitiveSphere() }", "union"),
        ("subtract  { primitiveCube() | primitiveSphere() } X.", "subtract"),
        ("intersect { A | B }", "intersect"),
        ("inline { A B } C", "inline"),
        ("inline Extract", "inline"),
        ("inline(unify) split(x) { 2 : A | ~1 : B }*", "inline"),
    ],
)
def test_boolean_and_inline_syntax_is_read(body, operation):
    # op_boolOp and op_inline: the syntax is read into the operation with its operands; the
    # operation either derives or is named in one line at its place, never a syntax error
    text = f"@StartRule\nLot --> extrude(2) {body}\nExtract --> X."
    tree = load(text, "r.cga")
    (node,) = [n for n in ast.walk(tree) if isinstance(n, ast.Operation) and n.name == operation]
    assert len(node.branches) == (1 if operation == "inline" else 2)
    assert all(branch.key is None for branch in node.branches)
    try:
        _derived(text)
    except GrammarError as error:
        assert str(error).startswith(f"r.cga:2:20: the CGA operation '{operation}' is not")


def test_inline_and_union_stay_names_elsewhere():
    text = "attr union = 2\n@StartRule\nLot --> extrude(union) inline."
    assert _derived(text).volume == pytest.approx(12 * 8 * 2)


def test_a_relative_import_is_looked_up_in_the_projects_rules_folder(tmp_path):
    # rules/Complete_Lanes/Lane.cga imports "Complete_Lanes/Imports/Reference.cga", which lies
    # in the project's rules folder (as CityEngine resolves it)
    imports = tmp_path / "rules" / "Complete_Lanes" / "Imports"
    imports.mkdir(parents=True)
    (imports / "Reference.cga").write_text("attr w = 3\nLane --> extrude(w) A.\n")
    lane = tmp_path / "rules" / "Complete_Lanes" / "Lane.cga"
    lane.write_text(
        'import ref : "Complete_Lanes/Imports/Reference.cga"\n@StartRule\nLot --> ref.Lane\n'
    )
    assert load_grammar(lane).build(lot=LOT).volume == pytest.approx(12 * 8 * 3)


def test_a_comp_selector_may_be_a_computed_index():
    # comp(f) { k + 0 = A | ... }: op_comp's index, written as an expression (real files do)
    text = (
        "attr k = 4\n@StartRule\n"
        "Lot --> extrude(3) comp(f) { k + 0 : Front. | k + 1 = Right. | all : Rest. }"
    )
    names = sorted(s.rule_path[-1] for s in _derived(text).surfaces)
    assert names == ["Front", "Rest", "Rest", "Rest", "Rest", "Right"]
    with pytest.raises(GrammarError, match="boolean or a component index, got 1.5"):
        _derived(text.replace("k + 0", "k - 2.5"))


def test_texture_coordinate_queries_read_the_scope_with_a_warning():
    # func_geometry's uMin/uMax/vMin/vMax and du/dv in uvSpace: uv taken as 0..1 over the
    # scope, as the UV split takes it; unitSpace is the scope's size in metres
    text = (
        "@StartRule\nLot --> extrude(3) comp(f) { front : F | all : X. }\n"
        'F --> report("u", geometry.uMin + geometry.uMax) report("v", geometry.vMax)\n'
        '  report("du", geometry.du(0, uvSpace)) report("dum", geometry.du(0, unitSpace)) A.'
    )
    model = _derived(text)
    assert model.metadata["reports"] == {"u": 1.0, "v": 1.0, "du": 1.0, "dum": 12.0}
    warnings = model.metadata["warnings"]
    assert {w.split(":")[0] for w in warnings} == {
        "geometry.uMin",
        "geometry.uMax",
        "geometry.vMax",
        "geometry.du",
    }
    assert all("no texture coordinates" in w for w in warnings)
