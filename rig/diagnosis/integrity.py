"""Data-integrity checks of a measured record before it is compared with a model.

Findings name the channel and what is wrong: units that look wrong for the quantity (an RMS out of the
plausible range), clipping (many samples at the channel's extreme value), dropouts (runs of repeated
values), and non-finite data is already refused when the record is read.
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
CLIP_SHARE = 0.002   # share of samples sitting at the extreme value
DROPOUT_RUN = 8      # samples of the same value in a row


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
        for extreme in (values.max(), values.min()):
            share = float(np.mean(values == extreme))
            if share > CLIP_SHARE and values.size > 100:
                findings.append(Finding(name, "clipping", f"{100 * share:.2f} % of the samples sit at {extreme:.4g}: "
                                                          f"clipped?", "warning"))
        repeated = _longest_run(values)
        if repeated >= DROPOUT_RUN and quantity != "drive":
            findings.append(Finding(name, "dropout", f"{repeated} identical samples in a row: a dropout or a frozen "
                                                     f"channel?", "warning"))
    return findings


def _longest_run(values: np.ndarray) -> int:
    same = np.concatenate([[False], values[1:] == values[:-1], [False]])
    edges = np.flatnonzero(np.diff(same.astype(int)))
    return int((edges[1::2] - edges[::2]).max() + 1) if edges.size else 1


def refuse_errors(findings: list[Finding]) -> None:
    """A RecordError naming every channel whose finding is an error (the record cannot be compared)."""
    errors = [f for f in findings if f.severity == "error"]
    if errors:
        raise RecordError("measured data failed the integrity checks: "
                          + "; ".join(f"{f.channel}: {f.message}" for f in errors))
