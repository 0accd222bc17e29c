"""What a record file format is: the suffixes it owns, how it reads and writes a record, and how messages name it.

A format module (``rig/io/<name>_format.py``) holds one ``FORMAT``; rig/io/files.py finds those modules, so a new file
format is a new module and nothing else: ``read_record`` and ``write_record`` dispatch on its suffixes, and the
messages that list the formats name it. ``rig.io.files.register_format`` adds one at run time (a test's throwaway
format).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from rig.io.channel_map import ChannelMap
from rig.io.record import Record

#: read(path, resample, channel_map): ``resample`` lets irregular time stamps through, interpolated onto a uniform grid
Reader = Callable[[Path, bool, ChannelMap | None], Record]
#: write(path, record, units): ``units`` maps channels to the units to write them in (default SI), atomically
Writer = Callable[[Path, Record, dict[str, str] | None], None]


@dataclass(frozen=True)
class RecordFormat:
    """A record file format: ``suffixes`` (lower case, with the dot), ``read``, ``write`` (None: read only),
    ``label`` (how a message that lists the formats names it: ``RPC III .rsp/.drv/.tim``) and ``order`` (its place
    in that list)."""

    suffixes: tuple[str, ...]
    read: Reader
    label: str
    write: Writer | None = None
    order: int = 100


def listed(labels: list[str]) -> str:
    """``a, b or c``."""
    return labels[0] if len(labels) == 1 else f"{', '.join(labels[:-1])} or {labels[-1]}"
