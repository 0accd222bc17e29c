"""Text files as real tools write them: UTF-8 with or without a byte-order mark, UTF-16 with its mark (a
spreadsheet's "Unicode text"), or a Windows code page (an older DAQ's export); binary content is refused."""

from __future__ import annotations

import codecs
import os
from pathlib import Path

#: bytes looked at for binary content
_SNIFF = 1 << 16


def read_text(path: str | os.PathLike, what: str, error: type[ValueError] = ValueError) -> str:
    """The text of ``path`` (a ``what``: "record", "vehicle file"...); ``error`` names a binary file."""
    raw = Path(path).read_bytes()
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return raw.decode("utf-16")
    zero = raw.find(b"\x00", 0, _SNIFF)
    if zero >= 0:
        raise error(f"{path}: binary content (a zero byte at offset {zero}), not a text {what}")
    for encoding in ("utf-8-sig", "cp1252"):
        try:
            return raw.decode(encoding)
        except UnicodeDecodeError:
            continue
    return raw.decode("latin-1")  # every byte is a character: what is not text fails where it is parsed


def metadata_lines(lines: list[str]) -> tuple[dict[str, str], int]:
    """A text record's ``# key: value`` lines at the top (blank lines between them allowed), and the index of the
    first line after them (the header's)."""
    metadata: dict[str, str] = {}
    index = 0
    while index < len(lines) and (lines[index].startswith("#") or not lines[index].strip()):
        key, sep, value = lines[index].lstrip("#").partition(":")
        if sep and key.strip():
            metadata[key.strip()] = value.strip()
        index += 1
    return metadata, index
