"""CGA's appearance operations: colour, texture, material attributes, UV set-up and normals.

They follow CityEngine's reference (``op_color``, ``op_texture``, ``attr_material``,
``op_setMaterial``, ``op_resetMaterial``, the ``*UV`` operations, ``op_setNormals``,
``op_softenNormals``) and only change ``state.appearance``, an immutable
:class:`~shapegen.model.appearance.Appearance` that the children of a shape inherit and that
the model's blocks and surfaces carry to the export. They never touch a shape's geometry, and
the statics never read them.

What is kept where:

- ``color(...)``, ``material.color.{r,g,b,rgb}``: :attr:`Appearance.color` (sRGB in [0, 1],
  values outside clamped as CityEngine does); ``material.opacity`` (and the fourth component of
  ``color``): :attr:`Appearance.opacity`;
- ``texture(path)``, ``material.colormap``: :attr:`Appearance.texture`;
- every other ``material.*`` attribute: :attr:`Appearance.material`;
- ``setupProjection``, ``projectUV``, ``tileUV``, ``translateUV``, ``rotateUV``, ``scaleUV``,
  ``normalizeUV``, ``copyUV``, ``deleteUV``: recorded in :attr:`Appearance.uv` (no texture
  coordinates are computed); ``offsetUV``, translateUV's name before 2009.3 (cga_changelog), is
  recorded as translateUV with a warning;
- the deprecated material names (cga_changelog 2011.1: ``material.color.a`` for
  ``material.opacity``, ``material.map3``/``map4``/``map5`` for the specular, opacity and normal
  maps) set and read the current ones, with a warning;
- ``setNormals``, ``softenNormals``: :attr:`Appearance.normals`.

:func:`compile_material_set` compiles ``set(material.X, value)``; :func:`material_value` reads
``material.X`` for the expression language (the catalogue of names, their types and defaults
is :data:`~shapegen.model.appearance.MATERIAL_ATTRIBUTES`).
"""

from __future__ import annotations

__all__ = ["compile_material_set", "material_value"]

import math
from dataclasses import replace

from shapegen.engine.derivation.finite import finite_parameter
from shapegen.engine.expressions.arrays import Array, format_value, type_name
from shapegen.engine.expressions.shape_attributes import material_alias
from shapegen.engine.operations.cga.arguments import plain_arguments, typed
from shapegen.engine.operations.registry import (
    Unsupported,
    batch_form,
    is_column,
    operation,
    warn_at,
)
from shapegen.errors import did_you_mean
from shapegen.grammar import ast
from shapegen.model.appearance import (
    DEFAULT_APPEARANCE,
    MATERIAL_ATTRIBUTES,
    changed,
    material_value,
    parse_hex_color,
    with_material,
    with_uv,
)

_TYPE_NAMES = {float: "number", str: "string", bool: "boolean"}
UV_SETS = 10  # uv-sets 0..9, one per texture channel


def _clamped(value: float) -> float:
    return min(max(value, 0.0), 1.0)


def _checked_value(name: str, value: object) -> object:
    """``value`` for ``material.<name>`` if its type fits, else ``ValueError``."""
    kind = MATERIAL_ATTRIBUTES[name][0]
    if type(value) is kind:
        if kind is float and not math.isfinite(value):
            raise ValueError(f"material.{name} must be a finite number, got {value}")
        return value
    raise ValueError(
        f"material.{name} takes a {_TYPE_NAMES[kind]}, got a {type_name(value)} "
        f"({format_value(value)!r})"
    )


def _from_text(name: str, text: str) -> object:
    """A ``setMaterial`` value given as text, converted to the attribute's type."""
    kind = MATERIAL_ATTRIBUTES[name][0]
    if kind is str:
        return text
    if kind is bool:
        if text.strip().lower() not in ("true", "false"):
            raise ValueError(f"material.{name} takes true or false, got {text!r}")
        return text.strip().lower() == "true"
    try:
        number = float(text)
    except ValueError:
        raise ValueError(f"material.{name} takes a number, got {text!r}") from None
    return _checked_value(name, number)


