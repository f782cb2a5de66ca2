"""The material shape attributes (attr_material, attr_material_color, attr_material_map) read
with the reference's defaults and set and read back; the annotations of cga_annotations load;
the keywords version and case/else (conditional rules and values) derive as described."""

from __future__ import annotations

import math

import pytest

from shapegen import parse_grammar
from shapegen.model.appearance import MATERIAL_ATTRIBUTES

_MAPS = (
    "colormap",
    "bumpmap",
    "dirtmap",
    "specularmap",
    "opacitymap",
    "normalmap",
    "emissivemap",
    "occlusionmap",
    "roughnessmap",
    "metallicmap",
)
# attr_material's defaults: white diffuse, black ambient, specular and emissive, opaque,
# shininess 1, bump 1, metallic 0, roughness 1, double-sided, no texture
DEFAULTS = {
    "name": "",
    "shader": "CityEngineShader",
    "color.rgb": "#ffffff",
    **{f"color.{c}": 1.0 for c in "rgb"},
    **{f"{k}.{c}": 0.0 for k in ("ambient", "specular", "emissive") for c in "rgb"},
    "opacity": 1.0,
    "reflectivity": 0.0,
    "shininess": 1.0,
    "bumpValue": 1.0,
    "metallic": 0.0,
    "roughness": 1.0,
    "doubleSided": True,
    "opacitymap.mode": "blend",
    "opacitymap.cutoff": 0.5,
    **dict.fromkeys(_MAPS, ""),
}
_FIELDS = ("su", "sv", "tu", "tv", "rw")

#: The reference entries each test shows (tools/cga_coverage.py reads this table).
COVERS = {
    "test_material_defaults": tuple(sorted(f"attr:material.{name}" for name in DEFAULTS)),
    "test_material_set_and_read_back": tuple(
        sorted(
            {f"attr:material.{name}" for name in DEFAULTS}
            | {f"attr:material.{{map}}.{field}" for field in _FIELDS}
        )
    ),
    "test_annotations_load": (
        "annotation:Angle",
        "annotation:Color",
        "annotation:Description",
        "annotation:Directory",
        "annotation:DisplayName",
        "annotation:Distance",
        "annotation:Enum",
        "annotation:File",
        "annotation:Group",
        "annotation:Handle",
        "annotation:Hidden",
        "annotation:InLine",
        "annotation:InMesh",
        "annotation:InPoint",
        "annotation:InPointCloud",
        "annotation:InPolygon",
        "annotation:MaterialFile",
        "annotation:Order",
        "annotation:Out",
        "annotation:Percent",
        "annotation:Range",
        "annotation:RuleFileDescription",
        "annotation:StartRule",
    ),
    "test_keywords": ("keyword:attr", "keyword:const", "keyword:version"),
    "test_case_and_else": ("keyword:case", "keyword:else"),
}


def _reports(text: str) -> dict:
    grammar = parse_grammar("@StartRule\n" + text, "material.cga")
    return grammar.build(lot=(12.0, 8.0)).metadata["reports"]


def test_material_defaults():
    reads = " ".join(f'report("{n}", material.{n})' for n in DEFAULTS)
    reports = _reports(f"Lot --> {reads} X.")
    assert reports == DEFAULTS


def _example(name: str):
    kind = MATERIAL_ATTRIBUTES[name][0]
    if name == "color.rgb":
        return '"#336699"', "#336699"
    if name == "opacitymap.mode":
        return '"mask"', "mask"
    if kind is str:
        return '"x.png"', "x.png"
    if kind is bool:
        return "false", False
    return "0.25", 0.25


@pytest.mark.parametrize(
    "name",
    sorted(DEFAULTS) + [f"{m}.{f}" for m in _MAPS for f in _FIELDS],
)
def test_material_set_and_read_back(name):
    written, value = _example(name)
    model = parse_grammar(
        f'@StartRule\nLot --> extrude(3) set(material.{name}, {written}) report("v", '
        f"material.{name}) X.",
        "material.cga",
    ).build(lot=(12.0, 8.0))
    assert model.metadata["reports"]["v"] == value
    look = model.blocks[0].appearance  # carried to the block (and the export)
    assert look is not None and not look.is_default


@pytest.mark.parametrize(
    "annotation",
    [
        "@Angle",
        "@Color",
        '@Description("a height")',
        "@Directory",
        '@DisplayName("Height")',
        "@Distance",
        '@Enum("a", "b")',
        "@File",
        '@Group("Shape", 1)',
        "@Handle(shape=Lot, axis=y)",
        "@Hidden",
        "@MaterialFile",
        "@Order(2)",
        "@Percent",
        "@Range(min=0, max=10)",
        '@RuleFileDescription("rules")',
    ],
)
def test_annotations_load(annotation):
    # cga_annotations: hints for the Inspector and other tools; they change nothing derived
    plain = parse_grammar('attr h = 3\n@StartRule\nLot --> report("h", h) X.', "a.cga")
    marked = parse_grammar(
        f"{annotation}\nattr h = 3\n@StartRule @InPolygon @InMesh @InLine @InPoint @InPointCloud "
        '@Out(granularity=separatedShapes)\nLot --> report("h", h) X.',
        "a.cga",
    )
    assert not marked.ast.warnings
    built = marked.build(lot=(12.0, 8.0))
    assert built.metadata["reports"] == plain.build(lot=(12.0, 8.0)).metadata["reports"]


def test_keywords():
    reports = _reports('attr a = 2\nconst b = a * 3\nLot --> report("a", a) report("b", b) X.')
    assert reports == {"a": 2.0, "b": 6.0}
    versioned = parse_grammar('version "2024.0"\n@StartRule\nLot --> report("v", 1) X.', "v.cga")
    assert versioned.build(lot=(4.0, 4.0)).metadata["reports"] == {"v": 1.0}


def test_case_and_else():
    reports = _reports(
        "c(x) = case x > 2 : 1 case x > 1 : 2 else : 3\n"
        'Lot --> case scope.sx > 20 : report("r", 1) X.\n'
        '        case scope.sx > 10 : report("r", 2) report("c", [c(3), c(2), c(1)]) X.\n'
        '        else : report("r", 3) X.'
    )
    assert reports["r"] == 2.0
    assert [*reports["c"].values] == [1.0, 2.0, 3.0]
    assert not math.isnan(reports["r"])
