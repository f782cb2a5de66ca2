"""Component tags (cga_componentTags, op_tag, op_deleteTags, op_comp's isTagged selector,
func_geometry's tags and hasTags), checked against the statements and figures of CityEngine's
CGA reference: which faces, edges and vertices each operation tags, how the tags survive the
operations after it, and what the selectors and functions read of them."""

from __future__ import annotations

import numpy as np
import pytest

from shapegen import parse_grammar
from shapegen.engine.shapes.tags import query_matches

LOT = (12.0, 8.0)

COVERS = {
    "test_tags_are_read_and_deleted_as_the_functions_say": (
        "op:tag",
        "op:deleteTags",
        "func:geometry.tags",
        "func:geometry.hasTags",
    ),
    "test_operations_tag_the_faces_they_make": ("op:roofGable", "op:taper"),
}


def _reports(text: str, lot=LOT) -> dict:
    model = parse_grammar(text, "tags.cga").build(lot=lot)
    return model.metadata["reports"]


def _count(reports: dict, key: str) -> int:
    value = reports.get(key)
    if value is None:
        return 0
    return len(value) if isinstance(value, list) else 1


# cga_componentTags, "Tag queries": '"Facade" matches not only the exact tag "Facade" but also
# tags with additional subtags, such as "Facade.Front", "Facade.TypeA.Side.Left"'; '?' matches
# exactly one subtag, '*' one or more.
@pytest.mark.parametrize(
    "query, tag, matches",
    [
        ("Facade", "Facade", True),
        ("Facade", "Facade.Front", True),
        ("Facade", "Facade.TypeA.Side.Left", True),
        ("Facade.Front", "Facade", False),
        ("Facade", "FacadeX", False),
        ("?.Front", "Facade.Front", True),
        ("?.Front", "Facade.TypeA.Front", False),
        ("Facade.*.Left", "Facade.TypeA.Side.Left", True),
        ("Facade.*.Left", "Facade.Left", False),
        ("extrude.side", "extrude.side.outer", True),
        ("extrude.side.inner", "extrude.side.outer", False),
    ],
)
def test_tag_queries_follow_the_hierarchy_and_wildcards(query, tag, matches):
    assert query_matches(query, tag) is matches


def _tagged_faces(body: str, queries: list[str], lot=LOT) -> dict[str, int]:
    """How many faces of the shape ``body`` makes each query selects (comp(f) with one
    selector per query, tried alone so that none takes another's faces)."""
    out = {}
    for query in queries:
        text = f'Lot --> {body} comp(f) {{ isTagged("{query}") : report("n", 1) X. }}'
        out[query] = _count(_reports(text, lot), "n")
    return out


# cga_componentTags, "Operations applying auto-tags on faces": the bottom faces are the
# original faces, side faces emanate from an edge (inner ones from a hole: shapegen's faces have
# none), the top; roofGable's gables are sides, its slopes the top; roofRidge and roofShed
# "additionally classify the sides as inner and outer"; taper's apex faces are its sides.
@pytest.mark.parametrize(
    "body, expected",
    [
        (
            "extrude(4)",
            {"extrude.bottom": 1, "extrude.top": 1, "extrude.side.outer": 4,
             "extrude.side.inner": 0, "extrude.side": 4, "extrude": 6},
        ),
        ("roofGable(byHeight, 4)", {"roof.bottom": 1, "roof.side": 2, "roof.top": 2, "roof": 5}),
        ("roofHip(byHeight, 4)", {"roof.bottom": 1, "roof.top": 4, "roof.side": 0}),
        ("roofPyramid(byHeight, 4)", {"roof.bottom": 1, "roof.top": 4}),
        ("roofShed(byHeight, 4)", {"roof.bottom": 1, "roof.top": 1, "roof.side.outer": 3}),
        ("taper(4)", {"taper.bottom": 1, "taper.side": 4}),
    ],
)  # fmt: skip
def test_operations_tag_the_faces_they_make(body, expected):
    assert _tagged_faces(body, list(expected)) == expected


