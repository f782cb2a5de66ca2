"""CGA's appearance operations (colour, texture, material attributes, UV set-up, normals):
what each leaves on ``state.appearance``, and the errors for a wrong use.

The operations are compiled from hand-made AST nodes on a real program and run on the lot's
shape, so these tests do not depend on how the parser spells a call.
"""

from __future__ import annotations

import pytest
from operation_nodes import lot_state, operation, operations_program

import shapegen
from shapegen.engine.operations.cga.appearance import compile_material_set
from shapegen.engine.operations.registry import compiler_for
from shapegen.errors import GrammarError
from shapegen.grammar import ast
from shapegen.model.appearance import DEFAULT_APPEARANCE, material_value, parse_hex_color


@pytest.fixture(scope="module")
def program():
    return operations_program()


def _state(program, width=6.0, depth=4.0):
    return lot_state(program, width, depth)


def _operation(name, *values, kinds=None):
    return operation(name, *values, kinds=kinds, text=ast.String)


def run(program, *operations, state=None):
    """Compile and run ``operations`` (name, arguments...) in order on one shape."""
    state = state or _state(program)
    for item in operations:
        if isinstance(item, ast.Set):
            op = compile_material_set(program, item, {})
        else:
            op = compiler_for(item.name)(program, item, {})
        assert op(state, (), []) is True
    return state


# ------------------------------------------------------------------------------ colour
@pytest.mark.parametrize(
    "arguments, rgb, opacity",
    [
        (("#ff0000",), (1.0, 0.0, 0.0), 1.0),
        (("#336699",), (0x33 / 255, 0x66 / 255, 0x99 / 255), 1.0),
        (("#ff000080",), (1.0, 0.0, 0.0), 0x80 / 255),
        ((1, 0, 0), (1.0, 0.0, 0.0), 1.0),
        ((0.2, 0.4, 0.6, 0.5), (0.2, 0.4, 0.6), 0.5),
        ((2.0, -1.0, 0.5, 3.0), (1.0, 0.0, 0.5), 1.0),  # clamped to [0, 1] (op_color)
    ],
)
def test_color_forms(program, arguments, rgb, opacity):
    state = run(program, _operation("color", *arguments))
    assert state.appearance.color == pytest.approx(rgb)
    assert state.appearance.opacity == pytest.approx(opacity)


def test_three_ways_to_set_a_colour_agree(program):
    """op_color's example: color("#ff0000"), color(1, 0, 0) and set(material.color.r/g/b)."""
    hex_form = run(program, _operation("color", "#ff0000")).appearance
    components = run(program, _operation("color", 1, 0, 0)).appearance
    sets = run(
        program,
        ast.Set("material.color.r", ast.Number(1.0)),
        ast.Set("material.color.g", ast.Number(0.0)),
        ast.Set("material.color.b", ast.Number(0.0)),
    ).appearance
    assert hex_form == components == sets


def test_one_component_keeps_the_default_white(program):
    state = run(program, ast.Set("material.color.g", ast.Number(0.25)))
    assert state.appearance.color == (1.0, 0.25, 1.0)
    assert material_value(state.appearance, "color.rgb") == "#ff40ff"


@pytest.mark.parametrize("text", ["red", "#ff00", "#gg0000", "ff0000", "#ff0000ff00"])
def test_bad_hex_colour_is_one_clear_error(program, text):
    with pytest.raises(GrammarError, match=r'color\(\): a colour is "#rrggbb"'):
        run(program, _operation("color", text))


def test_color_argument_count_and_types(program):
    with pytest.raises(GrammarError, match=r"color\(\) takes 1 or 3 or 4 arguments, got 2"):
        run(program, _operation("color", 1, 0))
    with pytest.raises(GrammarError, match=r"color\(\): green must be a finite number"):
        run(program, _operation("color", 1, "x", 0))


def test_children_inherit_and_push_does_not_leak(program):
    parent = run(program, _operation("color", "#00ff00"))
    child = parent.run.child(parent, parent.shape, None)
    assert child.appearance is parent.appearance
    copy = parent.copy()
    run(program, _operation("color", "#0000ff"), state=copy)
    assert parent.appearance.color == (0.0, 1.0, 0.0)
    assert copy.appearance.color == (0.0, 0.0, 1.0)