def _material_name(program, node, attribute: str) -> str:
    """The catalogue name of ``material.<...>`` (prefix removed, a deprecated name replaced),
    or a load-time error with a did-you-mean."""
    name = material_alias(attribute.removeprefix("material."))
    if name in MATERIAL_ATTRIBUTES:
        return name
    shown = {known: f"material.{known}" for known in MATERIAL_ATTRIBUTES}
    hint = did_you_mean(name, MATERIAL_ATTRIBUTES, parenthesised=True, shown=shown)
    raise program.error(node, f"unknown material attribute 'material.{name}'{hint}")


# ------------------------------------------------------------------------- compilers
def compile_material_set(program, node: ast.Set, params: dict[str, int]):
    """The operation of ``set(material.X, value)``: checks ``X`` when the rule is compiled
    (an unknown name is an error with a did-you-mean) and the value's type when it runs."""
    name = _material_name(program, node, node.attribute)
    value_of = program.expressions.compile(node.value, params)
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)
    written = node.attribute.removeprefix("material.")

    def set_material(state, args, out):
        if written != name:
            warn_at(state, node, f"material.{written} is deprecated (cga_changelog 2011.1); "
                                 f"it sets material.{name}")  # fmt: skip
        try:
            value = value_of(args, state)
            if type(value) is float and MATERIAL_ATTRIBUTES[name][0] is float:
                value = finite_parameter(program, node, state, value, f"material.{name}")
            value = _checked_value(name, value)
            state.appearance = with_material(state.appearance, name, value)
        except ValueError as exc:
            raise error(node, f"set(material.{name}, ...): {exc}") from None
        return True

    return set_material


def _uv_set(program, node, expression, params, what: str = "the uv-set"):
    number = typed(program, node, expression, params, float, what)
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def uv_set(args, state):
        value = number(args, state)
        if value != int(value) or not 0 <= value < UV_SETS:
            raise error(
                node, f"{node.name}(): {what} is a whole number 0..{UV_SETS - 1}, got {value:g}"
            )
        return int(value)

    return uv_set


def _selector(program, node, expression, choices: tuple[str, ...], what: str) -> str:
    """A selector argument (``scope.xy``, ``soft``, ``separatePerFace``): read from the rule
    text, never evaluated; refused at load time unless it is one of ``choices``."""
    if isinstance(expression, ast.Name):
        text = expression.name
    elif isinstance(expression, ast.ShapeAttribute):
        text = f"{expression.obj}.{expression.field}"
    elif isinstance(expression, ast.String):
        text = expression.value
    else:
        text = None
    if text not in choices:
        hint = did_you_mean(text, choices, parenthesised=True) if text else ""
        shown = repr(text) if text is not None else f"a {type(expression).__name__}"
        raise program.error(
            node, f"{node.name}(): {what} is one of {', '.join(choices)}; got {shown}{hint}"
        )
    return text


@operation("color")
def compile_color(program, node: ast.Operation, params):
    arguments = plain_arguments(program, node, (1, 3, 4))
    error = program.error
    if len(arguments) == 1:
        text = typed(program, node, arguments[0], params, str, 'the colour ("#rrggbb")')
        if isinstance(arguments[0], ast.String):
            try:
                parse_hex_color(arguments[0].value)
            except ValueError as exc:
                raise error(node, f"color(): {exc}") from None

        def color_hex(state, args, out):
            try:
                rgb, opacity = parse_hex_color(text(args, state))
            except ValueError as exc:
                raise program.operation_error(node, f"color(): {exc}") from None
            look = changed(state.appearance, color=rgb)
            state.appearance = look if opacity is None else changed(look, opacity=opacity)
            return True

        return color_hex
    names = ("red", "green", "blue", "opacity")
    components = [
        typed(program, node, expression, params, float, names[k])
        for k, expression in enumerate(arguments)
    ]

    def color_components(state, args, out):
        values = [_clamped(component(args, state)) for component in components]
        look = changed(state.appearance, color=tuple(values[:3]))
        state.appearance = look if len(values) == 3 else changed(look, opacity=values[3])
        return True

    return color_components


