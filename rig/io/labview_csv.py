"""CSV files as lab DAQs export them (LabVIEW and the like), read through a channel map.

Besides the contract CSV (``time [s],FL/drive [m],...``, rig/io/csv_format.py), which dispatches here when it
recognises one of these, a lab export may have:

- a ``Time - <name>`` / ``Amplitude - <name>`` column pair per channel (LabVIEW's waveform export), each pair
  with its own time column; the pairs' time bases are checked against each other (rate, start, length) and a
  pair on another one is refused, naming it, unless ``resample`` brings all to one rate (rig/io/multirate.py);
- quoted headers, and the unit in parentheses at the end of the name (``"Force (N)"``; ``[N]`` is read too, and
  ``"Amplitude - Fc (N"``, whose closing parenthesis LabVIEW cut off); a channel is named as the file writes it,
  unit included (map ``"Force (N)" = "damper/force"``, or a part of the name: rig/io/channel_map.py);
- a single time column of wall-clock ISO 8601 date-time stamps (``2025-11-14 20:07:10.531160``): time counts
  from the earliest stamp, which the record's metadata keeps (key ``start``), and each stamp may be off its
  uniform sampling by half a unit in its last printed digit (rig/io/time_stamps.py), as numeric time may;
- raw voltage columns (unit ``V`` or ``mV``) beside the scaled ones: left out unless a channel map names them
  (the metadata key ``unmapped`` lists them);
- a microcontroller's clock as the time column (Arduino's ``Millis`` or ``Micros``: ms or us unless the header gives
  a unit);
- event lines a logger writes between the samples (``11649,Switched from 1 to 0,,``: text in a channel's place and
  the other channels blank): skipped, and listed in the metadata (key ``events``); a last line cut short where the
  logger stopped (``20967,``: its time and no value) is left out and said (key ``truncated``).

Columns are split by ``,``, ``;`` or a tab (whichever the header uses; decimal points only). Written here:
Python's ``csv`` module splits the fields and ``datetime.fromisoformat`` reads the stamps; no library reads
these exports into a uniformly sampled record.
"""

from __future__ import annotations

import csv
import os
import re
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from rig.io.channel_map import ChannelMap, plan_channels, plan_metadata
from rig.io.multirate import Timed, record_at_one_rate
from rig.io.record import Record, RecordError
from rig.io.text import metadata_lines, read_text
from rig.io.time_stamps import TimeBase, on_uniform_time, printed_resolution
from rig.io.units import UnitError, split_unit, to_si

_PAIR = re.compile(r"^(?P<kind>Time|Amplitude) - (?P<name>.+)$")
_SECONDS = re.compile(r"\d{2}:\d{2}:\d{2}(?:[.,](\d+))?")  # the seconds of a stamp and their printed decimals
_TIME_NAMES = ("time", "timestamp", "date")
_CLOCK_UNITS = {"millis": "ms", "micros": "us"}  # a microcontroller's clock, by the name of the call that reads it
VOLTAGE_UNITS = ("V", "mV")
_DELIMITERS = ",;\t"


@dataclass(frozen=True)
class _Column:
    """One column of the file: its header text, the unit that text carries ('' if none), its values as text."""

    name: str
    unit: str
    texts: list[str]
    number: int  # 1-based column number, for messages
    lines: list[int]  # the file's 1-based line number of each value, for messages


def is_lab_export(lines: list[str]) -> bool:
    """Whether a ``.csv`` file's text ``lines`` are a lab export rather than a contract CSV: its header is quoted,
    holds ``Time - ``/``Amplitude - `` pairs, has no ``[unit]`` at all, or its first value is an ISO date-time."""
    header, first = _first_lines(lines)
    if header is None:
        return False
    fields = _split(header, _delimiter(header))
    if '"' in header or any(_PAIR.match(f.strip()) for f in fields) or not any("[" in f for f in fields):
        return True
    return first is not None and _is_stamp(_split(first, _delimiter(header))[0])


