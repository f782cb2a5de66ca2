"""load_grammar takes a path and only a path; parse_grammar takes text and only text."""

from pathlib import Path

import pytest

import shapegen
from shapegen.errors import GrammarError

SMALL = "@StartRule @Lot(2, 1)\nLot --> extrude(1) Box.\n"


@pytest.mark.parametrize(
    "text",
    [
        SMALL,
        "Lot --> extrude(1) Stone",  # one line of rule syntax
        "attr height = 3",
        "@StartRule Lot --> extrude(1) X",
        "   ",
        "",
    ],
)
def test_grammar_text_given_as_a_path_points_to_parse_grammar(text):
    with pytest.raises(GrammarError, match=r"use parse_grammar\(text\)") as caught:
        shapegen.load_grammar(text)
    assert len(str(caught.value).splitlines()) == 1


def test_a_one_line_grammar_longer_than_a_file_name_parses_as_text():
    # 381 of 10 000 fuzz inputs were one-line texts over 255 characters, read as file names.
    one_line = (
        "@StartRule @Lot(60, 1) Lot --> extrude(1) split(x) { "
        + " | ".join(["1 : Box."] * 60)
        + " }"
    )
    assert len(one_line) > 255 and "\n" not in one_line
    assert len(shapegen.parse_grammar(one_line).build().blocks) == 60
    with pytest.raises(GrammarError) as caught:
        shapegen.load_grammar("x" * 300)  # as a path it is too long: a clear error, no OSError
    assert "File name too long" in str(caught.value)


def test_a_path_given_as_text_is_parsed_as_text_never_read(tmp_path):
    secret = tmp_path / "secret.grammar"
    secret.write_text("attr password = 1234\n")
    with pytest.raises(GrammarError) as caught:
        shapegen.parse_grammar(str(secret))
    assert "1234" not in str(caught.value)
    assert "<string>:1:1" in str(caught.value)


@pytest.mark.parametrize("value", [b"cluny.grammar", 3, None])
def test_load_grammar_refuses_what_is_not_a_path(value):
    with pytest.raises(GrammarError, match="takes the path of a rule file"):
        shapegen.load_grammar(value)


def test_parse_grammar_refuses_a_path_object(tmp_path):
    path = tmp_path / "small.grammar"
    path.write_text(SMALL)
    with pytest.raises(GrammarError, match=r"use load_grammar\(path\)"):
        shapegen.parse_grammar(path)


def test_a_folder_or_a_nul_is_one_clear_line(tmp_path):
    with pytest.raises(GrammarError, match="is not a file"):
        shapegen.load_grammar(tmp_path)
    with pytest.raises(GrammarError, match="NUL"):
        shapegen.load_grammar("a\0b.grammar")


def test_parse_grammar_names_its_source():
    grammar = shapegen.parse_grammar("Lot --> extrude(1 / 0)\n", name="wall.grammar")
    assert grammar.name == "wall.grammar" and grammar.path is None
    with pytest.raises(GrammarError, match=r"wall\.grammar:1:"):
        grammar.build()


def test_bundled_name_with_or_without_suffix(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for name in ("wall_windows", "wall_windows.grammar", Path("wall_windows.grammar")):
        assert shapegen.load_grammar(name).path.name == "wall_windows.grammar"
