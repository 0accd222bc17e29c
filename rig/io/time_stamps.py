"""Sample rate from a record's printed time column: real exports round their stamps (docs/contracts.md).

A DAQ or spreadsheet prints time to 6-7 significant digits, so past a few seconds at 512 Hz no two steps
are equal. The rate is fitted to the whole column (least squares of time against sample index) and every
stamp may depart from the fitted line by half a unit in its last printed digit plus a small jitter.
Real gaps, repeated and reversed stamps are refused with the row named; a genuinely irregular log is
resampled only when asked. Where the print is coarser than a sample interval (5 digits past 10 s at
2048 Hz), a single missing sample leaves no trace in the time column and cannot be refused. Written here
because no library reads a rate from rounded text stamps.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rig.errors import RigError
from rig.io.record import RecordError

#: Timing jitter accepted on top of the printed resolution, as a fraction of the sample interval.
JITTER_FRACTION = 0.01


class TimeStampError(RigError):
    """Time stamps that are not a uniform sampling; ``row`` is the 0-based index of the offending stamp."""

    def __init__(self, row: int, reason: str):
        super().__init__(reason)
        self.row = row
        self.reason = reason


@dataclass(frozen=True)
class TimeBase:
    """Uniform sampling fitted to a time column: ``time[i] = start + i / rate`` (s, Hz)."""

    rate: float
    start: float


def printed_resolution(texts: list[str]) -> np.ndarray:
    """Half a unit in the last printed digit of each number, in the numbers' own unit.

    ``'1.011719'`` -> 5e-7, ``'3.5e-02'`` -> 5e-4, ``'12'`` -> 0.5; a printed zero is exact (0).
    """
    half = np.empty(len(texts))
    for i, text in enumerate(texts):
        text = text.strip().lower()
        mantissa, _, exponent = text.partition("e")
        _, point, decimals = mantissa.partition(".")
        digits = len(decimals) if point else 0
        half[i] = 0.5 * 10.0 ** (int(exponent or 0) - digits)
        if float(text) == 0.0:
            half[i] = 0.0
    return half


def fit_time_base(time: np.ndarray, resolution: np.ndarray) -> TimeBase:
    """The uniform sampling that explains ``time`` (s) within ``resolution`` (s, per stamp) plus jitter.

    The rate is the least-squares slope of time against index, snapped to a whole number of Hz when
    that explains the stamps as well. Raises TimeStampError naming the first stamp that no uniform
    sampling explains: a reversed or repeated stamp, a gap, or a drift beyond the resolution.
    """
    n = time.size
    steps = np.diff(time)
    span_step = (time[-1] - time[0]) / (n - 1)
    if span_step <= 0:
        raise TimeStampError(n - 1, "time does not increase")
    step_slack = resolution[:-1] + resolution[1:]
    jitter = JITTER_FRACTION * span_step
    for row in np.flatnonzero(steps <= step_slack):
        if step_slack[row] < 0.5 * span_step:  # rounding this fine cannot make a stamp repeat or go back
            what = "goes back from" if steps[row] < -step_slack[row] else "repeats"
            raise TimeStampError(row + 1, f"time stamp {time[row + 1]:.9g} s {what} the previous one "
                                          f"({time[row]:.9g} s)")
    excess = np.abs(steps - span_step) - (step_slack + 2 * jitter)
    if np.any(excess > 0):
        row = int(np.argmax(excess))  # the worst step: a gap stretches the span, so ordinary steps may fail too
        typical = _regular_step(steps)
        raise TimeStampError(row + 1, f"step {steps[row]:.6g} s where the record's step is {typical:.6g} s "
                                      f"({steps[row] / typical:.2f} samples: a gap or an irregular log)")
    index = np.arange(n)
    step, start = np.polyfit(index, time, 1)
    tolerance = resolution + jitter
    residual = time - (start + step * index)
    if np.any(np.abs(residual) > tolerance):
        row = int(np.argmax(np.abs(residual) - tolerance))
        raise TimeStampError(row, f"stamp {time[row]:.9g} s is {residual[row]:.3g} s off the fitted rate "
                                  f"{1 / step:.8g} Hz (beyond its printed resolution and jitter)")
    whole = round(1.0 / step)
    if whole > 0:
        whole_start = np.mean(time - index / whole)
        if np.all(np.abs(time - (whole_start + index / whole)) <= tolerance):
            step, start = 1.0 / whole, whole_start
    if abs(start - time[0]) <= tolerance[0]:  # the first stamp as printed, when the fit allows it (t = 0)
        start = time[0]
    return TimeBase(1.0 / step, float(start))


def on_uniform_time(time: np.ndarray, resolution: np.ndarray, values: np.ndarray, resample: bool, source: str,
                    at: Callable[[int], str]) -> tuple[TimeBase, np.ndarray, str]:
    """The uniform sampling of ``time`` (s) and ``values`` (samples x columns) on it: as they are, or with
    ``resample`` interpolated onto a uniform grid, with the reason they had to be ('' when they did not).

    Refuses with a RecordError naming ``source`` (the file, and the group in it) and ``at(row)`` (where a 0-based
    stamp is, in words: "data row 3 (line 4)", "sample 2")."""
    try:
        return fit_time_base(time, resolution), values, ""
    except TimeStampError as err:
        if not resample:
            raise RecordError(f"{source}: non-uniform time at {at(err.row)}: {err.reason}; if the log is irregular, "
                              f"resample it (--resample)") from None
        try:
            base, resampled = resample_uniform(time, values)
        except TimeStampError as again:
            raise RecordError(f"{source}: {at(again.row)}: {again.reason}") from None
        return base, resampled, err.reason


def resample_uniform(time: np.ndarray, table: np.ndarray) -> tuple[TimeBase, np.ndarray]:
    """Resample the columns of ``table`` from strictly increasing stamps ``time`` (s) to a uniform grid.

    The rate is that of the regular steps (gaps and dropouts left out) rounded to a whole Hz; values are
    linearly interpolated between stamps.
    """
    if np.any(np.diff(time) <= 0):
        row = int(np.flatnonzero(np.diff(time) <= 0)[0]) + 1
        raise TimeStampError(row, f"time stamp {time[row]:.9g} s does not follow {time[row - 1]:.9g} s: "
                                  f"cannot resample a log whose time repeats or goes back")
    rate = float(max(round(1.0 / _regular_step(np.diff(time))), 1))
    grid = time[0] + np.arange(int(np.floor((time[-1] - time[0]) * rate + 1e-9)) + 1) / rate
    return TimeBase(rate, float(time[0])), np.column_stack([np.interp(grid, time, col) for col in table.T])


def _regular_step(steps: np.ndarray) -> float:
    """The sampling step of a time column with gaps or dropouts (s): the mean of the steps within 2.5 times the
    median one (rounded stamps scatter the steps about it; a dropout is at least twice it)."""
    regular = steps[steps <= 2.5 * np.median(steps)]
    return float(regular.mean()) if regular.size else float(steps.mean())