def read_lab_csv(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read a lab export into a Record in SI units, through ``channel_map`` if given (see the module notes).

    Refused with a message naming the column and row: a pair without its partner, a time column that is not
    uniform (unless ``resample``), pairs on different time bases (unless ``resample``), values that are not
    numbers, and every refusal of the channel map (rig/io/channel_map.py).
    """
    path = Path(path)
    metadata, header_line, rows = _table(path)
    delimiter = _delimiter(rows[0])
    header = [field.strip() for field in _split(rows[0], delimiter)]
    body, lines = _samples(rows, delimiter, header_line, metadata)
    if len(body) < 2:
        raise RecordError(f"{path}: needs at least two rows of samples, found {len(body)}")
    columns = [_Column(name, _unit_of(name), [row[i].strip() if i < len(row) else "" for row in body], i + 1, lines)
               for i, name in enumerate(header)]
    groups = _pairs(path, columns) if any(_PAIR.match(c.name) for c in columns) else _one_clock(path, columns)
    signals = {c.name: c for _, channels in groups for c in channels}
    voltages = [n for n, c in signals.items() if c.unit in VOLTAGE_UNITS]
    readable = signals if channel_map is not None else {n: c for n, c in signals.items() if n not in voltages}
    plan = plan_channels(path, {n: c.unit for n, c in readable.items()}, channel_map,
                         {n: f"column {c.number}" for n, c in readable.items()})
    metadata.update(plan_metadata(plan, channel_map))
    if channel_map is None and voltages:
        metadata["unmapped"] = (f"{len(voltages)} raw voltage channel(s) left out (map them to read them): "
                                + ", ".join(voltages))
    wanted = {c.source: c for c in plan.conversions}
    clocks = [(clock, [c for c in channels if c.name in wanted]) for clock, channels in groups]
    clocks = [(clock, channels) for clock, channels in clocks if channels]
    if not clocks:
        raise RecordError(f"{path}: no channels to read")
    epoch = _epoch(path, [clock for clock, _ in clocks])
    if epoch is not None:
        metadata["start"] = epoch.isoformat(sep=" ")
    timed = []
    for clock, channels in clocks:
        time, resolution, rows_read = _seconds(path, clock, epoch)
        values = {wanted[c.name].name: wanted[c.name].apply(_numbers(path, c, rows_read)) for c in channels}
        timed.append(_on_time_base(path, clock, time, resolution, values, resample, metadata))
    units = {c.name: c.unit for c in plan.conversions}
    if not resample:
        _check_same_base(path, timed, [clock for clock, _ in clocks])
    return record_at_one_rate(path, timed, units, metadata)


def _first_lines(lines: list[str]) -> tuple[str | None, str | None]:
    """The header line and the first data line of a CSV (after ``#`` metadata and blank lines)."""
    found = [line for line in lines[:1000] if not line.startswith("#") and line.strip()][:2]
    padded = [*found, None, None]
    return padded[0], padded[1]


def _table(path: Path) -> tuple[dict[str, str], int, list[str]]:
    """``# key: value`` metadata, the header's 1-based line number, and the header and data lines."""
    lines = read_text(path, "CSV record", RecordError).splitlines()
    metadata, index = metadata_lines(lines)
    if index == len(lines):
        raise RecordError(f"{path}: no header line")
    return metadata, index + 1, lines[index:]


def _samples(rows: list[str], delimiter: str, header_line: int, metadata: dict) -> tuple[list[list[str]], list[int]]:
    """The data lines' fields and their 1-based line numbers, blank lines and a logger's event lines left out (text
    where a channel's number goes, the other channels blank: ``11649,Switched from 1 to 0,,``), these listed in
    ``metadata["events"]``, and a last line with its time and no value (``metadata["truncated"]``)."""
    body, lines, events = [], [], []
    for offset, line in enumerate(rows[1:], start=header_line + 1):
        if not line.strip():
            continue
        fields = _split(line, delimiter)
        channels = [f.strip() for f in fields[1:]]
        if channels and "" in channels and any(channels) and not any(_is_number(f) for f in channels if f):
            events.append(f"line {offset}: {' '.join(f for f in channels if f)}")
            continue
        body.append(fields)
        lines.append(offset)
    if events:
        metadata["events"] = f"{len(events)} event line(s) skipped: " + "; ".join(events)
    if len(body) > 2 and not any(f.strip() for f in body[-1][1:]) and any(f.strip() for f in body[-2][1:]):
        metadata["truncated"] = (f"line {lines[-1]} ('{delimiter.join(body[-1]).strip()}') holds a time and no value: "
                                 f"left out")
        body, lines = body[:-1], lines[:-1]
    return body, lines


def _delimiter(header: str) -> str:
    return max(_DELIMITERS, key=lambda d: len(_split(header, d)))


def _split(line: str, delimiter: str) -> list[str]:
    return next(csv.reader([line], delimiter=delimiter, skipinitialspace=True), [])


def _unit_of(name: str) -> str:
    """The unit a header writes at its end, in parentheses or brackets; '' when it writes none."""
    return split_unit(_PAIR.match(name)["name"] if _PAIR.match(name) else name)[1]


def _is_stamp(text: str) -> bool:
    text = text.strip()
    if not text or (text[0] in "+-.0123456789" and _is_number(text)):
        return False
    try:
        datetime.fromisoformat(text)
    except ValueError:
        return False
    return True


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _pairs(path: Path, columns: list[_Column]) -> list[tuple[_Column, list[_Column]]]:
    """LabVIEW's pairs: each ``Amplitude - X`` with its ``Time - X``, the amplitude renamed ``X``."""
    times, amplitudes = {}, []
    for column in columns:
        match = _PAIR.match(column.name)
        if match is None:
            raise RecordError(f"{path}: column {column.number} '{column.name}' is not a 'Time - <name>' or "
                              f"'Amplitude - <name>' column, as the other columns are")
        if match["kind"] == "Time":
            times[match["name"]] = column
        else:
            amplitudes.append(_Column(match["name"], column.unit, column.texts, column.number, column.lines))
    unpaired = [a.name for a in amplitudes if a.name not in times]
    unpaired += [n for n in times if n not in {a.name for a in amplitudes}]
    if unpaired:
        raise RecordError(f"{path}: channel(s) {', '.join(unpaired)} lack their 'Time - <name>' or "
                          f"'Amplitude - <name>' partner")
    # a pair's time column carries no unit of its own (its name ends with the channel's): seconds
    return [(_Column(times[a.name].name, "", times[a.name].texts, times[a.name].number, a.lines), [a])
            for a in amplitudes]


def _one_clock(path: Path, columns: list[_Column]) -> list[tuple[_Column, list[_Column]]]:
    """A single time column first, then the channels."""
    clock = columns[0]
    name = split_unit(clock.name)[0].lower()
    if not name.startswith((*_TIME_NAMES, *_CLOCK_UNITS)) and not _is_stamp(clock.texts[0]):
        raise RecordError(f"{path}: column 1 '{clock.name}' is not a time column (a name starting with "
                          f"time/timestamp/date/millis/micros, or ISO date-time stamps)")
    names = [c.name for c in columns[1:]]
    for column in columns[1:]:
        if names.count(column.name) > 1:
            raise RecordError(f"{path}: duplicate channel '{column.name}' in column {column.number}")
    return [(clock, columns[1:])]


def _epoch(path: Path, clocks: list[_Column]) -> datetime | None:
    """The earliest first stamp of the time columns that hold date-times (None if they hold numbers)."""
    stamped = [c for c in clocks if _is_stamp(c.texts[0])]
    if stamped and len(stamped) != len(clocks):
        raise RecordError(f"{path}: time column '{stamped[0].name}' holds date-times and "
                          f"'{next(c for c in clocks if c not in stamped).name}' numbers")
    return min(_stamp(path, c, 0) for c in stamped) if stamped else None


def _stamp(path: Path, clock: _Column, row: int) -> datetime:
    try:
        moment = datetime.fromisoformat(clock.texts[row])
    except ValueError:
        raise RecordError(f"{path}: column {clock.number} '{clock.name}', data row {row + 1} (line "
                          f"{clock.lines[row]}): '{clock.texts[row]}' is not an ISO date-time") from None
    return moment if moment.tzinfo is None else moment.astimezone(UTC).replace(tzinfo=None)


def _seconds(path: Path, clock: _Column, epoch: datetime | None) -> tuple[np.ndarray, np.ndarray, int]:
    """A time column in s (from ``epoch`` for date-times), half a unit of its last printed digit per stamp (s),
    and the number of rows it fills (a shorter pair leaves blank rows at the end)."""
    rows = _filled(path, clock)
    texts = clock.texts[:rows]
    if epoch is not None:
        time = np.array([(_stamp(path, clock, i) - epoch).total_seconds() for i in range(rows)])
        digits = [len(m[1] or "") if (m := _SECONDS.search(t)) else 0 for t in texts]
        return time, 0.5 * 10.0 ** -np.array(digits, float), rows
    unit = clock.unit or _CLOCK_UNITS.get(split_unit(clock.name)[0].lower(), "s")
    try:
        factor, si_unit = to_si(unit)
    except UnitError as err:
        raise RecordError(f"{path}: time column {clock.number} '{clock.name}': {err}") from None
    if si_unit != "s":
        raise RecordError(f"{path}: time column {clock.number} '{clock.name}' is in '{unit}', not a unit of time")
    values = _numbers(path, clock, rows)
    return values * factor, printed_resolution(texts) * factor, rows


def _filled(path: Path, column: _Column) -> int:
    """Rows a column fills from the top; a blank inside it (not only at its end) is refused."""
    blank = [i for i, text in enumerate(column.texts) if not text]
    rows = blank[0] if blank else len(column.texts)
    if any(column.texts[rows:]):
        raise RecordError(f"{path}: column {column.number} '{column.name}' has a blank value in data row "
                          f"{rows + 1} (line {column.lines[rows]})")
    return rows


def _numbers(path: Path, column: _Column, rows: int) -> np.ndarray:
    """The first ``rows`` values of a column as numbers; the first that is not one (or is not finite) is named."""
    if _filled(path, column) != rows:
        raise RecordError(f"{path}: column {column.number} '{column.name}' has {_filled(path, column)} "
                          f"values but its time column has {rows}")
    try:
        values = np.array(column.texts[:rows], dtype=float)
    except ValueError:
        row = next(i for i, t in enumerate(column.texts[:rows]) if not _is_number(t))
        raise RecordError(f"{path}: column {column.number} '{column.name}', data row {row + 1} (line "
                          f"{column.lines[row]}): '{column.texts[row]}' is not a number") from None
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise RecordError(f"{path}: column {column.number} '{column.name}' has a non-finite value "
                          f"({column.texts[bad[0]]}) in data row {bad[0] + 1} (line {column.lines[bad[0]]})")
    return values


def _on_time_base(path: Path, clock: _Column, time: np.ndarray, resolution: np.ndarray,
                  values: dict[str, np.ndarray], resample: bool, metadata: dict) -> Timed:
    """Channels on the uniform time base their time column gives; an irregular one is resampled if allowed."""
    base, table, irregular = on_uniform_time(time, resolution, np.column_stack(list(values.values())), resample,
                                             f"{path}: time column {clock.number} '{clock.name}'",
                                             lambda row: f"data row {row + 1} (line {clock.lines[row]})")
    if irregular:
        note = f"'{clock.name}': irregular time stamps ({irregular}) linearly interpolated to {base.rate:g} Hz"
        metadata["resampled"] = "; ".join(filter(None, (metadata.get("resampled"), note)))
    return Timed(base, {name: table[:, i] for i, name in enumerate(values)})


def _check_same_base(path: Path, timed: list[Timed], clocks: list[_Column]) -> None:
    """Each pair's time against the first's: the same rate, start (within half a sample) and length."""
    first, reference = timed[0], clocks[0]
    length = next(iter(first.channels.values())).size
    for group, clock in zip(timed[1:], clocks[1:], strict=True):
        base: TimeBase = group.base
        size = next(iter(group.channels.values())).size
        if (abs(base.rate - first.base.rate) > 1e-6 * first.base.rate or size != length
                or abs(base.start - first.base.start) > 0.5 / first.base.rate):
            raise RecordError(
                f"{path}: '{clock.name}' runs at {base.rate:.6g} Hz from {base.start:.6g} s ({size} samples) but "
                f"'{reference.name}' at {first.base.rate:.6g} Hz from {first.base.start:.6g} s ({length} samples); "
                f"bring them to one rate with --resample")
