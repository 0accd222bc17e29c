"""The sample rate a diagnosis works at: a record sampled far above what the diagnosis uses is decimated first.

A diagnosis simulates the car hundreds of times at one physics step per sample at least (rig/vehicle/mjcf.py
``timestep_for``), so a record at 1000 Hz costs each simulation twice the steps of one at 500 Hz, though the diagnosis
uses nothing above its analysis band (50 Hz at most, rig/constants.py) and its noise band (100-200 Hz,
rig/diagnosis/core/noise.py). A record at two or more times MIN_RATE is decimated by the largest whole factor that
keeps MIN_RATE (1000 and 1024 Hz by 2, 2048 Hz by 4, 5000 Hz by 10) through SciPy's polyphase resampler
(rig/io/multirate.py ``decimated``: a linear-phase anti-alias filter, so that the posts and the responses keep their
timing). MIN_RATE is 500 Hz: the coarse physics step of a fit (2 ms, rig/sim/step_size.py) then takes one step per
sample, and the noise band lies below NYQUIST_SHARE of the rate. The integrity checks read the record as sampled.
"""

from __future__ import annotations

from rig.diagnosis.core.noise import NOISE_BAND, NYQUIST_SHARE
from rig.io.multirate import decimated
from rig.io.record import Record
from rig.sim.step_size import COARSE_TIMESTEP

MIN_RATE = max(1.0 / COARSE_TIMESTEP, NOISE_BAND[1] / NYQUIST_SHARE)  # Hz: 500


def working_factor(rate: float) -> int:
    """By how much a record at ``rate`` Hz is decimated (1: not at all)."""
    return max(1, int(rate // MIN_RATE))


def at_working_rate(measured: Record, holdout: Record | None) -> tuple[Record, Record | None, list[str]]:
    """The records at the rates the diagnosis works at (each by its own ``working_factor``), and the notes that say
    where they were decimated."""
    records, notes = [], []
    for label, record in (("measured", measured), ("hold-out", holdout)):
        factor = 1 if record is None else working_factor(record.rate)
        records.append(record if record is None else decimated(record, factor))
        if factor > 1:
            notes.append(f"the {label} record decimated from {record.rate:g} to {record.rate / factor:g} Hz for the "
                         f"fits (anti-alias filter: scipy.signal.resample_poly): the analysis and noise bands lie "
                         f"below {NYQUIST_SHARE * record.rate / factor:g} Hz, and a simulation of it takes up to "
                         f"{factor} times fewer physics steps")
    return records[0], records[1], notes
