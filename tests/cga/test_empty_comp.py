"""A ``comp`` that comes to nothing, as CityEngine's runtime has it (PyPRT 1.12, measured on
envelope2002's compiled rules rewritten: its ``Create_interior_plan``, ``comp(f){bottom:
offset(-1) comp(f){inside: ...}}`` on a floor 1 m deep, keeps the floor whole; with
``offset(-0.1)``, or ``comp(f){border: ...}`` inside, the floor is taken apart; its outer
``comp(f){border: ...}``, which a closed box does not have, keeps the floor too; the ground
floor plan's ``offset(-2)`` whose inside vanishes leaves no border faces).

A component whose comp chooses nothing vanishes, and so does one whose chosen components all
vanished; a shape a rule made, whose comp came to nothing, goes on as it was."""

import pytest

import shapegen.prt as prt

LOT = [0.0, 0.0, 8.0, 12.0, 0.0, 8.0, 12.0, 0.0, 0.0, 0.0, 0.0, 0.0]


def counts(tmp_path, rules: str) -> tuple[int, int]:
    rule = tmp_path / "rule.cga"
    rule.write_text("Lot --> extrude(2) X\n" + rules + "\n")
    (model,) = prt.ModelGenerator([prt.InitialShape(LOT)]).generate_model([{}], str(rule))
    return len(model.get_vertices()) // 3, len(model.get_faces())


@pytest.mark.parametrize(
    "rules, expected",
    [
        # the offset's inside vanishes: the bottom comes to nothing, the box stays whole
        ("X --> comp(f){bottom: offset(-10) comp(f){inside: A}}", (8, 6)),
        # a comp that chooses nothing: the box stays whole
        ("X --> comp(f){border: A}", (8, 6)),
        # the box goes on to the next comp: only its top is left, no border of the offset
        ("X --> comp(f){bottom: offset(-10) comp(f){inside: A}} comp(f){top: B}", (4, 1)),
        # an inside to choose: the box is taken apart into it
        ("X --> comp(f){bottom: offset(-1) comp(f){inside: A}}", (4, 1)),
        # NIL is no coming to nothing: the box is deleted
        ("X --> comp(f){bottom: NIL}", (0, 0)),
    ],
)
def test_a_comp_that_comes_to_nothing(tmp_path, rules, expected):
    assert counts(tmp_path, rules) == expected
