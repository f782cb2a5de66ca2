"""What an operation does with a number that is not finite: one boundary for every dialect.

A parameter that is inf or NaN (:func:`finite_parameter`), and a shape that an operation makes
with a coordinate or a size that is inf, NaN or beyond the work limit ``max_coordinate``
(:func:`checked_operation`, :func:`checked_child`), are CGA errors of the runtime in a
``.cga`` file (:mod:`~shapegen.engine.derivation.cga_errors`: a warning at the operation's
place, the operation is skipped and the shape carries on, as CityEngine's runtime does), and
errors at their place in a ``.grammar`` file. So no such number reaches the model, the statics or a
writer."""

from __future__ import annotations

__all__ = [
    "CLEARS_TAGS",
    "checked_child",
    "checked_operation",
    "finite_parameter",
    "overflowed",
    "shape_problem",
    "with_carried_tags",
]

import math

import numpy as np

from shapegen.engine.shapes.shape import Shape
from shapegen.errors import OperationError, WorkLimitError
from shapegen.grammar import ast
from shapegen.limits import limit_hint


def finite_parameter(program, node, state, value: float, what: str) -> float:
    """``value`` when finite. Otherwise, in a ``.cga`` file, 0 and a warning: CityEngine's
    runtime replaces an inf or nan float parameter of its builtins with zero by default
    (cga_changelog 2013.1, "inf/nan checks"); in a ``.grammar`` file an error naming ``what``."""
    if math.isfinite(value):
        return value
    if program.cga_dialect:
        state.run.warn(f"{node.location}: {what} is {value}: replaced by 0, as CityEngine does")
        return 0.0
    raise program.error(node, f"{what} must be a finite number, got {value}")


def shape_problem(shape: Shape, bound: float, before: Shape | None = None) -> str | None:
    """None when ``shape``'s scope and geometry are finite numbers within ``bound`` (m), else
    what is wrong, for a message. The geometry is looked at only when it is not ``before``'s
    (a move or a turn keeps it)."""
    scope = shape.scope
    numbers = scope.o + scope.d
    # a sum carries an inf or a NaN through (and overflows only past the bound)
    total = sum(numbers) + sum(scope.r)
    ok = math.isfinite(total) and -bound <= min(numbers) and max(numbers) <= bound
    geometry = shape.geometry
    vertices = None
    if geometry is not None and (before is None or geometry is not before.geometry):
        vertices = geometry.vertices
        if ok and len(vertices):
            ok = float(np.abs(vertices).max()) <= bound
    if ok:
        return None
    arrays = [scope.origin, scope.size, scope.rotation.ravel()]
    if vertices is not None:
        arrays.append(vertices.ravel())
    values = np.concatenate(arrays)
    with np.errstate(invalid="ignore"):
        bad = values[~(np.abs(values) <= bound)]
    worst = float(bad[0]) if len(bad) else math.inf  # the sum overflowed: a huge reach
    if math.isnan(worst):
        return "has a coordinate that is NaN (not a number)"
    if math.isinf(worst):
        return "has a coordinate that is infinite"
    return f"reaches {abs(worst):.3g} m, beyond {bound:g} m " + limit_hint("max_coordinate")


_KEEPS_SHAPE = (ast.Successor, ast.Nil, ast.Push, ast.Label, ast.Print, ast.Report)

_NAMES = {
    "Extrude": "extrude",
    "Translate": "t",
    "Scale": "s",
    "Rotate": "r",
    "Center": "center",
    "Insert": "i",
    "Split": "split",
    "Comp": "comp",
    "CompBranch": "comp",  # a shape a comp's branch makes
    "Set": "set",
}


#: The operations that replace the geometry and so clear its component tags
#: (cga_componentTags: "i (insert), insertAlongUV operations, primitiveXXX operations, footprint
#: operation, resetGeometry operation"; splitArea and reduceGeometry "do (currently) not support
#: working with component tags and clear all tags").
CLEARS_TAGS = frozenset(
    {
        "i",
        "insert",
        "insertAlongUV",
        "footprint",
        "resetGeometry",
        "splitArea",
        "reduceGeometry",
        "primitiveCube",
        "primitiveCylinder",
        "primitiveCone",
        "primitiveDisk",
        "primitiveQuad",
        "primitiveSphere",
        "primitiveTorus",
    }
)


