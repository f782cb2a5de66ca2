"""getTreeKey, edgeAttr, readMaterial, split's and splitArea's noAdjust, edges split in parts
(by split and in modify's recomposition) and rules defined twice, checked against the
statements and printed results of CityEngine's reference (func_getTreeKey, func_edgeAttr,
func_readMaterial, op_split, op_splitArea, op_modify, changelog)."""

from __future__ import annotations

import contextlib
import io

import pytest

from shapegen import load_grammar, parse_grammar
from shapegen.errors import ShapegenError

COVERS = {
    "test_tree_keys_as_the_reference_prints_them": ("func:getTreeKey",),
    "test_edge_attributes_give_the_default_with_a_warning": (
        "func:edgeAttr.getFloat",
        "func:edgeAttr.getString",
        "func:edgeAttr.getBool",
    ),
    "test_read_material_of_an_mtl_file": ("func:readMaterial",),
    "test_get_material_as_the_reference_prints_it": ("func:getMaterial",),
}


def _printed(text: str, lot=(12.0, 8.0)) -> tuple[list[str], dict]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        model = parse_grammar(text, "gaps.cga").build(lot=lot)
    return out.getvalue().splitlines(), model.metadata


# func_getTreeKey: the two examples and the console output the reference prints for them. The
# key is the path of child indices from the root; it stays the same through the whole rule
# (the shapes a split makes print their parent's key until their own rule starts).
_FACADE = """
Init-->
    print(getTreeKey() + " - Init")
    center(xz)
    extrude(10)
    comp(f) { front: Facade}
Facade-->
    print(getTreeKey() + " - Facade")
    split(y) {'0.5 : Floor }*
Floor-->
    print(getTreeKey() + " - Floor")
    split(x) { '0.1 : Wall | '0.3 : Window | '0.1 : Wall }*
Wall-->
    print(getTreeKey() + " - Wall")
Window-->
    print(getTreeKey() + " - Window")
"""
_FACADE_KEYS = [
    "0; - Init", "0;0; - Facade", "0;0;0; - Floor", "0;0;1; - Floor",
    "0;0;0;0; - Wall", "0;0;0;1; - Window", "0;0;0;2; - Wall", "0;0;0;3; - Wall",
    "0;0;0;4; - Window", "0;0;0;5; - Wall", "0;0;1;0; - Wall", "0;0;1;1; - Window",
    "0;0;1;2; - Wall", "0;0;1;3; - Wall", "0;0;1;4; - Window", "0;0;1;5; - Wall",
]  # fmt: skip
_SAME_KEY = """
ShapeA -->
    print(getTreeKey)
    split(x){ 2: ShapeB print(getTreeKey) | 3: ShapeC print(getTreeKey) }
"""


@pytest.mark.parametrize(
    "text, expected", [(_FACADE, _FACADE_KEYS), (_SAME_KEY, ["0;", "0;", "0;"])]
)
def test_tree_keys_as_the_reference_prints_them(text, expected):
    printed, _ = _printed(text)
    # shapegen derives depth first, CityEngine's console lists breadth first: the same keys
    assert sorted(printed) == sorted(expected)


# func_edgeAttr: "If no attribute /edgeattr/attributeName exists ... a default value is
# returned (0, "", false respectively)". shapegen's lots have none: the default, and a warning.
@pytest.mark.parametrize(
    "call, shown",
    [
        ('edgeAttr.getFloat("widths")', "0"),
        ('edgeAttr.getString("colors")', ""),
        ('edgeAttr.getBool("street")', "false"),
    ],
)
def test_edge_attributes_give_the_default_with_a_warning(call, shown):
    printed, metadata = _printed(f"Lot --> comp(f) {{ all : print({call}) X. }}")
    assert printed == [shown]
    assert any("no edge attributes" in w for w in metadata["warnings"])


# func_readMaterial: the file "as 2D string array of cga material attributes", which
# setMaterial() takes (op_setMaterial, example 2). A Wavefront .mtl file's first material.
_MTL = """# two materials: the first is read
newmtl Metal
Kd 0.5 0.25 1
Ns 20
d 0.8
map_Kd metal.png
newmtl Other
Kd 1 0 0
"""