@batch_form("color")
def batch_color(program, node: ast.Operation, params):
    """``color("#rrggbb")`` on a batch of lots: checked, as the one-shape form checks it; a
    city's lots are drawn in the colours of their statics (fixed, structural), not this one."""
    if len(node.arguments) != 1 or node.arguments[0].kind != "plain" or node.branches:
        raise Unsupported("color() with other than one argument")
    argument = node.arguments[0].value

    def color_batch(batch, out):
        value = batch.value(argument)
        if is_column(value) or type(value) is not str or len(value) != 7:
            raise Unsupported("color() of other than a #rrggbb string")
        try:
            parse_hex_color(value)
        except ValueError:
            raise Unsupported("color() of other than a #rrggbb string") from None
        return True

    return color_batch


@operation("texture")
def compile_texture(program, node: ast.Operation, params):
    (path,) = plain_arguments(program, node, (1,))
    path_of = typed(program, node, path, params, str, "the texture file")

    def texture(state, args, out):
        # texture() sets the colour map and resets the opacity map (op_texture); shapegen does
        # not read the image, so an alpha channel is not looked for.
        look = with_material(state.appearance, "colormap", path_of(args, state))
        state.appearance = with_material(look, "opacitymap", "")
        return True

    return texture


@operation("setMaterial")
def compile_set_material(program, node: ast.Operation, params):
    (pairs,) = plain_arguments(program, node, (1,))
    pairs_of = program.expressions.compile(pairs, params)
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def set_material(state, args, out):
        values = pairs_of(args, state)
        if isinstance(values, Array):  # what a string array literal or readMaterial() gives
            values = values.values
        if not isinstance(values, list | tuple) or len(values) % 2:
            raise error(
                node,
                "setMaterial() takes a string array of name, value pairs "
                f'(["color.r", "1", ...]), got {format_value(values)!r}',
            )
        look = state.appearance
        for key, text in zip(values[::2], values[1::2], strict=True):
            key, text = format_value(key), format_value(text)
            name = material_alias(key.removeprefix("material."))
            if name not in MATERIAL_ATTRIBUTES:
                hint = did_you_mean(name, MATERIAL_ATTRIBUTES, parenthesised=True)
                raise error(node, f"setMaterial(): unknown material attribute {key!r}{hint}")
            try:
                look = with_material(look, name, _from_text(name, text))
            except ValueError as exc:
                raise error(node, f"setMaterial(): {exc}") from None
        state.appearance = look
        return True

    return set_material


@operation("resetMaterial")
def compile_reset_material(program, node: ast.Operation, params):
    arguments = plain_arguments(program, node, (0, 1))
    target = "shape"
    if arguments:
        target = _selector(program, node, arguments[0], ("shape", "geometry", "all"), "the target")

    def reset_material(state, args, out):
        # An inserted asset's own materials are not carried, so "geometry" has nothing to reset.
        if target != "geometry":
            state.appearance = None
        return True

    return reset_material


def _recorder(name: str, values: list):
    """An operation appending ``(name, evaluated values)`` to the shape's UV log."""

    def record(state, args, out):
        entry = (name, tuple(v(args, state) if callable(v) else v for v in values))
        state.appearance = with_uv(state.appearance, entry)
        return True

    return record


_PROJECTION_AXES = tuple(
    f"{frame}.{u}{v}" for frame in ("scope", "world") for u in "xyz" for v in "xyz" if u != v
)


_NO_OFFSET = ast.OperationArgument("plain", ast.Number(0.0))
_OFFSET_UV = "deprecated name of translateUV (cga_changelog 2009.3), with a warning"
_RECORDED = "recorded for the export; shapegen computes no texture coordinates"


