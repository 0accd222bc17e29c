"""Channels logged at different rates (MDF channel groups, TDMS waveforms) brought to one rate.

The common rate is the one shared by most of the channels read (a tie goes to the higher rate), so most
channels pass untouched and a record read through a map takes the rate of its mapped channels. The others
go through SciPy's polyphase resampler (``scipy.signal.resample_poly``): its FIR low-pass (Kaiser window)
removes what lies above the new Nyquist frequency before decimating (anti-aliasing) and the images when
interpolating. The record covers the time every channel covers; a group whose samples fall between the
common grid's is linearly interpolated onto it.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from scipy.signal import resample_poly

from rig.io.record import Record, RecordError
from rig.io.time_stamps import TimeBase

#: Largest denominator of the resampling ratio between two rates (1024 Hz -> 1000 Hz is 125/128).
MAX_RATIO_DENOMINATOR = 1000


@dataclass(frozen=True)
class Timed:
    """Channels sampled together: ``time[i] = base.start + i / base.rate`` (s, Hz), equal lengths."""

    base: TimeBase
    channels: dict[str, np.ndarray]


@dataclass(frozen=True)
class OneRate:
    """Channels on one time base; ``note`` says what was resampled (None when nothing was)."""

    base: TimeBase
    channels: dict[str, np.ndarray]
    note: str | None


def to_one_rate(groups: list[Timed]) -> OneRate:
    """Bring ``groups`` (at least one channel in all) to the rate most of their channels have.

    Raises ValueError when the groups share no time span.
    """
    counts = Counter()
    for group in groups:
        counts[group.base.rate] += len(group.channels)
    rate = max(counts, key=lambda r: (counts[r], r))
    reference = next(g for g in groups if g.base.rate == rate)
    series, notes = [], []
    for group in groups:
        values = group.channels
        group_rate = group.base.rate
        offset = (group.base.start - reference.base.start) * rate
        if group.base.rate != rate:
            ratio = Fraction(rate / group.base.rate).limit_denominator(MAX_RATIO_DENOMINATOR)
            values = {n: resample_poly(v, ratio.numerator, ratio.denominator, padtype="line")
                      for n, v in values.items()}
            group_rate = group_rate * ratio.numerator / ratio.denominator
            notes.append(f"{', '.join(group.channels)} at {group.base.rate:g} Hz resampled to {rate:g} Hz "
                         f"(anti-alias filter: scipy.signal.resample_poly, up {ratio.numerator} down "
                         f"{ratio.denominator})")
        elif abs(offset - round(offset)) > 1e-6:
            notes.append(f"{', '.join(group.channels)} shifted {offset % 1:.3f} sample onto the common time grid "
                         f"(linear interpolation)")
        time = group.base.start + np.arange(next(iter(values.values())).size) / group_rate
        # resampling pads past the group's last sample: keep what its data cover
        covered = time <= group.base.start + (next(iter(group.channels.values())).size - 1) / group.base.rate + 1e-9
        series.append((time[covered], {n: v[covered] for n, v in values.items()}))
    start = max(t[0] for t, _ in series)
    end = min(t[-1] for t, _ in series)
    first = int(np.ceil((start - reference.base.start) * rate - 1e-6))
    last = int(np.floor((end - reference.base.start) * rate + 1e-6))
    if last < first:
        raise ValueError("the channel groups share no time span: "
                         + ", ".join(f"{', '.join(v)} {t[0]:g}-{t[-1]:g} s" for t, v in series))
    grid = reference.base.start + np.arange(first, last + 1) / rate
    channels = {name: np.interp(grid, time, v) for time, values in series for name, v in values.items()}
    return OneRate(TimeBase(rate, float(grid[0])), channels, "; ".join(notes) or None)


def record_at_one_rate(path, groups: list[Timed], units: dict[str, str], metadata: dict) -> Record:
    """The record of a file's channel groups at one rate; what was resampled is added to the ``resampled``
    metadata; groups that cannot be brought together are refused with the file named."""
    try:
        one = to_one_rate(groups)
    except ValueError as err:
        raise RecordError(f"{path}: {err}") from None
    if one.note:
        metadata["resampled"] = "; ".join(filter(None, (metadata.get("resampled"), one.note)))
    return Record(one.base.rate, one.channels, units, metadata, start_time=one.base.start)


def resampled(record: Record, ratio: Fraction) -> Record:
    """``record`` at ``ratio`` times its rate: every channel through ``resample_poly``'s anti-alias filter (up by the
    ratio's numerator, down by its denominator; linear phase: channels keep their timing against each other and
    against the start time), its ``resampled`` metadata saying so."""
    if ratio == 1:
        return record
    rate = record.rate * ratio.numerator / ratio.denominator
    how = f"down {ratio.denominator}" if ratio.numerator == 1 else f"up {ratio.numerator} down {ratio.denominator}"
    note = (f"all channels at {record.rate:g} Hz resampled to {rate:g} Hz (anti-alias filter: "
            f"scipy.signal.resample_poly, {how})")
    metadata = dict(record.metadata)
    metadata["resampled"] = "; ".join(filter(None, (metadata.get("resampled"), note)))
    return Record(rate, {n: resample_poly(v, ratio.numerator, ratio.denominator, padtype="line")
                         for n, v in record.channels.items()}, dict(record.units), metadata,
                  start_time=record.start_time)