def _derived_in(folder, text: str) -> tuple[list[str], dict]:
    rules = folder / "rules.cga"
    rules.write_text(text, "utf-8")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        model = load_grammar(rules).build(lot=(12.0, 8.0))
    return out.getvalue().split(), model.metadata


def test_read_material_of_an_mtl_file(tmp_path):
    (tmp_path / "metal.mtl").write_text(_MTL, "utf-8")
    printed, _ = _derived_in(
        tmp_path,
        'Lot --> primitiveCube() setMaterial(readMaterial("metal.mtl"))\n'
        "        print(material.color.r) print(material.color.b) print(material.opacity)\n"
        "        print(material.shininess) X.\n",
    )
    assert [float(v) for v in printed] == [0.5, 1.0, 0.8, 20.0]
    printed, metadata = _derived_in(
        tmp_path,
        'Lot --> setMaterial(readMaterial("nowhere.mtl")) print(material.opacity) X.\n',
    )
    assert printed == ["1"]  # the material as it was
    assert any("nowhere.mtl" in w and "not found" in w for w in metadata["warnings"])


# func_getMaterial, example 1: after color(0.5, 0.6, 0.7), getMaterial(used, changed) is the
# three rows color.b 0.7, color.g 0.6, color.r 0.5 (the reference prints them in another
# order); (shape, all) has every attribute, and setMaterial of it gives the default back.
def test_get_material_as_the_reference_prints_it():
    printed, _ = _printed(
        "Lot --> color(0.5, 0.6, 0.7) print(getMaterial(used, changed))\n"
        "        print(size(getMaterial(geometry, changed)))\n"
        "        print(getMaterial(shape, all)[0, 0]) A\n"
        "A --> setMaterial(getMaterial(geometry, all)) print(material.color.r) X.\n"
    )
    assert printed[0] == "(3x2)"
    assert sorted(line.split() for line in printed[1:4]) == [
        ["color.b", "0.7"], ["color.g", "0.6"], ["color.r", "0.5"]
    ]  # fmt: skip
    assert printed[4:] == ["0", "name", "1"]


# op_split, op_splitArea: "noAdjust avoids [adjusting the scope to the geometry's bounding
# box], therefore the scopes of the resulting shapes fill the parent's scope without gaps". A
# right triangle lot, its scope 8 m (x) by 12 m (z): cut at x = 6, the far piece is a triangle
# 2 m by 12 * 2 / 8 = 3 m; its quarter of the area is the similar triangle of half the size,
# 4 m by 6 m. With noAdjust each piece keeps the whole depth, and the widths add up to 8 m.
_TRIANGLE = [(0.0, 0.0), (12.0, 0.0), (0.0, 8.0)]


@pytest.mark.parametrize(
    "operation, sizes",
    [
        ("split(x) { 6 : A | ~1 : A }", [6.0, 12.0, 2.0, 3.0]),
        ("split(x, noAdjust) { 6 : A | ~1 : A }", [6.0, 12.0, 2.0, 12.0]),
        ("splitArea(x) { '0.75 : A | '0.25 : A }", [4.0, 12.0, 4.0, 6.0]),
        ("splitArea(x, noAdjust) { '0.75 : A | '0.25 : A }", [4.0, 12.0, 4.0, 12.0]),
    ],
)
def test_no_adjust_keeps_the_slices_of_the_scope(operation, sizes):
    printed, _ = _printed(
        f"Lot --> {operation}\nA --> print(scope.sx) print(scope.sz) X.", lot=_TRIANGLE
    )
    assert [float(v) for v in printed] == pytest.approx(sizes, abs=1e-9)


# An edge of comp(e) split in parts (op_modify's examples split edges: "Each iteration splits
# every edge into three parts"): the parts have the lengths of the pattern along the edge.
def test_an_edge_splits_into_edges():
    printed, _ = _printed(
        "Lot --> comp(e) { 0 : split(x) { '0.25 : A | ~1 : A | '0.25 : A } }\n"
        "A --> print(scope.sx) X."
    )
    assert [float(v) for v in printed] == pytest.approx([3.0, 6.0, 3.0])


