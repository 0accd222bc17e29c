"""Data-integrity checks of a measured record before it is compared with a model.

Findings name the channel and what is wrong: units that look wrong for the quantity (an RMS out of the
plausible range), clipping and dropouts; non-finite data is already refused when the record is read.

Real input is never flagged for being real. An encoder or an ADC quantises: its values are levels a step q apart, a
quantised sine repeats its peak level for a few samples each cycle, and a slow or still plate holds one level for
long. Clipping is the signal flat at its extreme where the samples on both sides say it would go on: a parabola
through the two samples before and the two after a run at the extreme rises above it by more than CLIP_HEADROOM
steps (a sine's peak lies below such a parabola's). A dropout is a run of one value where the channel moves: it
jumps into or out of the run by more than a step beyond twice its change per sample there, or changes by more than
a step per sample on both sides of it. A channel that holds one value over the whole record is reported as such.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.io.channels import split_channel
from rig.io.record import Record, RecordError

#: plausible RMS range per quantity, SI; outside it the unit is probably wrong (mm for m, g for m/s^2...)
PLAUSIBLE_RMS = {"drive": (1e-5, 0.05), "actuator_disp": (1e-5, 0.05), "sprung_acc": (0.005, 50.0),
                 "unsprung_acc": (0.05, 500.0), "susp_travel": (1e-5, 0.05), "tyre_force": (10.0, 1e5),
                 "actuator_force": (10.0, 1e5)}
CLIP_SHARE = 0.002   # share of samples sitting clipped at the extreme value
CLIP_HEADROOM = 3.0  # quantisation steps the samples around a run at the extreme must say it would exceed it by
DROPOUT_RUN = 8      # samples of the same value in a row
STEP_MARGIN = 1.5    # changes beyond this many quantisation steps are motion, not quantisation


@dataclass(frozen=True)
class Finding:
    """A problem found in a record: the channel, the check ('units', 'clipping', 'dropout'), what is wrong and how
    bad it is ('error': the record cannot be compared; 'warning': it can, with care)."""

    channel: str
    check: str
    message: str
    severity: str


def integrity_findings(record: Record) -> list[Finding]:
    """Problems found in the record."""
    findings = []
    for name in record.names:
        values = record[name]
        quantity = split_channel(name)[1]
        rms = float(np.sqrt(np.mean((values - values.mean()) ** 2)))
        if quantity in PLAUSIBLE_RMS:
            low, high = PLAUSIBLE_RMS[quantity]
            if not low <= rms <= high:
                findings.append(Finding(name, "units", f"RMS {rms:.3g} {record.units[name]} is outside the plausible "
                                                       f"{low:g}..{high:g} for {quantity}: wrong unit in the file?",
                                        "error"))
        findings += _clipping(name, values)
        if quantity != "drive":
            findings += _dropouts(name, values)
    return findings


def quantisation_step(values: np.ndarray) -> float:
    """The channel's quantisation step: the smallest gap between its distinct levels, gaps under 1e-9 of its range
    (a level written twice in floating point) left out; 0 for a constant channel."""
    levels = np.unique(values)
    gaps = np.diff(levels)
    gaps = gaps[gaps > 1e-9 * (levels[-1] - levels[0])] if levels.size > 1 else gaps
    return float(gaps.min()) if gaps.size else 0.0


def _runs(flags: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) of each run of True in ``flags``."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], flags.astype(int), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist()))


def _clipping(name: str, values: np.ndarray) -> list[Finding]:
    """A warning per extreme where more than CLIP_SHARE of the samples sit clipped at it (module docstring)."""
    if values.size <= 100:
        return []
    step = quantisation_step(values)
    findings = []
    for extreme, sign in ((values.max(), 1.0), (values.min(), -1.0)):
        clipped = sum(stop - start for start, stop in _runs(values == extreme)
                      if _headroom(values, start, stop, sign) > CLIP_HEADROOM * step)
        share = clipped / values.size
        if share > CLIP_SHARE:
            findings.append(Finding(name, "clipping", f"{100 * share:.2f} % of the samples sit at {extreme:.4g} where "
                                                      f"the signal on both sides would go on: clipped?", "warning"))
    return findings


def _headroom(values: np.ndarray, start: int, stop: int, sign: float) -> float:
    """How far beyond the run [start, stop) at an extreme (``sign`` +1: the maximum, -1: the minimum) the parabola
    through the two samples on each side of it goes; 0 where the record's ends leave fewer than three."""
    index = np.array([i for i in (start - 2, start - 1, stop, stop + 1) if 0 <= i < values.size])
    if index.size < 3:
        return 0.0
    curve = np.polyval(np.polyfit(index - start, values[index], 2), np.arange(stop - start))
    return float(np.max(sign * (curve - values[start])))


def _dropouts(name: str, values: np.ndarray) -> list[Finding]:
    """A warning for the longest run of one value that is a dropout (module docstring), or for a constant channel."""
    if values.size >= DROPOUT_RUN and np.all(values == values[0]):
        return [Finding(name, "dropout", f"the channel holds {values[0]:.4g} over the whole record: a dead channel?",
                        "warning")]
    margin = STEP_MARGIN * quantisation_step(values)
    same = np.concatenate([values[1:] == values[:-1], [False]])
    longest = 0
    for start, stop in _runs(same):
        length, stop = stop - start + 1, stop + 1  # the run of equal neighbours spans one sample more
        if length >= DROPOUT_RUN and length > longest and _moves_around(values, start, stop, margin):
            longest = length
    if not longest:
        return []
    return [Finding(name, "dropout", f"{longest} identical samples in a row where the channel moves: a dropout or a "
                                     f"frozen channel?", "warning")]


def _moves_around(values: np.ndarray, start: int, stop: int, margin: float) -> bool:
    """Whether the channel moves around the run [start, stop) of one value: it changes by more than ``margin`` per
    sample on both sides, or jumps into or out of it by more than ``margin`` beyond twice its change per sample on
    that side (a motion that starts from rest, even abruptly, steps out of its run by about one sample's change)."""
    held = values[start]
    before = abs(values[start - 1] - values[start - 2]) if start >= 2 else 0.0
    after = abs(values[stop + 1] - values[stop]) if stop + 1 < values.size else 0.0
    jumps = [(abs(values[i] - held), beyond) for i, beyond in ((start - 1, before), (stop, after))
             if 0 <= i < values.size]
    return min(before, after) > margin or any(jump > margin + 2 * beyond for jump, beyond in jumps)


def refuse_errors(findings: list[Finding]) -> None:
    """A RecordError naming every channel whose finding is an error (the record cannot be compared)."""
    errors = [f for f in findings if f.severity == "error"]
    if errors:
        raise RecordError("measured data failed the integrity checks: "
                          + "; ".join(f"{f.channel}: {f.message}" for f in errors))
