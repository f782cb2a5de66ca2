"""Output files of the commands: checked before any work, written all at once at the end."""

from __future__ import annotations

__all__ = ["check_outputs", "write_all"]

from pathlib import Path

from shapegen.errors import InputFormatError


def check_outputs(model: str | None, report: str | None, **others: str | None) -> None:
    """Fail before any work when an output cannot be written: an unknown model format, a missing
    or read-only folder, a folder named as a file, or two outputs naming the same file."""
    from shapegen.export.atomic import check_distinct, check_writable
    from shapegen.export.model_io import check_output_path

    if model:
        check_output_path(model)
    for path in (report, *others.values()):
        if path:
            check_writable(path)
    check_distinct(model=model, report=report, **others)


def write_all(outputs: list[tuple[Path, bytes]]) -> None:
    from shapegen.pipeline import write_outputs

    write_outputs(outputs)


def require_suffix(path: str | None, suffixes: tuple[str, ...], what: str) -> None:
    if path and Path(path).suffix.lower() not in suffixes:
        raise InputFormatError(f"{path}: {what} is written as {' or '.join(suffixes)}")
