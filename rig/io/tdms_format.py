"""NI TDMS files (``.tdms``) through ``npTDMS``: read.

Channel names are the file's; a name that several groups use is read as ``group/name``. Values are
scaled as the file says (DAQmx scaling applied by npTDMS) and converted to SI from the channel's
``unit_string`` property. Time comes from a channel's waveform properties (``wf_increment`` in s,
``wf_start_offset`` in s, after ``wf_start_time``) or else from a ``time`` channel in its group (unit from
its ``unit_string``, seconds when it has none; absolute stamps count from the file's earliest, so groups
that started at different moments keep their offsets). Channels at different rates are brought to one rate
(``rig.io.multirate``) and the record's metadata key ``resampled`` says so. The file's own properties become record
metadata.
"""

from __future__ import annotations

import os
from collections import Counter
from pathlib import Path

import numpy as np
from nptdms import TdmsFile

from rig.io.channel_map import ChannelMap, plan_channels, plan_metadata
from rig.io.formats import RecordFormat
from rig.io.multirate import Timed, record_at_one_rate
from rig.io.record import Record, RecordError
from rig.io.time_stamps import TimeBase, on_uniform_time
from rig.io.units import UnitError, to_si

UNIT_PROPERTY = "unit_string"


def read_tdms(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read a TDMS file into a Record in SI units, through ``channel_map`` if given.

    A ``time`` channel's stamps must be uniform (within 1 % of a sample); ``resample`` interpolates an
    irregular group onto a uniform grid instead, and says so.
    """
    path = Path(path)
    try:
        tdms = TdmsFile.read(path)
    except (OSError, ValueError, KeyError) as err:
        raise RecordError(f"{path}: not a readable TDMS file ({err})") from None
    found = [(group, channel) for group in tdms.groups() for channel in group.channels()
             if not _is_time(channel)]
    counts = Counter(channel.name for _, channel in found)
    where = {(f"{group.name}/{channel.name}" if counts[channel.name] > 1 else channel.name): (group, channel)
             for group, channel in found}
    plan = plan_channels(path, {name: str(channel.properties.get(UNIT_PROPERTY, ""))
                                for name, (_, channel) in where.items()},
                         channel_map, {name: f"group '{group.name}'" for name, (group, _) in where.items()})
    if not plan.conversions:
        raise RecordError(f"{path}: TDMS file has no channels")
    metadata = {key: str(value) for key, value in tdms.properties.items()}
    epoch = _epoch(tdms)
    groups = []
    for conversion in plan.conversions:
        group, channel = where[conversion.source]
        values = np.asarray(channel[:])
        if values.ndim != 1 or values.dtype.kind not in "biuf":
            raise RecordError(f"{path}: channel '{conversion.source}' is not a numeric time series "
                              f"({values.dtype}); leave it out with a channel map (--map)")
        timed, note = _timed(path, group, channel, conversion.name, conversion.apply(values), resample,
                             epoch)
        if note:
            metadata["resampled"] = "; ".join(filter(None, (metadata.get("resampled"), note)))
        groups.append(timed)
    metadata.update(plan_metadata(plan, channel_map))
    return record_at_one_rate(path, groups, {c.name: c.unit for c in plan.conversions}, metadata)


def _is_time(channel) -> bool:
    return channel.name.strip().lower() == "time"


def _epoch(tdms: TdmsFile) -> np.datetime64 | None:
    """The earliest absolute time in the file (a ``time`` channel's stamps, a waveform's ``wf_start_time``):
    groups that started at different moments keep their offsets from it. None when the file has none."""
    stamps = [c.properties["wf_start_time"] for g in tdms.groups() for c in g.channels()
              if isinstance(c.properties.get("wf_start_time"), np.datetime64)]
    stamps += [np.min(c[:]) for g in tdms.groups() for c in g.channels() if _is_time(c) and c.dtype.kind == "M"]
    return min(stamps) if stamps else None


def _seconds_since(epoch: np.datetime64 | None, moment) -> float:
    return (0.0 if epoch is None or not isinstance(moment, np.datetime64)
            else float((moment - epoch) / np.timedelta64(1, "s")))


def _timed(path: Path, group, channel, name: str, values: np.ndarray, resample: bool,
           epoch: np.datetime64 | None) -> tuple[Timed, str | None]:
    """A channel on its time base (s from ``epoch`` where the file has absolute times), and a note when its
    irregular time channel was resampled."""
    label = f"{path}: channel '{channel.name}' of group '{group.name}'"
    if values.size < 2:
        raise RecordError(f"{label} has {values.size} sample(s); a record needs two or more")
    increment = channel.properties.get("wf_increment")
    if increment is not None:
        if not float(increment) > 0 or not np.isfinite(float(increment)):
            raise RecordError(f"{label}: wf_increment {increment} is not a positive number of s")
        rate = 1.0 / float(increment)
        if abs(rate - round(rate)) <= 1e-9 * rate:
            rate = float(round(rate))
        start = float(channel.properties.get("wf_start_offset", 0.0))
        start += _seconds_since(epoch, channel.properties.get("wf_start_time"))
        return Timed(TimeBase(rate, start), {name: values}), None
    clocks = [c for c in group.channels() if _is_time(c)]
    if not clocks:
        raise RecordError(f"{label} has no wf_increment property and its group has no time channel")
    raw = np.asarray(clocks[0][:])
    if raw.dtype.kind == "M":  # absolute time stamps
        time = (raw - epoch) / np.timedelta64(1, "s")
    else:
        unit = str(clocks[0].properties.get(UNIT_PROPERTY, "")).strip() or "s"
        try:
            factor, si_unit = to_si(unit)
        except UnitError as err:
            raise RecordError(f"{path}: time channel of group '{group.name}': {err}") from None
        if si_unit != "s":
            raise RecordError(f"{path}: time channel of group '{group.name}' is in '{unit}', not a unit of time")
        time = raw.astype(float) * factor
    if time.size != values.size:
        raise RecordError(f"{label} has {values.size} samples but its group's time channel has {time.size}")
    base, table, irregular = on_uniform_time(time, np.zeros(time.size), values[:, None], resample,
                                             f"{path}: group '{group.name}'", lambda row: f"sample {row}")
    note = (f"'{channel.name}': irregular time stamps ({irregular}) linearly interpolated to {base.rate:g} Hz"
            if irregular else None)
    return Timed(base, {name: table[:, 0]}), note


FORMAT = RecordFormat((".tdms",), read_tdms, "TDMS .tdms", order=40)  # read only
