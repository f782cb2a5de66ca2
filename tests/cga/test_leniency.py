"""CityEngine's leniency in .cga files: where its compiler or runtime warns and carries on, the
file loads, the model derives and the warning reaches ``metadata["warnings"]``; ``.grammar``
files keep refusing the same text."""

from __future__ import annotations

import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.errors import GrammarError

LOT = (12.0, 8.0)


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
    assert grammar.build(lot=LOT).volume == pytest.approx(
        12 * 8 * 3.0
    )  # extrude(v[1]), v = [2, 3]


def test_setpivot_axis_permutations_load():
    # op_setPivot: axisMap is xyz, yzx or zxy
    for axes in ("xyz", "yzx", "zxy"):
        text = f"@StartRule\nLot --> extrude(2) setPivot({axes}, 2) A."
        assert len(parse_grammar(text, "r.cga").build(lot=LOT).blocks) == 1


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