def with_carried_tags(before: Shape, shape: Shape) -> Shape:
    """``shape`` (made from ``before`` by an operation that gives no tags of its own) with the
    component tags of ``before`` that its components keep, worked out when read
    (:func:`~shapegen.engine.shapes.tags.carried_tags`)."""
    from shapegen.engine.shapes.tags import Pending

    return shape.with_tags(Pending(before))


def operation_name(node) -> str:
    """``extrude``, ``t``, ``roofHip``: the name of the operation ``node`` as written."""
    kind = type(node).__name__
    return _NAMES.get(kind) or getattr(node, "name", None) or kind.lower()


def checked_operation(program, node, operation):
    """``operation`` (a compiled :data:`~shapegen.engine.derivation.state.Operation`) followed by a
    look at the shape it leaves. A mesh of more than ``max_mesh_faces`` faces is an error; a
    shape that is not finite or too large (``max_coordinate``), or arithmetic that overflows
    on the way (``OverflowError``), is :func:`overflowed`. An operation that fails leaves the
    shape as it was and none of the successors it had made. The items that never change the
    shape (a successor, ``NIL``, ``[ ]``, ``label``, ``print``, ``report``) are left as they are."""
    if isinstance(node, _KEEPS_SHAPE):
        return operation
    name = operation_name(node)

    def checked(state, args, out):
        before = state.shape
        made = len(out)
        try:
            going_on = operation(state, args, out)
            shape = state.shape
            if shape is before:
                return going_on
            if before.tags is not None and shape.tags is None and name not in CLEARS_TAGS:
                # (before has tags only where the derivation keeps them: Derivation.tags)
                state.shape = shape = with_carried_tags(before, shape)
            limits = state.run.limits
            geometry = shape.geometry
            if geometry is not None and geometry is not before.geometry:
                state.run.check_clock(node)  # a mesh's work grows with its faces
                faces = len(geometry.faces)
                if faces > limits.max_mesh_faces:
                    raise program.error(
                        node,
                        f"{name}(): the shape it makes has {faces} faces, more than "
                        f"{limits.max_mesh_faces} " + limit_hint("max_mesh_faces", limits),
                    )
            problem = shape_problem(shape, limits.max_coordinate, before)
            if problem is not None:
                raise overflowed(program, node, f"the shape it makes {problem}")
            return going_on
        except OverflowError:  # a number past a float's range on the way (int(inf), 10.0**400)
            state.shape = before
            del out[made:]
            raise overflowed(program, node, "a number it works out overflows") from None
        except OperationError:
            state.shape = before
            del out[made:]
            raise
        except WorkLimitError as exc:  # a kernel's loop past the clock: at this operation
            raise program.error(node, f"{name}(): {exc}") from None

    return checked


def overflowed(program, node, problem: str) -> OperationError:
    """The error of an operation at ``node`` whose result is out of range (``problem``, for
    the message): a CGA error the shape carries on past in a ``.cga`` file, an error in a
    ``.grammar`` file."""
    # ``program`` is what can place an error at ``node``: the operations' compiler, or the
    # program a derivation's new shape is checked for (Derivation.child)
    # a generic operation's branch (setback's front : ...) is placed, and not named, here
    prefix = "" if type(node).__name__ == "OperationBranch" else f"{operation_name(node)}(): "
    message = prefix + problem
    error = program.error(node, message)
    return OperationError(message, error.location, error.source)


def checked_child(program, node, parent, shape: Shape) -> None:
    """Raise :func:`overflowed` for a new shape below ``parent`` that is not finite or
    beyond ``max_coordinate`` (the operation that makes it fails as a whole)."""
    problem = shape_problem(shape, parent.run.limits.max_coordinate)
    if problem is not None:
        raise overflowed(program, node, f"a shape it makes {problem}")