def test_an_l_shaped_lot_extruded_has_a_side_per_edge():
    lot = [(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)]
    found = _tagged_faces("extrude(3)", ["extrude.side.outer", "extrude.top"], lot)
    assert found == {"extrude.side.outer": 6, "extrude.top": 1}


# "When splitting geometry, tags on existing edge and face components that were cut are kept.
# New components, such as new faces to close cut volumes, have no initial tags."
def test_a_split_keeps_the_tags_of_the_faces_it_cuts_and_its_caps_have_none():
    text = """Lot --> extrude(4) tag("Mass") split(x) { '0.25 : A | ~1 : A | '0.25 : A }
A --> comp(f) { isTagged("Mass") : report("tagged", 1) X. | all : report("cap", 1) X. }"""
    reports = _reports(text)
    assert _count(reports, "tagged") == 5 + 4 + 5  # the middle slab has two caps
    assert _count(reports, "cap") == 1 + 2 + 1


# "New faces constructed on top of existing ones get the tags of their source face ... Each
# face now has both extrude and roof auto-tags."
def test_an_extrusion_keeps_the_tags_of_the_faces_it_grows_from():
    text = """Lot --> roofGable(byHeight, 4) extrude(1)
    comp(f) { isTagged("roof") && isTagged("extrude") : report("both", 1) X.
            | all : report("other", 1) X. }"""
    reports = _reports(text)
    assert _count(reports, "both") > 0 and _count(reports, "other") == 0


# op_comp: "the edges of the face tagged "envelope.top" are selected"; "vertices can be selected
# based on the tags of adjacent faces and edges"; with e, "all faces that share an edge with a
# face tagged "envelope.bottom" or have an edge tagged as such, are selected. Note that the face
# tagged "envelope.bottom" (blue) is selected as well."
@pytest.mark.parametrize(
    "split, expected",
    [
        ('comp(e) { isTagged("extrude.top") : report("n", 1) X. }', 4),
        ('comp(v) { isTagged("extrude.top") : report("n", 1) X. }', 4),
        ('comp(f) { isTagged("extrude.top", e) : report("n", 1) X. }', 5),
        ('comp(e) { isTagged("extrude.top", v) : report("n", 1) X. }', 8),
        ('comp(f) { isTagged("extrude.top", e) && side : report("n", 1) X. }', 4),
        ('comp(f) { isTagged("extrude.top", v) && bottom : report("n", 1) X. }', 0),
    ],
)
def test_is_tagged_selects_components_by_the_tags_that_identify_them(split, expected):
    assert _count(_reports(f"Lot --> extrude(4) {split}"), "n") == expected


# cga_componentTags' setup: a gable roof, its edges and vertices tagged with tag(name, edges)
# and tag(name, vertices): a gable roof on a rectangle has 9 edges and 6 vertices.
def test_tag_on_edges_and_vertices_tags_every_one():
    text = """Lot --> roofGable(byHeight, 4) tag("EdgeTag", edges) tag("VertexTag", vertices)
    comp(e) { isTagged("EdgeTag") : report("edge", 1) X. }
    comp(v) { geometry.hasTags("VertexTag", vertices) : report("vertex", 1) X. }"""
    reports = _reports(text)
    # a gable roof's bottom, slopes and gable ends share no edge and no corner: CityEngine's
    # runtime lists 17 edges and 16 corners (tests/data/prt_roof_edges.json)
    assert (_count(reports, "edge"), _count(reports, "vertex")) == (17, 16)


