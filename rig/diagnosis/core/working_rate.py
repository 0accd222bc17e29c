"""The sample rate a diagnosis works at: a record sampled well above what the diagnosis uses is resampled first.

A diagnosis simulates the car hundreds of times at one physics step per sample at least (rig/vehicle/mjcf.py
``timestep_for``), so a record at 1000 Hz costs each simulation twice the steps of one at 500 Hz, and one at 800 Hz
1.6 times, though the diagnosis uses nothing above its analysis band (50 Hz at most, rig/constants.py) and its noise
band (100-200 Hz, rig/diagnosis/core/noise.py). MIN_RATE is 500 Hz: the coarse physics step of a fit (2 ms,
rig/sim/step_size.py) then takes one step per sample, and the noise band lies below NYQUIST_SHARE of the rate.
- A record at two or more times MIN_RATE is decimated by the largest whole factor that keeps MIN_RATE (1000 and 1024
  Hz by 2, 2048 Hz by 4, 5000 Hz by 10).
- A record between WORTH_RESAMPLING and two times MIN_RATE (600-999 Hz) is brought to MIN_RATE or just above by the
  ratio of smallest denominator (the shortest resampling filter) that lands within RATE_MARGIN above it: 800 Hz by
  5/8, 819.2 Hz by 11/18 (to 500.6 Hz), 960 Hz by 12/23 (to 500.9 Hz).
- A record below WORTH_RESAMPLING (512 Hz) is kept as sampled: it would save few steps.
Both through SciPy's polyphase resampler (rig/io/multirate.py ``resampled``: a linear-phase anti-alias filter, so that
the posts and the responses keep their timing). The integrity checks read the record as sampled.
"""

from __future__ import annotations

import math
from fractions import Fraction

from rig.diagnosis.core.noise import NOISE_BAND, NYQUIST_SHARE
from rig.io.multirate import resampled
from rig.io.record import Record
from rig.sim.step_size import COARSE_TIMESTEP

MIN_RATE = max(1.0 / COARSE_TIMESTEP, NOISE_BAND[1] / NYQUIST_SHARE)  # Hz: 500
WORTH_RESAMPLING = 1.2 * MIN_RATE  # Hz: from here on a record is resampled (it saves a sixth of the steps or more)
RATE_MARGIN = 0.002     # a ratio lands within this share above MIN_RATE (never below it: a step per sample)
MAX_DENOMINATOR = 1000  # of the ratio (the resampler's filter grows with it)


def working_ratio(rate: float) -> Fraction:
    """The ratio of the rate a record at ``rate`` Hz is diagnosed at to ``rate`` (1: as sampled; module
    docstring)."""
    if rate >= 2 * MIN_RATE:
        return Fraction(1, int(rate // MIN_RATE))
    if rate < WORTH_RESAMPLING:
        return Fraction(1)
    for denominator in range(1, MAX_DENOMINATOR + 1):
        numerator = math.ceil(denominator * MIN_RATE / rate - 1e-12)
        if numerator * rate / denominator <= (1.0 + RATE_MARGIN) * MIN_RATE:
            return Fraction(numerator, denominator)
    return Fraction(1)


def at_working_rate(measured: Record, holdout: Record | None) -> tuple[Record, Record | None, list[str]]:
    """The records at the rates the diagnosis works at (each by its own ``working_ratio``), and the notes that say
    where they were resampled."""
    records, notes = [], []
    for label, record in (("measured", measured), ("hold-out", holdout)):
        ratio = Fraction(1) if record is None else working_ratio(record.rate)
        records.append(record if record is None else resampled(record, ratio))
        if ratio != 1:
            how = "decimated" if ratio.numerator == 1 else "resampled"
            notes.append(f"the {label} record {how} from {record.rate:g} to {records[-1].rate:g} Hz for the "
                         f"fits (anti-alias filter: scipy.signal.resample_poly): the analysis and noise bands lie "
                         f"below {NYQUIST_SHARE * records[-1].rate:g} Hz, and a simulation of it takes up to "
                         f"{float(1 / ratio):.3g} times fewer physics steps")
    return records[0], records[1], notes
