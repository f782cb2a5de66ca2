"""The bytes of an input file and the JSON in them, refused in one line when they cannot be
read: not a regular file, over the work limits (``max_file_bytes``, a gzipped file's once
inflated; ``max_json_depth``), not a whole gzip stream, not UTF-8, not JSON.

A gzipped file is inflated in a stream (:class:`gzip.GzipFile`) that stops as soon as it has
given more than ``max_file_bytes``: a small file that inflates to gigabytes costs what the limit
costs. A JSON document's nesting is measured before it is decoded (brackets outside strings,
counted at C speed), so a document nested 100 000 arrays deep is refused by its depth instead of
exhausting the decoder's recursion.
"""

from __future__ import annotations

__all__ = [
    "GZIP_MAGIC",
    "is_gzip_file",
    "json_depth",
    "parse_json_document",
    "read_input_bytes",
    "read_model_bytes",
]

import gzip
import json
import re
import stat
import zlib
from pathlib import Path

import numpy as np

from shapegen.errors import InputFormatError
from shapegen.limits import current_limits, limit_hint

#: Integers with more digits than this are read as floats (10**400 becomes inf, which the
#: checks then refuse by name), so no number is beyond what the checks can compare.
_MAX_INT_DIGITS = 20


GZIP_MAGIC = b"\x1f\x8b"


def read_model_bytes(path: str | Path) -> bytes:
    """The bytes of a model file (see :func:`read_input_bytes`)."""
    return read_input_bytes(path, "model file")


def read_input_bytes(path: str | Path, kind: str = "model file", *, gunzip: bool = False) -> bytes:
    """The bytes of an input file, refused before reading when it is not a regular file (a FIFO
    would block, a device such as /dev/zero never ends) or is over ``max_file_bytes``
    (:class:`~shapegen.limits.WorkLimits`). With ``gunzip``, a gzipped file (by its first two
    bytes) comes inflated, refused as soon as it inflates past ``max_file_bytes``. ``kind``
    names what the file should be in the messages (``"lots file"``)."""
    path = Path(path)
    try:
        status = path.stat()
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if not stat.S_ISREG(status.st_mode):
        what = "a folder" if stat.S_ISDIR(status.st_mode) else "a device, pipe or socket"
        raise InputFormatError(f"{path}: not a {kind} ({what})")
    limit = current_limits().max_file_bytes
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)  # the file may have grown since stat()
            if status.st_size > limit or len(data) > limit:
                size = max(status.st_size, len(data))
                raise InputFormatError(
                    f"{path}: the file has {size} bytes, more than {limit} "
                    + limit_hint("max_file_bytes")
                )
            if gunzip and data[:2] == GZIP_MAGIC:
                handle.seek(0)
                return _inflated(handle, path, limit)
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None
    return data


def is_gzip_file(path: str | Path) -> bool:
    """True when the file at ``path`` starts as a gzip stream does (its first two bytes)."""
    try:
        with open(path, "rb") as handle:
            return handle.read(2) == GZIP_MAGIC
    except OSError as exc:
        raise InputFormatError(f"{path}: cannot read ({exc.strerror or exc})") from None


def _inflated(handle, path: Path, limit: int) -> bytes:
    """The inflated bytes of a gzip file, read in a stream that stops past ``limit``."""
    try:
        with gzip.GzipFile(fileobj=handle, mode="rb") as stream:
            data = stream.read(limit + 1)
    except (OSError, EOFError, zlib.error) as exc:
        reason = "it ends before its data does" if isinstance(exc, EOFError) else exc
        raise InputFormatError(f"{path}: not a whole gzip file ({reason})") from None
    if len(data) > limit:
        raise InputFormatError(
            f"{path}: the gzipped file inflates to more than {limit} bytes "
            + limit_hint("max_file_bytes")
        )
    return data


# A JSON string, escapes included (unrolled: no backtracking on long strings).
_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"', re.DOTALL)
_OPENING = np.zeros(256, dtype=np.int8)
_OPENING[[ord("["), ord("{")]] = 1
_OPENING[[ord("]"), ord("}")]] = -1


def json_depth(data: bytes | str) -> int:
    """How deep arrays and objects nest in a JSON text (brackets within strings do not count);
    read at C speed, without decoding."""
    raw = data.encode("utf-8", "surrogatepass") if isinstance(data, str) else data
    if b"[" not in raw and b"{" not in raw:
        return 0
    bare = _JSON_STRING.sub(b'""', raw)  # UTF-8 keeps ASCII bytes out of multi-byte characters
    steps = _OPENING[np.frombuffer(bare, dtype=np.uint8)]
    steps = steps[steps != 0]
    return int(np.cumsum(steps, dtype=np.int64).max(initial=0))


def parse_json_document(data: bytes | str, where: str, expected: str = "") -> object:
    """A JSON document from a file's contents; every failure is an InputFormatError, whose
    message says ``expected`` (``"not a GeoJSON file"``) before what is wrong, when given.

    Integers of more than 20 digits are read as floats (10**400 becomes inf, which the checks
    then refuse by name), so no number is beyond what the checks can compare. A document nested
    deeper than ``max_json_depth`` is refused before it is decoded.
    """
    said = f"{expected}: " if expected else ""
    try:
        text = data.decode("utf-8") if isinstance(data, bytes) else data
    except UnicodeDecodeError:
        raise InputFormatError(f"{where}: {said}not a text file (invalid UTF-8)") from None
    limit = current_limits().max_json_depth
    depth = json_depth(data)
    if depth > limit:
        raise InputFormatError(
            f"{where}: the JSON nests too deeply ({depth} arrays or objects in one another, "
            f"more than {limit}) " + limit_hint("max_json_depth")
        )
    try:
        return json.loads(text, parse_int=_parse_int)
    except json.JSONDecodeError as exc:
        raise InputFormatError(
            f"{where}:{exc.lineno}:{exc.colno}: {said}invalid JSON: {exc.msg}"
        ) from None
    except RecursionError:
        raise InputFormatError(f"{where}: the JSON nests too deeply to read") from None
    except ValueError as exc:  # any other refusal of the decoder
        raise InputFormatError(f"{where}: {said}invalid JSON: {exc}") from None


def _parse_int(text: str) -> int | float:
    return int(text) if len(text) <= _MAX_INT_DIGITS else float(text)