@operation("setupProjection", partial=_RECORDED)
def compile_setup_projection(program, node: ast.Operation, params):
    """setupProjection(uvSet, axes, width, height[, widthOffset, heightOffset[, uwFactor]]):
    width and height may be relative (``'0.5``: that share of the scope) or floating (``~2``:
    tiles of about 2 m fitting the scope a whole number of times), resolved on the scope.
    CGA's older form ``setupProjection(uvSet, axes, width, height, uwFactor)`` (the corpus's
    candler.cga) is the 7-argument one with both offsets 0."""
    count = len(node.arguments)
    if count not in (4, 5, 6, 7):
        raise program.error(node, f"setupProjection() takes 4, 5, 6 or 7 arguments, got {count}")
    if node.branches:
        raise program.error(node, "setupProjection() takes no { ... } block")
    first, second, *rest = node.arguments
    for argument in (first, second, *rest[4:]):
        if argument.kind != "plain":
            raise program.error(
                node,
                "setupProjection(): only the texture width, height and offsets may be relative",
            )
    uv_set = _uv_set(program, node, first.value, params)
    axes = _selector(program, node, second.value, _PROJECTION_AXES, "the projection axes")
    scope_axes = ["xyz".index(axes[-2]), "xyz".index(axes[-1])]
    sizes = []
    for k, argument in enumerate(rest[:2]):
        if argument.kind == "keyword":
            raise program.error(node, "setupProjection() takes no keyword arguments")
        number = typed(program, node, argument.value, params, float, ("width", "height")[k])
        sizes.append((number, argument.kind, scope_axes[k]))
    if count == 5:  # (..., uwFactor): no offsets
        rest = [*rest[:2], _NO_OFFSET, _NO_OFFSET, rest[2]]
    for k, argument in enumerate(rest[2:4]):  # offsets: '0.5 is half the scope, as a size
        if argument.kind in ("keyword", "floating"):
            raise program.error(node, "setupProjection(): an offset is a number or relative ('x)")
        number = typed(program, node, argument.value, params, float, "an offset")
        sizes.append((number, argument.kind, scope_axes[k]))
    others = [typed(program, node, a.value, params, float, "uwFactor") for a in rest[4:]]
    error = program.operation_error  # a CGA error in .cga (engine/derivation/cga_errors.py)

    def size(args, state, number, kind, axis):
        value = number(args, state)
        extent = state.shape.scope.d[axis]
        if kind == "relative":
            value *= extent
        elif kind == "floating":
            if value <= 0:
                raise error(node, f"setupProjection(): a floating size must be > 0, got {value:g}")
            value = extent / max(1, round(extent / value)) if extent > 0 else value
        return value

    def setup_projection(state, args, out):
        values = (
            uv_set(args, state),
            axes,
            *(size(args, state, *s) for s in sizes),
            *(o(args, state) for o in others),
        )
        state.appearance = with_uv(state.appearance, ("setupProjection", values))
        return True

    return setup_projection


@operation("projectUV", "deleteUV", partial=_RECORDED)
def compile_uv_set_only(program, node: ast.Operation, params):
    (uv_set,) = plain_arguments(program, node, (1,))
    uv_set_of = _uv_set(program, node, uv_set, params)
    if node.name == "projectUV":
        return _recorder("projectUV", [uv_set_of])

    def delete_uv(state, args, out):
        index = uv_set_of(args, state)
        look = state.appearance or DEFAULT_APPEARANCE
        kept = tuple(entry for entry in look.uv if _uv_target(entry) != index)
        state.appearance = replace(look, uv=kept + (("deleteUV", (index,)),))
        return True

    return delete_uv


def _uv_target(entry: tuple) -> int:
    """The uv-set an entry of the UV log writes to (copyUV writes to its second)."""
    name, values = entry
    return values[1] if name == "copyUV" else values[0]


