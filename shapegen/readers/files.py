"""The bytes of an input file and the JSON in them, refused in one line when they cannot be
read: not a regular file, over the work limits, not UTF-8, not JSON."""

from __future__ import annotations

__all__ = ["parse_json_document", "read_model_bytes"]

import json
import stat
from pathlib import Path

from shapegen.errors import InputFormatError
from shapegen.limits import current_limits, limit_hint

#: Integers with more digits than this are read as floats (10**400 becomes inf, which the
#: checks then refuse by name), so no number is beyond what the checks can compare.
_MAX_INT_DIGITS = 20


def read_model_bytes(path: str | Path) -> bytes:
    """The bytes of an input file, refused before reading when it is not a regular file (a FIFO
    would block, a device such as /dev/zero never ends) or is over ``max_file_bytes``
    (:class:`~shapegen.limits.WorkLimits`)."""
    path = Path(path)
    try:
        status = path.stat()
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(status.st_mode):
        kind = "a folder" if stat.S_ISDIR(status.st_mode) else "a device, pipe or socket"
        raise InputFormatError(f"{path}: not a model file ({kind})")
    limit = current_limits().max_file_bytes
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)  # the file may have grown since stat()
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if status.st_size > limit or len(data) > limit:
        raise InputFormatError(
            f"{path}: the file has {max(status.st_size, len(data))} bytes, more than {limit} "
            + limit_hint("max_file_bytes")
        )
    return data


def parse_json_document(data: bytes | str, where: str) -> object:
    """A JSON document from a file's contents; every failure is an InputFormatError.

    Integers of more than 20 digits are read as floats (10**400 becomes inf, which the checks
    then refuse by name), so no number is beyond what the checks can compare.
    """
    try:
        text = data.decode("utf-8") if isinstance(data, bytes) else data
    except UnicodeDecodeError:
        raise InputFormatError(f"{where}: not a text file (invalid UTF-8)") from None
    try:
        return json.loads(text, parse_int=_parse_int)
    except json.JSONDecodeError as exc:
        raise InputFormatError(
            f"{where}:{exc.lineno}:{exc.colno}: invalid JSON: {exc.msg}"
        ) from None
    except RecursionError:
        raise InputFormatError(f"{where}: the JSON nests too deeply to read") from None
    except ValueError as exc:  # any other refusal of the decoder
        raise InputFormatError(f"{where}: invalid JSON: {exc}") from None


def _parse_int(text: str) -> int | float:
    return int(text) if len(text) <= _MAX_INT_DIGITS else float(text)
