"""modify() (op_modify, cga_shapeRecomposition), splitAndSetbackPerimeter
(op_splitAndSetbackPerimeter), comp's ``=:`` operator and comp(g), comp(m) (op_comp), checked
against the reference's statements and closed-form figures of the shapes they make."""

from __future__ import annotations

import pytest

from shapegen import parse_grammar

COVERS = {
    "test_modify_moves_the_vertices_of_what_it_transforms": ("op:modify",),
    "test_split_and_setback_perimeter_sections": ("op:splitAndSetbackPerimeter",),
    "test_connected_sets_of_faces": ("op:comp",),
}


def _reports(text: str, lot=(12.0, 8.0)) -> dict:
    model = parse_grammar(text, "recompose.cga").build(lot=lot)
    return model.metadata["reports"]


def _values(reports: dict, key: str) -> list[float]:
    value = reports.get(key, [])
    return value if isinstance(value, list) else [value]


# op_modify, "Tapered Mass": the top of an extruded mass rescaled (about its face scope's
# origin, a corner) makes slanted facades. A 12 x 8 m lot extruded 5 m, its top 6 x 4 m: a
# prismatoid, V = h / 6 (A_bottom + A_top + 4 A_middle) = 5 / 6 (96 + 24 + 4 * 9 * 6) = 280 m3.
# modify(v, noAlign): a vertex's scope keeps the lot's axes, so t(0, 1, 0) lifts the lot 1 m.
# A face deleted with NIL leaves its place open.
@pytest.mark.parametrize(
    "operations, expected",
    [
        ("extrude(5) modify(f) { top : s('0.5, '0.5, '0.5) X. }",
         {"volume": 280.0, "faces": 6.0, "closed": True}),
        ("extrude(5) modify(f) { top : NIL }", {"faces": 5.0, "closed": False}),
        ("modify(v, noAlign) { all : t(0, 1, 0) X. }", {"elevation": 1.0, "area": 96.0}),
        ("extrude(5) modify(e) { 0 : t(0, 0, 0) X. }", {"volume": 480.0, "faces": 6.0}),
        # "shared vertices are merged by summing their individual offsets": each side face
        # lifts its 4 corners 1 m, and every corner of the box is in 2 sides: it rises 2 m
        ("extrude(5) modify(f, noAlign) { side : t(0, 1, 0) X. }",
         {"volume": 480.0, "elevation": 2.0}),
    ],
)  # fmt: skip
def test_modify_moves_the_vertices_of_what_it_transforms(operations, expected):
    text = f"""Lot --> {operations}
    report("volume", geometry.volume) report("faces", geometry.nFaces)
    report("closed", geometry.isClosedSurface) report("elevation", scope.elevation)
    report("area", geometry.area)"""
    reports = _reports(text)
    for key, value in expected.items():
        assert reports[key] == pytest.approx(value, abs=1e-6), key


def test_modify_keeps_one_shape_and_gives_its_tags_to_the_components():
    """ "The modify operation only changes the current shape's geometry and does not add
    successor shapes"; a tag() in a branch tags the component it was given."""
    text = """Lot --> extrude(5) modify(f) { top : tag("Roof") X. }
    comp(f) { isTagged("Roof") : report("roof", geometry.area) X. }"""
    assert _values(_reports(text), "roof") == [96.0]


# op_splitAndSetbackPerimeter. A 60 x 40 m lot, its first edge 60 m long: a 40 m section from
# 6 m along it, set back 5 m, is the 40 x 5 m strip (both neighbours stay put), the remainder
# the rest; a relative offset and length are shares of the 200 m perimeter; each section's depth
# is evaluated with its split.index; the sections and the remainder tile the lot.
@pytest.mark.parametrize(
    "pattern, sections, remainder",
    [
        ("splitAndSetbackPerimeter(6) { 40 : 5 : S }", [200.0], 2200.0),
        ("splitAndSetbackPerimeter('0.1) { '0.2 : 5 : S }", [200.0], 2200.0),
        ("splitAndSetbackPerimeter(0) { 10 : split.index + 1 : S | ~1 : 0 : NIL }",
         [10.0], 2390.0),
    ],
)  # fmt: skip
def test_split_and_setback_perimeter_sections(pattern, sections, remainder):
    text = f"""Lot --> {pattern} {{ remainder : report("rest", geometry.area) R. }}
S --> report("section", geometry.area) X."""
    reports = _reports(text, lot=(60.0, 40.0))
    assert _values(reports, "section") == pytest.approx(sections)
    assert _values(reports, "rest") == pytest.approx([remainder])


def test_split_and_setback_perimeter_tiles_the_lot():
    """ "The overlap belongs to the shape that has been generated with larger depth and is cut
    away from the other": the pieces never overlap, so their areas add up to the lot's."""
    text = """Lot --> splitAndSetbackPerimeter(3) { 2 : 6 : S | 2 : 0 : NIL | 2 : 4 : S }*
    { remainder : R }
S --> report("a", geometry.area) X.
R --> report("a", geometry.area) X."""
    assert sum(_values(_reports(text, lot=(20.0, 14.0)), "a")) == pytest.approx(280.0)


# op_comp: "=: Each connected set of selected components is combined into a new shape. ... Two
# components are connected if their faces share an edge."
@pytest.mark.parametrize(
    "selector, shapes",
    [("side", 1), ("top || bottom", 2), ("front || back", 2), ("front || right", 1)],
)
def test_connected_sets_of_faces(selector, shapes):
    text = f'Lot --> extrude(3) comp(f) {{ {selector} =: report("n", geometry.nFaces) X. }}'
    assert len(_values(_reports(text), "n")) == shapes


# op_comp, g and m: shapegen's geometry is one group of one material: one component.
@pytest.mark.parametrize("kind", ["g", "m"])
def test_groups_and_materials_are_the_whole_geometry(kind):
    text = f'Lot --> extrude(3) comp({kind}) {{ 0 : report("n", geometry.nFaces) X. }}'
    assert _values(_reports(text), "n") == [6.0]