@operation("tileUV", partial=_RECORDED)
def compile_tile_uv(program, node: ast.Operation, params):
    """tileUV(uvSet, width, height): the sizes are kept with their mode (``'``, ``~``) since
    they refer to the texture space, which shapegen does not compute."""
    if len(node.arguments) != 3 or node.branches:
        raise program.error(node, f"tileUV() takes 3 arguments, got {len(node.arguments)}")
    first, *sizes = node.arguments
    uv_set = _uv_set(program, node, first.value, params)
    compiled = []
    for k, argument in enumerate(sizes):
        if argument.kind == "keyword":
            raise program.error(node, "tileUV() takes no keyword arguments")
        number = typed(program, node, argument.value, params, float, ("width", "height")[k])
        prefix = {"plain": "", "relative": "'", "floating": "~"}[argument.kind]
        compiled.append(
            number if not prefix else (lambda a, s, n=number, p=prefix: f"{p}{n(a, s):g}")
        )
    return _recorder("tileUV", [uv_set, *compiled])


@operation(
    "translateUV",
    "scaleUV",
    "rotateUV",
    "offsetUV",
    partial={"offsetUV": _OFFSET_UV, "translateUV": _RECORDED, "scaleUV": _RECORDED}
    | {"rotateUV": _RECORDED},
)
def compile_uv_transform(program, node: ast.Operation, params):
    counts = (2,) if node.name == "rotateUV" else (3,)
    first, *rest = plain_arguments(program, node, counts)
    uv_set = _uv_set(program, node, first, params)
    numbers = [typed(program, node, r, params, float, "a factor or offset") for r in rest]
    if node.name != "offsetUV":
        return _recorder(node.name, [uv_set, *numbers])
    record = _recorder("translateUV", [uv_set, *numbers])

    def offset_uv(state, args, out):
        warn_at(state, node, "offsetUV() is deprecated (cga_changelog 2009.3: it is now "
                             "translateUV); recorded as translateUV")  # fmt: skip
        return record(state, args, out)

    return offset_uv


@operation("normalizeUV", partial=_RECORDED)
def compile_normalize_uv(program, node: ast.Operation, params):
    first, mode, kind = plain_arguments(program, node, (3,))
    uv_set = _uv_set(program, node, first, params)
    mode = _selector(program, node, mode, ("uv", "uvUniform", "u", "v"), "the mode")
    kind = _selector(
        program, node, kind, ("separatePerFace", "collectiveAllFaces"), "the normalize type"
    )
    return _recorder("normalizeUV", [uv_set, mode, kind])


@operation("copyUV", partial=_RECORDED)
def compile_copy_uv(program, node: ast.Operation, params):
    source, target = plain_arguments(program, node, (2,))
    source_of = _uv_set(program, node, source, params, "the source uv-set")
    target_of = _uv_set(program, node, target, params, "the destination uv-set")
    return _recorder("copyUV", [source_of, target_of])


_NORMAL_MODES = ("hard", "conform", "soft", "auto")


@operation("setNormals")
def compile_set_normals(program, node: ast.Operation, params):
    (mode,) = plain_arguments(program, node, (1,))
    mode = _selector(program, node, mode, _NORMAL_MODES, "the normals mode")

    def set_normals(state, args, out):
        state.appearance = replace(state.appearance or DEFAULT_APPEARANCE, normals=mode)
        return True

    return set_normals


@operation("softenNormals")
def compile_soften_normals(program, node: ast.Operation, params):
    (angle,) = plain_arguments(program, node, (1,))
    angle_of = typed(program, node, angle, params, float, "the angle (degrees)")

    def soften_normals(state, args, out):
        # op_softenNormals: 0 degrees is setNormals(hard), 180 is setNormals(soft).
        value = min(max(angle_of(args, state), 0.0), 180.0)
        state.appearance = replace(state.appearance or DEFAULT_APPEARANCE, normals=value)
        return True

    return soften_normals