# ------------------------------------------------------------------------------ material
def test_material_attributes_are_typed_and_kept(program):
    state = run(
        program,
        ast.Set("material.opacity", ast.Number(0.4)),
        ast.Set("material.metallic", ast.Number(0.7)),
        ast.Set("material.name", ast.String("stone")),
        ast.Set("material.doubleSided", ast.Boolean(False)),
        ast.Set("material.colormap", ast.String("textures/brick.jpg")),
    )
    look = state.appearance
    assert look.opacity == 0.4
    assert look.texture == "textures/brick.jpg"
    assert dict(look.material) == {"metallic": 0.7, "name": "stone", "doubleSided": False}
    assert material_value(look, "roughness") == 1.0  # the reference's default
    assert material_value(None, "shader") == "CityEngineShader"


def test_unknown_material_attribute_has_a_did_you_mean(program):
    with pytest.raises(
        GrammarError, match=r"'material\.colr\.r' \(did you mean 'material\.color\.r'"
    ):
        run(program, ast.Set("material.colr.r", ast.Number(1.0)))


def test_material_value_type_is_checked(program):
    with pytest.raises(GrammarError, match=r"material\.opacity takes a number, got a string"):
        run(program, ast.Set("material.opacity", ast.String("half")))
    with pytest.raises(GrammarError, match=r"opacitymap\.mode is one of blend, mask, opaque"):
        run(program, ast.Set("material.opacitymap.mode", ast.String("cutout")))


def test_set_material_takes_name_value_pairs(program, monkeypatch):
    """op_setMaterial's first example; the string array is what the argument evaluates to."""
    pairs = ["color.r", "1.0", "color.g", "0.0", "color.b", "0.0", "opacitymap", "builtin:default"]

    monkeypatch.setattr(
        program.expressions, "compile", lambda expression, params: lambda a, s: list(pairs)
    )
    state = run(program, _operation("setMaterial", 0))
    assert state.appearance.color == (1.0, 0.0, 0.0)
    assert dict(state.appearance.material)["opacitymap"] == "builtin:default"
    pairs[1] = "bright"
    with pytest.raises(GrammarError, match=r"material\.color\.r takes a number, got 'bright'"):
        run(program, _operation("setMaterial", 0))
    pairs[:2] = ["colour.r", "1"]
    with pytest.raises(GrammarError, match=r"unknown material attribute 'colour\.r' \(did you"):
        run(program, _operation("setMaterial", 0))


def test_texture_sets_the_colour_map_and_resets_the_opacity_map(program):
    state = run(
        program,
        ast.Set("material.opacitymap", ast.String("alpha.png")),
        _operation("texture", "facade.jpg"),
    )
    assert state.appearance.texture == "facade.jpg"
    assert material_value(state.appearance, "opacitymap") == ""


@pytest.mark.parametrize("target, reset", [(None, True), ("@shape", True), ("@all", True),
                                           ("@geometry", False)])  # fmt: skip
def test_reset_material(program, target, reset):
    operations = [_operation("color", "#123456")]
    operations.append(_operation("resetMaterial", *([target] if target else [])))
    state = run(program, *operations)
    assert (state.appearance is None) is reset


def test_reset_material_target_is_checked(program):
    with pytest.raises(GrammarError, match=r"one of shape, geometry, all; got 'geomtry' \(did"):
        run(program, _operation("resetMaterial", "@geomtry"))


# ------------------------------------------------------------------------------ UV and normals
def test_uv_operations_are_recorded_in_order(program):
    state = run(
        program,
        _operation("setupProjection", 0, "@scope.xy", 2.0, 1.5),
        _operation("projectUV", 0),
        _operation("scaleUV", 0, 2, 3),
        _operation("translateUV", 0, 0.5, 0),
        _operation("rotateUV", 0, 90),
        _operation("normalizeUV", 0, "@uvUniform", "@collectiveAllFaces"),
        _operation("copyUV", 0, 2),
        _operation("tileUV", 2, 1.0, 1.0, kinds=["plain", "floating", "relative"]),
    )
    assert [name for name, _ in state.appearance.uv] == [
        "setupProjection", "projectUV", "scaleUV", "translateUV", "rotateUV", "normalizeUV",
        "copyUV", "tileUV",
    ]  # fmt: skip
    uv = dict(state.appearance.uv)
    assert uv["setupProjection"] == (0, "scope.xy", 2.0, 1.5)
    assert uv["scaleUV"] == (0, 2.0, 3.0)
    assert uv["tileUV"] == (2, "~1", "'1")
    assert state.appearance.color is None  # the UV set-up leaves the colour alone


