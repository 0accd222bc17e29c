"""Read and write records by file type: CSV (``.csv``), RPC III (``.rsp``, ``.drv``, ``.tim``, ``.rpc``),
ASAM MDF (``.mf4``, ``.mdf``, ``.dat``; written as MDF 4.10) and NI TDMS (``.tdms``, read only)."""

from __future__ import annotations

import os
from pathlib import Path

from rig.io.channel_map import ChannelMap
from rig.io.checks import check_plausible
from rig.io.csv_format import read_csv, write_csv
from rig.io.mdf_format import MDF_SUFFIXES, read_mdf, write_mdf
from rig.io.record import Record, RecordError
from rig.io.rpc3_format import read_rpc3, write_rpc3
from rig.io.tdms_format import read_tdms

_RPC3_SUFFIXES = {".rsp", ".drv", ".tim", ".rpc", ".rpc3"}
_KNOWN = "use .csv, RPC III .rsp/.drv/.tim, MDF .mf4 or TDMS .tdms"
#: file types ``write_record`` writes
WRITABLE_SUFFIXES = {".csv", *_RPC3_SUFFIXES, *MDF_SUFFIXES}


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
    if suffix == ".csv":
        record = read_csv(path, resample, channel_map)
    elif suffix in _RPC3_SUFFIXES:
        record = read_rpc3(path, channel_map)
    elif suffix in MDF_SUFFIXES:
        record = read_mdf(path, resample, channel_map)
    elif suffix == ".tdms":
        record = read_tdms(path, resample, channel_map)
    else:
        raise RecordError(f"{path}: unknown record type '{suffix}' ({_KNOWN})")
    check_plausible(record, str(path))
    return record


def write_record(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None) -> None:
    """Write a record to CSV, RPC III or MDF 4 according to the file's suffix, atomically."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        write_csv(path, record, units)
    elif suffix in _RPC3_SUFFIXES:
        write_rpc3(path, record, units)
    elif suffix in MDF_SUFFIXES:
        write_mdf(path, record, units)
    else:
        raise RecordError(f"{path}: cannot write record type '{suffix}' (use .csv, RPC III .rsp/.drv/.tim or MDF .mf4)")
