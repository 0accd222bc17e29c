"""Which inverse model estimates a target's drive: each checked on the part of the training record it was not fitted
on, by its drive error and by the residual tests of the neuro-model paper ("Neuro Model for Passive Suspension of a
Light Car" (paper); rig/signal/residual_tests.py).

Each method is fitted on the first 1 - VALIDATION of the training record (the FRF's H1, the NARX, the neuro form;
Nurhadiyanto's Eq 5.1 needs no fit) and estimates the drive of the whole record from its responses (the NARX runs
free from the cut, its inputs formed on the whole record); its held-out error per corner is Nurhadiyanto's drive
error on the rest, and its residual there (true minus estimated drive, in the drive band, EDGE s dropped at each
end) is tested for whiteness against the corner's body and wheel accelerations. The choice (``choose``): the lowest
held-out worst-corner error; among the methods within CHOICE_MARGIN of it, the one whose residual is white at the
most corners; and where the target leaves what the training taught (controllers/training_coverage.py), the method
whose structure is the car's (the neuro form: Eq 5.1 with a learned suspension force, which extrapolates as a spring
and a damper do) before a black box (the NARX, the FRF inverse), whose held-out error says nothing of a target
beyond its training. Measured on the independent large-event case (tests/drive_estimation_case.py): held-out worst
corners Eq 5.1 21.7 %, FRF 36.3 %, NARX 2.41 % (white at 1 corner), neuro form 2.54 % (white at 3), and on the
target beyond the training 29.2 %, 49.1 %, 12.4 % and 6.0 %.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import band_pass
from rig.signal.metrics import drive_error_pct
from rig.signal.residual_tests import ResidualTests, residual_tests

VALIDATION = 0.25     # of the training record held out
EDGE = 1.0            # s dropped at each end of the held-out part
CHOICE_MARGIN = 1.5   # methods within this factor of the best held-out error are compared on their residuals
STRUCTURED = ("neuro", "inverse-model")  # the car's structure, before the black boxes where the target is beyond


@dataclass
class HeldOut:
    """One method's check on the held-out part: drive error per corner (%) and residual tests per corner."""

    method: str
    errors: np.ndarray
    tests: list[ResidualTests]

    @property
    def worst(self) -> float:
        return float(np.max(np.where(np.isfinite(self.errors), self.errors, np.inf)))

    @property
    def white(self) -> int:
        """Corners whose residual is white against their responses (every cross-correlation passes)."""
        return sum(all(c.white for c in t.cross) for t in self.tests)

    def to_json(self) -> dict:
        return {"held_out_error_pct": [round(float(e), 3) for e in self.errors], "worst_pct": round(self.worst, 3),
                "white_corners": self.white, "residual_tests": {t.model: t.to_json() for t in self.tests}}


def split(train: Record) -> tuple[Record, Record]:
    """The fitted and the held-out parts of a training record."""
    cut = int(round((1 - VALIDATION) * train.n_samples))
    parts = [{n: v[:cut] for n, v in train.channels.items()}, {n: v[cut:] for n, v in train.channels.items()}]
    return (Record(train.rate, parts[0], dict(train.units), dict(train.metadata)),
            Record(train.rate, parts[1], dict(train.units), dict(train.metadata), train.start_time + cut / train.rate))


def held_out(method: str, estimate: Callable[[Record, Record], np.ndarray] | None, train: Record,
             corners: tuple[str, ...], band: tuple[float, float], parameters: int = 0,
             drive: np.ndarray | None = None) -> HeldOut:
    """The check of ``method``: ``estimate(fitted part, whole record)`` gives the drive of the whole record, fitted on
    the first part (samples x corners; or ``drive``, already estimated on the held-out part)."""
    fitted, held = split(train)
    values = estimate(fitted, train)[-held.n_samples:] if drive is None else drive
    truth = held.quantity("drive", corners)
    edge = int(round(EDGE * train.rate))
    inside = slice(edge, truth.shape[0] - edge)
    errors = drive_error_pct(truth[inside], values[inside], train.rate, band)
    residual = band_pass(truth - values, train.rate, band)[inside]
    tests = []
    for i, corner in enumerate(corners):
        inputs = {channel(corner, q): band_pass(held[channel(corner, q)], train.rate, band)[inside]
                  for q in ("sprung_acc", "unsprung_acc")}
        tests.append(residual_tests(f"{method} drive, {corner}", residual[:, i], inputs, parameters, train.rate,
                                    band))
    return HeldOut(method, errors, tests)


def choose(checks: list[HeldOut], covered: bool) -> tuple[HeldOut, str]:
    """The chosen method's check and why (module docstring)."""
    best = min(checks, key=lambda c: c.worst)
    close = [c for c in checks if c.worst <= CHOICE_MARGIN * best.worst]
    if not covered:
        structured = [c for c in close if c.method in STRUCTURED]
        if structured:
            chosen = min(structured, key=lambda c: (STRUCTURED.index(c.method), c.worst))
            return chosen, (f"the target leaves the training: {chosen.method}, the car's structure, held out "
                            f"{chosen.worst:.2f} % (best {best.method} {best.worst:.2f} %)")
    chosen = max(close, key=lambda c: (c.white, -c.worst))
    return chosen, (f"{chosen.method}: held out {chosen.worst:.2f} % worst corner, white at {chosen.white} of "
                    f"{len(chosen.tests)} corners (within {CHOICE_MARGIN:g} x of the best, {best.method} "
                    f"{best.worst:.2f} %)")