def test_setup_projection_resolves_relative_and_floating_sizes_on_the_scope(program):
    """'0.5 is half the scope's extent; ~2.5 is the tile size that fits the extent a whole
    number of times (6 m along x: 2 tiles of 3 m; 4 m along z: 2 tiles of 2 m)."""
    state = run(
        program,
        _operation("setupProjection", 1, "@scope.xz", 0.5, 2.5, kinds=["plain", "plain",
                                                                         "relative", "floating"]),
    )  # fmt: skip
    ((_, values),) = state.appearance.uv
    assert values == (1, "scope.xz", 3.0, 2.0)


def test_delete_uv_drops_that_set_only(program):
    state = run(
        program,
        _operation("scaleUV", 0, 2, 2),
        _operation("scaleUV", 1, 3, 3),
        _operation("deleteUV", 0),
    )
    assert state.appearance.uv == (("scaleUV", (1, 3.0, 3.0)), ("deleteUV", (0,)))


@pytest.mark.parametrize(
    "operation, message",
    [
        (_operation("scaleUV", 10, 1, 1), r"the uv-set is a whole number 0\.\.9, got 10"),
        (_operation("projectUV", 0.5), r"the uv-set is a whole number 0\.\.9, got 0\.5"),
        (_operation("setupProjection", 0, "@scope.xx", 1, 1), r"the projection axes is one of"),
        (_operation("normalizeUV", 0, "@uvw", "@separatePerFace"), r"the mode is one of uv,"),
        (_operation("rotateUV", 0), r"rotateUV\(\) takes 2 arguments, got 1"),
        (_operation("setNormals", "@smooth"), r"the normals mode is one of hard, conform"),
    ],
)
def test_uv_and_normals_errors(program, operation, message):
    with pytest.raises(GrammarError, match=message):
        run(program, operation)


def test_normals(program):
    assert run(program, _operation("setNormals", "@soft")).appearance.normals == "soft"
    assert run(program, _operation("softenNormals", 45)).appearance.normals == 45.0
    assert run(program, _operation("softenNormals", 400)).appearance.normals == 180.0


def test_appearance_round_trips_as_json(program):
    look = run(
        program,
        _operation("color", 0.2, 0.4, 0.6, 0.5),
        _operation("texture", "t.png"),
        _operation("scaleUV", 0, 2, 2),
        _operation("setNormals", "@hard"),
    ).appearance
    assert type(look).from_dict(look.to_dict()) == look
    assert DEFAULT_APPEARANCE.to_dict() == {}


def test_parse_hex_color():
    assert parse_hex_color("#FFFFFF") == ((1.0, 1.0, 1.0), None)
    with pytest.raises(ValueError):
        parse_hex_color("#fff")


def test_rule_text_end_to_end():
    """From rule text to the blocks' appearance: each piece keeps its own colour and UV set-up,
    and the colour never changes the geometry (a 16-sided cylinder in a 2 x 2 x 4 m scope, its
    flats fitted to it as CityEngine's runtime fits them: 8 sin(pi/8) x 1 x 2 / cos(pi/16)^2
    m^2 of base, 2 m high)."""
    import math

    grammar = shapegen.parse_grammar(
        "@StartRule\n"
        'Lot --> extrude(2) split(x) { 2 : color("#ff0000") A. | 2 : set(material.color.g, 0.5)'
        " primitiveCylinder() B. | ~1 : setupProjection(0, scope.xy, 1, 1) projectUV(0) C. }"
    )
    a, b, c = grammar.build(lot=(8, 4)).blocks
    assert a.appearance.color == (1.0, 0.0, 0.0) and a.volume == pytest.approx(2 * 2 * 4)
    assert b.appearance.color == (1.0, 0.5, 1.0)
    base = 8 * math.sin(math.pi / 8) * 1 * 2 / math.cos(math.pi / 16) ** 2
    assert b.volume == pytest.approx(base * 2)
    assert c.appearance.uv == (("setupProjection", (0, "scope.xy", 1.0, 1.0)), ("projectUV", (0,)))


def test_set_material_reads_a_string_array_written_in_the_file():
    """op_setMaterial's first example as text: the argument is a CGA string array."""
    grammar = shapegen.parse_grammar(
        'Lot --> setMaterial(["color.r", "1.0", "color.g", "0.0", "color.b", "0.0"]) X',
        "set_material.cga",
    )
    model = grammar.build(lot=(4.0, 2.0))
    colours = {tuple(surface.appearance.color) for surface in model.surfaces}
    assert colours == {(1.0, 0.0, 0.0)}
