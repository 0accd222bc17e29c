"""Read and write records by file type, each type a format module (``rig/io/<name>_format.py`` holding a ``FORMAT``,
rig/io/formats.py): CSV (``.csv``), RPC III (``.rsp``, ``.drv``, ``.tim``, ``.rpc``), ASAM MDF (``.mf4``, ``.mdf``,
``.dat``; written as MDF 4.10) and NI TDMS (``.tdms``, read only). The modules are found on first use, so a new file
format is a new module; ``register_format`` adds one at run time."""

from __future__ import annotations

import functools
import importlib
import os
import pkgutil
from pathlib import Path

from rig.io.channel_map import ChannelMap
from rig.io.checks import check_plausible
from rig.io.formats import RecordFormat, listed
from rig.io.record import Record, RecordError

_REGISTERED: list[RecordFormat] = []


@functools.cache
def _found() -> tuple[RecordFormat, ...]:
    """The ``FORMAT`` of every module of this package named ``*_format``."""
    package = __name__.rpartition(".")[0]
    return tuple(importlib.import_module(f"{package}.{info.name}").FORMAT
                 for info in pkgutil.iter_modules([str(Path(__file__).parent)]) if info.name.endswith("_format"))


def record_formats() -> list[RecordFormat]:
    """Every format, in the order messages list them."""
    return sorted([*_found(), *_REGISTERED], key=lambda f: f.order)


def register_format(record_format: RecordFormat) -> None:
    """Add a format from outside this package (a test's throwaway one); its suffixes must be new."""
    taken = {s for f in record_formats() for s in f.suffixes} & set(record_format.suffixes)
    if taken:
        raise ValueError(f"suffix(es) {', '.join(sorted(taken))} already have a record format")
    _REGISTERED.append(record_format)


def unregister_format(record_format: RecordFormat) -> None:
    _REGISTERED.remove(record_format)


def writable_suffixes() -> set[str]:
    """The file types ``write_record`` writes."""
    return {s for f in record_formats() if f.write is not None for s in f.suffixes}


def _format_of(suffix: str) -> RecordFormat | None:
    return next((f for f in record_formats() if suffix in f.suffixes), None)


def read_record(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read a record from a CSV, RPC III, MDF or TDMS file, in SI units.

    ``resample`` lets irregular time stamps through (a CSV time column, an MDF group, a TDMS time
    channel), interpolated onto a uniform grid (the metadata key ``resampled`` says so); RPC III files
    are uniformly sampled by construction. ``channel_map`` (``rig.io.channel_map``) picks the channels
    and names them by the contract; the metadata key ``unmapped`` lists the channels it left out. A value no
    vehicle test produces is refused (``rig.io.checks.check_plausible``).
    """
    path = Path(path)
    if not path.is_file():
        raise RecordError(f"{path}: no such file")
    suffix = path.suffix.lower()
    record_format = _format_of(suffix)
    if record_format is None:
        raise RecordError(f"{path}: unknown record type '{suffix}' "
                          f"(use {listed([f.label for f in record_formats()])})")
    record = record_format.read(path, resample, channel_map)
    check_plausible(record, str(path))
    return record


def write_record(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None) -> None:
    """Write a record to CSV, RPC III or MDF 4 according to the file's suffix, atomically."""
    suffix = Path(path).suffix.lower()
    record_format = _format_of(suffix)
    if record_format is None or record_format.write is None:
        raise RecordError(f"{path}: cannot write record type '{suffix}' "
                          f"(use {listed([f.label for f in record_formats() if f.write is not None])})")
    record_format.write(path, record, units)
