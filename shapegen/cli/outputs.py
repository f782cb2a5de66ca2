"""Output files of the commands: checked before any work, written all at once at the end.

Every check names the option and the path (``-o out: is a folder; name a file to write``), so
a mistake costs nothing: it is found before a model is built or a search is run.
"""

from __future__ import annotations

__all__ = ["check_outputs", "print_written", "require_suffix", "write_all"]

from collections.abc import Mapping, Sequence
from pathlib import Path

from shapegen.cli.common_options import CommandLineError
from shapegen.errors import InputFormatError


def check_outputs(
    files: Mapping[str, str | None],
    *,
    models: Sequence[str] = (),
    folders: Mapping[str, str | None] | None = None,
) -> None:
    """Fail before any work when an output cannot be written.

    ``files`` maps each output option (``"-o"``, ``"--report"``) to the file it names (None when
    not given); the options in ``models`` are model files, whose extension must name a format.
    ``folders`` maps options that name a folder to fill (``--frames``) to it. Refused, with the
    option and the path: a folder named as a file, a missing or unwritable folder (tried by
    creating a file there), an unknown model format, and two options naming the same file.
    """
    from shapegen.export.atomic import check_distinct, check_writable
    from shapegen.export.model_io import check_output_path

    for option, path in files.items():
        if not path:
            continue
        try:
            check_writable(path)
            if option in models:
                check_output_path(path)
        except InputFormatError as exc:
            raise CommandLineError(f"{option} {exc}") from None
    for option, path in (folders or {}).items():
        if path:
            _check_folder(option, Path(path))
    try:
        check_distinct({option: path for option, path in files.items() if path})
    except InputFormatError as exc:
        raise CommandLineError(str(exc)) from None


def _check_folder(option: str, folder: Path) -> None:
    """A folder to fill with files: it is a folder, or it can be created in a writable one."""
    from shapegen.export.atomic import check_writable

    if folder.exists() and not folder.is_dir():
        raise CommandLineError(f"{option} {folder}: exists and is not a folder")
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise CommandLineError(f"{option} {folder}: {existing} is not a folder")
    try:
        check_writable(existing / ".shapegen")  # tries to create a file in it
    except InputFormatError:
        raise CommandLineError(f"{option} {folder}: folder {existing} is not writable") from None


def write_all(outputs: list[tuple[Path, bytes]]) -> None:
    from shapegen.pipeline import write_outputs

    write_outputs(outputs)


def print_written(outputs: list[tuple[Path, bytes]]) -> None:
    """One line per file written, ``wrote arch.glb (45.2 kB)``, in the order given: what a
    command made is named, not left to be guessed from its options."""
    for path, content in outputs:
        print(f"wrote {path} ({_size(len(content))})", flush=True)


def _size(count: int) -> str:
    if count < 1000:
        return f"{count} bytes"
    for unit in ("kB", "MB", "GB"):
        count /= 1000
        if count < 1000 or unit == "GB":
            return f"{count:.3g} {unit}"
    raise AssertionError("unreachable")


def require_suffix(path: str | None, suffixes: tuple[str, ...], what: str, option: str = "-o"):
    """Refuse an output whose extension is not one of ``suffixes`` (``what`` says what it is)."""
    if path and Path(path).suffix.lower() not in suffixes:
        raise CommandLineError(f"{option} {path}: {what} is written as {' or '.join(suffixes)}")
