"""CGA errors of the runtime: an operation's bad argument or degenerate geometry in a ``.cga``.

CityEngine's runtime does not stop a generation there: it records a CGA error (PyPRT's
``GeneratedModel.get_cga_errors()``), skips the operation and derives on. An operation says so
by raising :class:`~shapegen.errors.OperationError` (``program.operation_error(node, message)``);
in a ``.cga`` file every operation is compiled :func:`carrying_on`, which turns it into a
warning at the operation's place (``file:line:col``), counted in the derivation's
``cga_errors``, and leaves the shape as it was before the operation. In a ``.grammar`` file the
error stops the derivation, as every error there does.
"""

from __future__ import annotations

__all__ = ["carrying_on", "record_cga_error"]

from shapegen.errors import GeometryError, OperationError


def record_cga_error(state, error: OperationError) -> None:
    """Count ``error`` in the derivation and list it once among its warnings."""
    run = state.run
    run.cga_errors += 1
    where = f"{error.location}: " if error.location is not None else ""
    run.warn(
        f"{where}{error.message}; the operation is skipped and the shape carries on, as "
        "CityEngine's runtime does (a CGA error)"
    )


def carrying_on(operation, node, program):
    """``operation`` (``op(state, args, out)``, compiled from ``node``) that records its
    :class:`OperationError`, or a geometry kernel's :class:`GeometryError` (located at
    ``node``), and lets the shape carry on as it was."""

    def carry_on(state, args, out):
        try:
            return operation(state, args, out)
        except OperationError as error:
            record_cga_error(state, error)
        except GeometryError as error:
            record_cga_error(state, program.operation_error(node, str(error)))
        return True

    return carry_on
