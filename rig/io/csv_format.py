"""Test-record CSV files (contract: docs/contracts.md): ``# key: value`` metadata, ``name [unit]`` header, time first.

Units in brackets are converted to SI on import; the writer stores SI (or the units asked for).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from rig.io.atomic import atomic_path
from rig.io.channel_map import ChannelMap, plan_channels, plan_metadata
from rig.io.formats import RecordFormat
from rig.io.labview_csv import is_lab_export, read_lab_csv
from rig.io.record import Record, RecordError
from rig.io.text import metadata_lines, read_text
from rig.io.time_stamps import on_uniform_time, printed_resolution
from rig.io.units import UnitError, si_to, to_si

_HEADER_FIELD = re.compile(r"^\s*(?P<name>[^\[\]]+?)\s*(\[(?P<unit>[^\]]*)\])?\s*$")


def read_csv(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read a test-record CSV into a Record in SI units, through ``channel_map`` if given.

    The rate is fitted to the whole time column, whose stamps may be rounded as printed
    (``rig.time_stamps``). Refuses, with a message naming the column or row: a first column that is not
    ``time``, a column without a unit or with an unknown one, duplicate channels, non-numeric, NaN or
    infinite values, and time that is not uniformly sampled: gaps, repeated or reversed stamps. With
    ``resample`` an irregular (but increasing) log is interpolated onto a uniform grid instead, and the
    record's metadata key ``resampled`` says so. A channel map (``rig.io.channel_map``) picks and renames
    the columns and may give their units; the columns it leaves out are not checked.
    """
    path = Path(path)
    lines = read_text(path, "CSV record", RecordError).splitlines()
    if is_lab_export(lines):  # LabVIEW-style pairs, quoted headers, units in parentheses, ISO stamps
        return read_lab_csv(path, resample, channel_map)
    metadata, index = metadata_lines(lines)
    if index == len(lines):
        raise RecordError(f"{path}: no header line (expected 'time [s],<corner>/<quantity> [unit],...')")
    header_line = index + 1  # 1-based line number, for messages
    names, file_units, time_factor = _parse_header(path, lines[index])
    plan = plan_channels(path, dict(zip(names[1:], file_units[1:])), channel_map,
                         {name: f"header column {col}" for col, name in enumerate(names[1:], start=2)})
    metadata.update(plan_metadata(plan, channel_map))
    data_lines = lines[index + 1:]
    read = [0] + [names.index(source) for source in plan.sources]
    table = _numbers(path, data_lines, names, read, header_line)
    time = table[:, 0] * time_factor
    resolution = printed_resolution([line.split(",", 1)[0] for line in data_lines]) * time_factor
    base, values, irregular = on_uniform_time(  # only the columns read were checked
        time, resolution, table[:, read], resample, str(path),
        lambda row: f"data row {row + 1} (line {header_line + row + 1})")
    if irregular:
        table = np.full((values.shape[0], table.shape[1]), np.nan)
        table[:, read] = values
        metadata["resampled"] = (f"irregular time stamps ({time.size} rows, {irregular}) linearly interpolated "
                                 f"to {base.rate:g} Hz")
    channels = {c.name: c.apply(table[:, names.index(c.source)]) for c in plan.conversions}
    return Record(base.rate, channels, {c.name: c.unit for c in plan.conversions}, metadata, start_time=base.start)


def _numbers(path: Path, data_lines: list[str], names: list[str], read: list[int], header_line: int) -> np.ndarray:
    """The samples as a table (rows x columns); the columns ``read`` must be finite numbers, at least two rows."""
    if len(data_lines) < 2:
        raise RecordError(f"{path}: needs at least two rows of samples, found {len(data_lines)}")
    try:
        table = np.loadtxt(data_lines, delimiter=",", ndmin=2)
    except ValueError as err:
        raise RecordError(f"{path}: {_locate_parse_error(data_lines, len(names), header_line)} ({err})") from None
    if table.shape[1] != len(names):
        raise RecordError(f"{path}: header has {len(names)} columns but rows have {table.shape[1]}")
    bad_rows, bad_cols = np.nonzero(~np.isfinite(table[:, read]))
    if bad_rows.size:
        row, col = bad_rows[0], read[bad_cols[0]]
        raise RecordError(f"{path}: column '{names[col]}' has a non-finite value ({table[row, col]}) "
                          f"in data row {row + 1} (line {header_line + row + 1})")
    return table


def write_csv(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None) -> None:
    """Write ``record`` as a contract CSV, atomically; ``units`` optionally maps channels to export units."""
    units = units or {}
    header = ["time [s]"]
    columns = [record.time]
    for name in record.names:
        unit = units.get(name, record.units[name])
        header.append(f"{name} [{unit}]")
        columns.append(record[name] * si_to(unit, record.units[name]))
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as out:
        for key, value in record.metadata.items():
            out.write(f"# {key}: {value}\n")
        out.write(",".join(header) + "\n")
        np.savetxt(out, np.column_stack(columns), delimiter=",", fmt="%.10g")


def _parse_header(path: Path, line: str) -> tuple[list[str], list[str], float]:
    """Column names, their units as written, and the factor that converts the time column to s."""
    names, units = [], []
    for col, field in enumerate(line.split(","), start=1):
        match = _HEADER_FIELD.match(field)
        if not match:
            raise RecordError(f"{path}: header column {col} '{field.strip()}' is not 'name [unit]'")
        name, unit = match["name"], match["unit"]
        if unit is None:
            raise RecordError(f"{path}: header column {col} '{name}' has no unit; write it as '{name} [unit]'")
        if name in names:
            raise RecordError(f"{path}: duplicate channel '{name}' in header columns {names.index(name) + 1} and {col}")
        names.append(name)
        units.append(unit)
    try:
        time_factor, time_unit = to_si(units[0])
    except UnitError as err:
        raise RecordError(f"{path}: header column 1 '{names[0]}': {err}") from None
    if names[0] != "time" or time_unit != "s":
        raise RecordError(f"{path}: first column must be 'time [s]', got '{line.split(',')[0].strip()}'")
    return names, units, time_factor


def _locate_parse_error(data_lines: list[str], n_columns: int, header_line: int) -> str:
    """Find the first row and column that numpy could not read."""
    for row, text in enumerate(data_lines, start=1):
        fields = text.split(",")
        if len(fields) != n_columns:
            return f"data row {row} (line {header_line + row}) has {len(fields)} fields, expected {n_columns}"
        for col, field in enumerate(fields, start=1):
            try:
                float(field)
            except ValueError:
                return f"data row {row} (line {header_line + row}), column {col}: '{field.strip()}' is not a number"
    return "unreadable data"


FORMAT = RecordFormat((".csv",), read_csv, ".csv", write=write_csv, order=10)
