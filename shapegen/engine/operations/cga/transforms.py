"""The scope moved, turned, sized or centred: ``t``, ``r``, ``s``, ``center`` (the parser's
nodes of their own), and ``translate(mode, coordSystem, x, y, z)`` and ``rotate(mode,
coordSystem, x, y, z)`` (op_translate, op_rotate): the scope moved or turned in one of the frames of
:mod:`shapegen.engine.shapes.frames` (``scope``, ``pivot``, ``object``, ``world``); the
geometry moves with the scope, as after ``t`` and ``r``.

- ``translate(abs, ...)`` puts the scope's origin at ``(x, y, z)`` of the frame,
  ``translate(rel, ...)`` adds the vector ``(x, y, z)`` along the frame's axes
  (``translate(rel, scope, ...)`` is ``t``);
- ``rotate(abs, ...)`` sets the scope's orientation in the frame to the Euler angles ``(x, y,
  z)`` (degrees, cga_eulerAngles), ``rotate(rel, ...)`` adds them to the scope's angles in that
  frame ("relative means the angles are added"); the scope turns about its origin.
"""

from __future__ import annotations

__all__ = [
    "compile_center",
    "compile_r",
    "compile_rotate",
    "compile_s",
    "compile_t",
    "compile_translate",
]


import numpy as np

from shapegen.engine.derivation.finite import finite_parameter
from shapegen.engine.expressions.arrays import type_name
from shapegen.engine.operations.cga.arguments import argument_word, plain_arguments
from shapegen.engine.operations.registry import operation
from shapegen.engine.shapes.frames import FRAMES, euler_angles, euler_matrix, frame_of
from shapegen.engine.shapes.shape import center as centered_scope
from shapegen.engine.shapes.shape import rotate as rotated_scope
from shapegen.engine.shapes.shape import translate as translated_scope
from shapegen.grammar import ast
from shapegen.model.scope import Scope

_MODES = ("abs", "rel")


def _vector(program, node, compiled, args, state) -> np.ndarray:
    values = [c(args, state) for c in compiled]
    for value in values:
        if type(value) is not float:
            raise program.error(node, f"{node.name}() needs numbers, got a {type_name(value)}")
    # .cga: nan and inf are 0 with a warning, as CityEngine's runtime does
    return np.array([finite_parameter(program, node, state, v, f"{node.name}()") for v in values])


def _compiled_numbers(program, node, params):
    values = [a.value for a in node.arguments[2:]]
    return [program.expressions.compile(v, params) for v in values]


def _words(program, node):
    plain_arguments(program, node, range(len(node.arguments) + 1))  # plain, no block
    if len(node.arguments) != 5:
        raise program.error(
            node, f"{node.name}() takes (mode, coordSystem, x, y, z), got {len(node.arguments)}"
        )
    words = []
    for argument, choices, what in zip(
        node.arguments, (_MODES, FRAMES), ("mode", "coordSystem"), strict=False
    ):
        word = argument_word(argument.value)
        if word not in choices:
            raise program.error(
                node,
                f"{node.name}()'s {what} is one of {', '.join(choices)}; got {word or 'a value'}",
            )
        words.append(word)
    return words


@operation("translate")
def compile_translate(program, node: ast.Operation, params):
    mode, system = _words(program, node)
    numbers = _compiled_numbers(program, node, params)

    def translate(state, args, out):
        vector = _vector(program, node, numbers, args, state)
        shape = state.shape
        scope = shape.scope
        origin, axes = frame_of(state, system)
        if mode == "rel" or system == "scope":  # the scope's own origin is 0 in its frame
            moved = scope.origin + axes @ vector
        else:
            moved = origin + axes @ vector
        state.shape = shape.with_scope(Scope(moved, scope.rotation, scope.size))
        return True

    return translate


@operation("rotate")
def compile_rotate(program, node: ast.Operation, params):
    mode, system = _words(program, node)
    numbers = _compiled_numbers(program, node, params)

    def rotate(state, args, out):
        angles = _vector(program, node, numbers, args, state)
        shape = state.shape
        scope = shape.scope
        _, axes = frame_of(state, system)
        if mode == "rel":
            angles = angles + np.array(euler_angles(axes.T @ scope.rotation))
        turned = axes @ euler_matrix(angles)
        state.shape = shape.with_scope(Scope(scope.origin, turned, scope.size))
        return True

    return rotate


def _coordinates(program, node, coordinates, params, what: str):
    """A closure giving the values of ``t()``'s or ``s()``'s coordinates (m; ``'x`` relative
    to the scope's size)."""
    compiled = [
        (program.number(node, c.value, params, what), c.relative, k)
        for k, c in enumerate(coordinates)
    ]

    def values(args, state):
        size = state.shape.scope.d  # floats: an overflow is inf, not a warning
        return [
            value(args, state) * size[k] if relative else value(args, state)
            for value, relative, k in compiled
        ]

    return values


@operation("t", nodes=(ast.Translate,))
def compile_t(program, node: ast.Translate, params):
    """``t(x, y, z)``: the scope moved along its own axes."""
    values = _coordinates(program, node, (node.x, node.y, node.z), params, "a t() offset")

    def translate_op(state, args, out):
        state.shape = state.shape.with_scope(
            translated_scope(state.shape.scope, values(args, state))
        )
        return True

    return translate_op


@operation("s", nodes=(ast.Scale,))
def compile_s(program, node: ast.Scale, params):
    """``s(x, y, z)``: the scope's size set, the geometry scaled with it."""
    values = _coordinates(program, node, (node.x, node.y, node.z), params, "an s() size")
    operation_error = program.operation_error

    def scale_op(state, args, out):
        try:
            state.shape = state.shape.resized(values(args, state))
        except ValueError as exc:
            raise operation_error(node, str(exc)) from None
        return True

    return scale_op


@operation(
    "r",
    nodes=(ast.Rotate,),
    partial="turns about the scope's own axes: rotate(rel, pivot, ...) while they are the pivot's",
)
def compile_r(program, node: ast.Rotate, params):
    """``r([scopeCenter,] x, y, z)``: the scope turned (degrees) about its origin or centre."""
    angles = [program.number(node, e, params, "an r() angle") for e in (node.x, node.y, node.z)]
    about_center = node.pivot == "center"

    def rotate_op(state, args, out):
        values = [angle(args, state) for angle in angles]
        state.shape = state.shape.with_scope(rotated_scope(state.shape.scope, values, about_center))
        return True

    return rotate_op


@operation("center", nodes=(ast.Center,))
def compile_center(program, node: ast.Center, params):
    """``center(axes)``: the scope centred in the shape's initial scope along ``axes``."""
    axes = node.axes
    if not axes or any(a not in "xyz" for a in axes):
        raise program.error(node, f"center() takes x, y, z, xy, xz, yz or xyz, got {axes!r}")

    def center_op(state, args, out):
        scope = centered_scope(state.shape.scope, state.initial_scope, axes)
        state.shape = state.shape.with_scope(scope)
        return True

    return center_op