# op_modify, "Chaikin's Corner Cutting Algorithm": every edge split into three parts, the last
# collapsed, cleanupGeometry merging the collapsed ends. Each round doubles the outline's
# corners (4 -> 8 -> 16), the new corners at 1/4 and 3/4 of each edge of the round before.
_CHAIKIN = """
Init --> ChaikinSmoothing({n})
ChaikinSmoothing(n) -->
    case n > 0:
        modify(fe) {{ all: SplitEdge }}
        modify(fe) {{ isTagged("Collapse"): s(0,0,0) X. }}
        cleanupGeometry(vertices,0)
        ChaikinSmoothing(n-1)
    else:
        print(geometry.nVertices) print(geometry.area) Done.
SplitEdge -->
    split(x) {{ '0.25: CornerCut.
             | ~1: Fixed.
             | '0.25: tag("Collapse") Collapse. }}
"""


@pytest.mark.parametrize(
    "rounds, corners, area",
    # one round cuts a corner triangle of legs 3 and 2 (a quarter of 12 and of 8) from each
    # corner of the 12 x 8 lot: 96 - 4 * 3 = 84 m2
    [(0, 4, 96.0), (1, 8, 84.0), (2, 16, None)],
)
def test_chaikin_corner_cutting(rounds, corners, area):
    printed, metadata = _printed(_CHAIKIN.format(n=rounds))
    assert int(float(printed[0])) == corners
    if area is not None:
        assert float(printed[1]) == pytest.approx(area)
    assert not [w for w in metadata["warnings"] if "modify" in w]


# op_modify, "Corrugated Facade": the edge the two footprints share split into outsets, each a
# centre part pushed in by Depth and shrunk to InnerL between two 0.01 m sides; extrude carries
# the edge tags to the facades. An 8 m shared edge holds two outsets (~4 m each).
_CORRUGATED = """
const OpeningL = 2
const Depth = 0.75
const InnerL = 1
Init -->
    inline(recompose) split(x) { 5:  tag("Front") F.
                               | ~1: tag("House") H. }
    modify(e) { isTagged("Front") && isTagged("House"):
        split(x) { ~4: CreateOutset }* }
    comp(f) { isTagged("House"): BuildHouse }
CreateOutset -->
    split(x) { ~1      : Wall.
             | 0.01    : tag("Side") Side.
             | OpeningL: tag("Outset") Outset
             | 0.01    : tag("Side") Side.
             | ~1      : Wall. }
Outset --> t(0,-Depth,0) s(InnerL,0,0) center(x)
BuildHouse -->
    extrude(3)
    comp(f) { isTagged("Side")  : report("side", scope.sx) Blue.
            | isTagged("Outset"): report("outset", scope.sx) Green.
            | all               = White. }
"""


def test_corrugated_facade():
    _, metadata = _printed(_CORRUGATED)
    reports = metadata["reports"]
    assert reports["side"] == pytest.approx([0.01] * 4)
    assert reports["outset"] == pytest.approx([1.0] * 2)  # InnerL


# A rule defined twice with the same parameters: CityEngine's compiler marks a "duplicate
# definition" (cga_changelog); op_pushpop's two House rules are alternatives, not one file.
def test_a_rule_defined_twice_is_refused():
    with pytest.raises(ShapegenError, match="duplicate rule 'House'"):
        parse_grammar("House --> extrude(10)\nHouse --> extrude(20)\n", "twice.cga")


# cga_changelog 2019.1: operations are told from rules of the same name by their signature. A
# rule ``i`` taking no parameters is what a bare ``i`` names (every signature of the operation
# i() takes arguments); with no such rule a bare ``i`` stays an operation written wrong.
def test_a_bare_name_is_the_rule_when_the_operation_needs_arguments():
    rules = 'Lot --> split(x) { 2 : i | ~1 : X. }\ni --> i("builtin:cube")\n'
    model = parse_grammar(rules, "rule_i.cga").build(lot=(12.0, 8.0))
    assert len(model.blocks) == 1  # the cube inserted into the 2 m piece
    with pytest.raises(ShapegenError, match="'i' is an operation"):
        parse_grammar("Lot --> split(x) { 2 : i | ~1 : X. }\n", "bare_i.cga")