@pytest.mark.parametrize(
    "operations, function, expected",
    [
        ('deleteTags() tag("b") tag("a")', "geometry.tags()", "(2)[a,b]"),  # alphabetically sorted
        ('tag("a") tag("b") deleteTags("a")', 'geometry.hasTags("a")', "false"),
        ('tag("a") tag("b") deleteTags("a")', 'geometry.hasTags("b")', "true"),
        ('tag("a.x") tag("b")', 'geometry.tags("a")', "(1)[a.x]"),
        ('tag("a") deleteTags()', "geometry.hasTags()", "false"),
        ('tag("a") deleteTags("a", edges)', 'geometry.hasTags("a")', "true"),
        ('tag("a", edges)', 'geometry.hasTags("a", faces)', "false"),
        ('tag("a", edges)', 'geometry.hasTags("a", edges)', "true"),
        ('deleteTags() tag("a*b?")', "geometry.tags()", "(1)[ab]"),  # op_tag filters out ? and *
        # cga_componentTags: i, insertAlongUV, primitiveXXX, footprint... clear the tags
        ('tag("a") primitiveCube()', "geometry.hasTags()", "false"),
        ('tag("a") t(1, 2, 3) r(0, 30, 0) s(2, 3, 4)', 'geometry.hasTags("a")', "true"),
    ],
)
def test_tags_are_read_and_deleted_as_the_functions_say(operations, function, expected, capsys):
    parse_grammar(f"Lot --> extrude(2) {operations} print({function})", "t.cga").build(lot=LOT)
    assert capsys.readouterr().out.strip().splitlines()[-1] == expected


# op_setback, "Component tags": on the shape, setback.front the original selected edges,
# setback.back the new setback edge, setback.side the side edges; on the remainder,
# setback.back the setback edge, setback.remainder the original edges (and, as its picture
# shows, the rest of a cut original edge is a side edge).
@pytest.mark.parametrize(
    "branch, expected",
    [
        ("front", {"setback.front": 1, "setback.back": 1, "setback.side": 2}),
        ("remainder", {"setback.back": 1, "setback.remainder": 1, "setback.side": 2}),
    ],
)
def test_setback_tags_the_edges_of_its_pieces(branch, expected):
    found = {}
    for query in expected:
        text = f"""Lot --> setback(4) {{ front : F | remainder : R }}
{"F" if branch == "front" else "R"} --> comp(e) {{ isTagged("{query}") : report("n", 1) X. }}
{"R" if branch == "front" else "F"} --> X."""
        found[query] = _count(_reports(text), "n")
    assert found == expected


# cga_componentTags, "Boolean operations": faces tagged by their operand, bool.A or bool.B, and
# the new intersection edges bool.cut. A 2 m cube without its corner unit cube: 3 faces from B,
# each meeting the faces of A along 2 edges.
def test_booleans_tag_faces_by_operand_and_the_cut_edges():
    text = """Lot --> s(2, 2, 2) subtract { primitiveCube() | t(1, 1, 1) primitiveCube() }
    comp(f) { isTagged("bool.B") : report("b", 1) X. | isTagged("bool.A") : report("a", 1) X. }
    comp(e) { isTagged("bool.cut") : report("cut", 1) X. }"""
    reports = _reports(text)
    assert _count(reports, "b") == 3
    assert _count(reports, "a") >= 6
    assert _count(reports, "cut") == 6


# op_setback: "isTagged(tagQuery): Selects tagged edges ... Edges can also be selected based on
# the tags of adjacent faces." The strips of the edges a branch selects are one face each where
# they meet (tests/data/prt_setback.json): all four edges of the 12 x 8 m lot are one ring.
@pytest.mark.parametrize(
    "operations, selector, shapes, area",
    [
        ('tag("E", edges)', 'isTagged("E") && front', 1, 24.0),
        ('tag("E", edges)', 'isTagged("E")', 1, 64.0),
        ('tag("F")', 'isTagged("F") && (back || left)', 1, 36.0),  # the tags of the face
        ('tag("E", edges)', 'isTagged("Other")', 0, 0.0),
    ],
)
def test_setback_selects_tagged_edges(operations, selector, shapes, area):
    text = (
        f'Lot --> {operations} setback(2) {{ {selector} : report("a", geometry.area) X. '
        "| remainder : R. }"
    )
    reports = _reports(text)
    assert _count(reports, "a") == shapes
    assert sum(np.atleast_1d(reports.get("a", 0.0))) == pytest.approx(area)


def test_is_tagged_outside_a_selector_is_an_error():
    with pytest.raises(Exception, match="selector of comp"):
        _reports('Lot --> extrude(2) print(isTagged("a"))')
