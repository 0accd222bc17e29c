"""ASAM MDF files (``.mf4``, ``.mdf``, ``.dat``) through ``asammdf``: read any version, write MDF 4.10.

Channel names are the file's; a name that several channel groups use is read as ``name (group N)``.
Values are the physical values (the file's conversions applied), converted to SI from each channel's
unit. Channel groups sampled at different rates are brought to one rate (``rig.io.multirate``) and the
record's metadata key ``resampled`` says so. Record metadata travels in the file header's
``<common_properties>`` (``<e name="vehicle">proton_x</e>``).
"""

from __future__ import annotations

import contextlib
import gc
import os
import sys
import xml.etree.ElementTree as ET
from collections import Counter
from collections.abc import Iterator
from pathlib import Path

from struct import error as struct_error

import numpy as np
from asammdf import MDF, Signal
from asammdf.blocks.utils import MdfException

from rig.io.atomic import atomic_path
from rig.io.channel_map import ChannelMap, plan_channels, plan_metadata
from rig.io.formats import RecordFormat
from rig.io.multirate import Timed, record_at_one_rate
from rig.io.record import Record, RecordError
from rig.io.time_stamps import on_uniform_time
from rig.io.units import si_to

MDF_SUFFIXES = (".mf4", ".mdf", ".dat")


@contextlib.contextmanager
def _quiet_destructors() -> Iterator[None]:
    """Let the half-opened MDF object of a failed read go quietly: asammdf's destructor fails on one that never
    opened its file, and that failure, printed by Python, says nothing the read's own error does not."""
    hook, sys.unraisablehook = sys.unraisablehook, lambda unraisable: None
    try:
        yield
    finally:
        gc.collect()
        sys.unraisablehook = hook


def read_mdf(path: str | os.PathLike, resample: bool = False, channel_map: ChannelMap | None = None) -> Record:
    """Read an MDF file into a Record in SI units, through ``channel_map`` if given.

    Each channel group's time stamps must be uniform (within 1 % of a sample); ``resample`` interpolates
    an irregular group onto a uniform grid instead, and says so.
    """
    path = Path(path)
    failure = None
    with _quiet_destructors():
        try:
            mdf = MDF(path)
        except (MdfException, OSError, ValueError, KeyError, IndexError, struct_error) as err:
            failure = f"{type(err).__name__}: {err}"
    if failure:
        raise RecordError(f"{path}: not a readable MDF file ({failure})")
    with mdf:
        where = _channels(mdf)
        units = {name: mdf.groups[group].channels[index].unit for name, (group, index) in where.items()}
        plan = plan_channels(path, units, channel_map,
                             {name: f"group {group}" for name, (group, _) in where.items()})
        by_group: dict[int, dict[str, np.ndarray]] = {}
        times: dict[int, np.ndarray] = {}
        for conversion in plan.conversions:
            group, index = where[conversion.source]
            signal = mdf.get(group=group, index=index)
            if signal.samples.ndim != 1 or signal.samples.dtype.kind not in "biuf":
                raise RecordError(f"{path}: channel '{conversion.source}' is not a numeric time series "
                                  f"({signal.samples.dtype}); leave it out with a channel map (--map)")
            by_group.setdefault(group, {})[conversion.name] = conversion.apply(signal.samples)
            times[group] = signal.timestamps
        metadata = _metadata(mdf.header.comment)
    if not by_group:
        raise RecordError(f"{path}: MDF file has no channels")
    groups = [_timed(path, group, times[group], channels, resample, metadata)
              for group, channels in by_group.items()]
    metadata.update(plan_metadata(plan, channel_map))
    return record_at_one_rate(path, groups, {c.name: c.unit for c in plan.conversions}, metadata)


def write_mdf(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None) -> None:
    """Write ``record`` as MDF 4.10 (one channel group, float64 values), atomically.

    ``units`` optionally maps channels to the units to store; the default is SI.
    """
    units = units or {}
    signals = []
    for name in record.names:
        unit = units.get(name, record.units[name])
        signals.append(Signal(record[name] * si_to(unit, record.units[name]), record.time, name=name, unit=unit))
    mdf = MDF(version="4.10")
    comment = ET.Element("HDcomment")
    ET.SubElement(comment, "TX")
    properties = ET.SubElement(comment, "common_properties")
    for key, value in record.metadata.items():
        ET.SubElement(properties, "e", name=key).text = str(value)
    mdf.header.comment = ET.tostring(comment, encoding="unicode")
    mdf.append(signals, comment="test record")
    with atomic_path(path, suffix=".mf4") as tmp:
        mdf.save(tmp, overwrite=True)
    mdf.close()


def _channels(mdf: MDF) -> dict[str, tuple[int, int]]:
    """Every data channel (masters left out) by name -> (group, index); repeated names get their group."""
    found = [(channel.name, group, index) for group, data_group in enumerate(mdf.groups)
             for index, channel in enumerate(data_group.channels) if mdf.masters_db.get(group) != index]
    counts = Counter(name for name, _, _ in found)
    return {(f"{name} (group {group})" if counts[name] > 1 else name): (group, index) for name, group, index in found}


def _timed(path: Path, group: int, time: np.ndarray, channels: dict[str, np.ndarray], resample: bool,
           metadata: dict[str, str]) -> Timed:
    """One channel group on its fitted time base (or resampled onto one, when allowed)."""
    names = ", ".join(channels)
    if time.size < 2:
        raise RecordError(f"{path}: group {group} ({names}) has {time.size} sample(s); a record needs two or more")
    base, table, irregular = on_uniform_time(time, np.zeros(time.size), np.column_stack(list(channels.values())),
                                             resample, f"{path}: group {group} ({names})", lambda row: f"sample {row}")
    if irregular:
        note = (f"group {group}: irregular time stamps ({time.size} samples, {irregular}) linearly interpolated "
                f"to {base.rate:g} Hz")
        metadata["resampled"] = "; ".join(filter(None, (metadata.get("resampled"), note)))
    return Timed(base, dict(zip(channels, table.T)))


def _metadata(comment: str) -> dict[str, str]:
    """``<common_properties>`` of the header comment as ``key: value`` (empty for a plain-text comment)."""
    try:
        root = ET.fromstring(comment)
    except ET.ParseError:
        return {}
    return {e.get("name"): (e.text or "") for e in root.iter("e") if e.get("name")}


FORMAT = RecordFormat(MDF_SUFFIXES, read_mdf, "MDF .mf4", write=write_mdf, order=30)
