"""Read and write records by file type: CSV (``.csv``) or RPC III (``.rsp``, ``.drv``, ``.tim``, ``.rpc``)."""

from __future__ import annotations

import os
from pathlib import Path

from rig.io.channel_map import ChannelMap
from rig.io.csv_format import read_csv, write_csv
from rig.io.record import Record, RecordError
from rig.io.rpc3_format import read_rpc3, write_rpc3

_RPC3_SUFFIXES = {".rsp", ".drv", ".tim", ".rpc", ".rpc3"}


def read_record(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read a record from a CSV or RPC III file, in SI units.

    ``resample`` lets a CSV with irregular time stamps through, interpolated onto a uniform grid
    (its metadata key ``resampled`` says so); RPC III files are uniformly sampled by construction.
    ``channel_map`` (``rig.io.channel_map``) picks the channels and names them by the contract; the
    metadata key ``unmapped`` lists the channels it left out.
    """
    path = Path(path)
    if not path.is_file():
        raise RecordError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return read_csv(path, resample, channel_map)
    if suffix in _RPC3_SUFFIXES:
        return read_rpc3(path, channel_map)
    raise RecordError(f"{path}: unknown record type '{suffix}' (use .csv or RPC III .rsp/.drv/.tim)")


def write_record(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None) -> None:
    """Write a record to CSV or RPC III according to the file's suffix, atomically."""
    suffix = Path(path).suffix.lower()
    if suffix == ".csv":
        write_csv(path, record, units)
    elif suffix in _RPC3_SUFFIXES:
        write_rpc3(path, record, units)
    else:
        raise RecordError(f"{path}: unknown record type '{suffix}' (use .csv or RPC III .rsp/.drv/.tim)")
