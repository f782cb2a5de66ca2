"""Reading a rule file's text as CityEngine does: UTF-8 (with or without a byte-order mark),
else Windows-1252, the encoding of rule files written on Windows before CityEngine wrote UTF-8
(umlauts and degree signs in comments).

>>> import tempfile, pathlib
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> (folder / "old.cga").write_bytes(b"// H\\xf6he in m\\nLot --> extrude(3)\\n")
32
>>> text, warning = read_rule_file(folder / "old.cga")
>>> text.splitlines()[0], warning
('// Höhe in m', 'not UTF-8: read as Windows-1252 (cp1252)')
"""

from __future__ import annotations

__all__ = ["read_rule_file"]

import codecs
from pathlib import Path

from shapegen.errors import GrammarError
from shapegen.grammar.parser import source_too_long
from shapegen.limits import current_limits

#: UTF-8 spends at most 4 bytes on a character: a file larger than this many bytes per allowed
#: character is refused before it is read.
_MAX_BYTES_PER_CHARACTER = 4


def read_rule_file(path: Path, what: str = "") -> tuple[str, str | None]:
    """The text of the rule file ``path`` and, when it is not UTF-8, a warning naming the
    encoding it was read in (None for UTF-8).

    Parameters
    ----------
    path
        The file.
    what
        How an error names the file (``"the imported file"``); empty for the file itself.

    Raises
    ------
    GrammarError
        For a file that cannot be read, or is larger than the work limits allow.
    """
    shown = f"{what} {str(path)!r}" if what else repr(str(path))
    try:
        size = path.stat().st_size
        if size > _MAX_BYTES_PER_CHARACTER * current_limits().max_source_chars:
            raise GrammarError(f"{path}: {source_too_long(size, 'bytes')}")
        data = path.read_bytes()
    except OSError as exc:
        raise GrammarError(f"cannot read {shown}: {exc.strerror or exc}") from None
    if data.startswith(codecs.BOM_UTF8):
        data = data[len(codecs.BOM_UTF8) :]
    try:
        return data.decode("utf-8"), None
    except UnicodeDecodeError:
        pass
    if b"\0" in data:
        raise GrammarError(f"cannot read {shown}: it is not text (it holds NUL bytes)")
    try:
        return data.decode("cp1252"), "not UTF-8: read as Windows-1252 (cp1252)"
    except UnicodeDecodeError:  # one of the five bytes cp1252 leaves undefined
        return data.decode("latin-1"), "not UTF-8 nor Windows-1252: read as Latin-1"
