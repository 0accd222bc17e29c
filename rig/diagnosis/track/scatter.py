"""The scatter of repeated runs as the accuracy a model must reach (Forsén 1999): per channel, the band the repeats
span, their scatter, and whether the model lies inside it.

Forsén measures a test's repeatability with the same index as a model's discrepancy: the TDDI of two runs of equal
status (eq. 7), averaged over the pairs of repeats, is the experimental scatter; "when the difference between the
identified model's output and a specific experimental run's result is less than the scatter between nominally
identical experiments, then further improvements of the simulation model's predictive power cannot be verified
experimentally". So a channel's model is *inside* the scatter when its mean TDDI against the repeats (eq. 7, the model
taken as one more run) is at most the repeats' mean TDDI against each other, *outside* when it is more. The band is the
repeats' smallest and largest value at each sample (their envelope), for the figures and the Rerun view.

Channels are compared in the analysis band (rig/constants.py), as a rig test's are.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.channels import split_channel
from rig.io.record import Record, RecordError
from rig.signal.filters import band_pass
from rig.signal.metrics import tddi

COMPARED = ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force", "seat_acc")


@dataclass(frozen=True)
class ChannelScatter:
    """One channel of a case: the repeats' scatter (mean TDDI over their pairs, and the largest pair's), the model's
    mean TDDI against the repeats, and the verdict."""

    scatter: float
    scatter_max: float
    model: float

    @property
    def inside(self) -> bool:
        return self.model <= self.scatter

    def to_json(self) -> dict:
        return {"scatter": self.scatter, "scatter_max": self.scatter_max, "model": self.model,
                "verdict": "inside" if self.inside else "outside"}


@dataclass
class CaseScatter:
    """A case of a test matrix (a road at a speed): its repeats and the model as compared (band-passed, the repeats'
    common length), the band per channel and each channel's scatter and verdict."""

    label: str
    rate: float
    names: list[str]
    repeats: np.ndarray = field(repr=False)   # repeats x samples x channels
    model: np.ndarray = field(repr=False)     # samples x channels
    channels: dict[str, ChannelScatter]

    @property
    def low(self) -> np.ndarray:
        return self.repeats.min(axis=0)

    @property
    def high(self) -> np.ndarray:
        return self.repeats.max(axis=0)

    @property
    def outside(self) -> list[str]:
        return [n for n, c in self.channels.items() if not c.inside]

    def to_json(self) -> dict:
        return {"label": self.label, "repeats": int(self.repeats.shape[0]), "seconds": self.model.shape[0] / self.rate,
                "outside": self.outside, "channels": {n: c.to_json() for n, c in self.channels.items()}}


def case_scatter(label: str, model: Record, repeats: list[Record], band: tuple[float, float] = ANALYSIS_BAND
                 ) -> CaseScatter:
    """The scatter of ``repeats`` (at least two records of one road at one speed) and the ``model``'s run against it,
    on the channels of COMPARED quantities they all have, over their common length (RecordError when they share no
    such channel, differ in rate, or are fewer than two)."""
    if len(repeats) < 2:
        raise RecordError(f"{label}: the scatter of repeated runs needs at least two repeats, got {len(repeats)}")
    if any(r.rate != model.rate for r in repeats):
        raise RecordError(f"{label}: the repeats' sample rates ({', '.join(f'{r.rate:g}' for r in repeats)} Hz) "
                          f"differ from the model's {model.rate:g} Hz")
    names = [n for n in model.names if split_channel(n)[1] in COMPARED and all(n in r for r in repeats)]
    if not names:
        raise RecordError(f"{label}: the repeats and the model share none of the compared quantities "
                          f"({', '.join(COMPARED)})")
    length = min(r.n_samples for r in [model, *repeats])

    def compared(record: Record) -> np.ndarray:
        return band_pass(np.column_stack([record[n][:length] for n in names]), model.rate, band)

    runs = np.stack([compared(r) for r in repeats])
    simulated = compared(model)
    channels = {}
    for k, name in enumerate(names):
        pairs = [tddi(runs[i, :, k], runs[j, :, k]) for i, j in itertools.combinations(range(len(runs)), 2)]
        against = [tddi(run[:, k], simulated[:, k]) for run in runs]
        channels[name] = ChannelScatter(float(np.mean(pairs)), float(np.max(pairs)), float(np.mean(against)))
    return CaseScatter(label, model.rate, names, runs, simulated, channels)
