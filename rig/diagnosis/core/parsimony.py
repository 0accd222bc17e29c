"""Parsimony, stated honestly: a cause that adds a body, a stop or a law to the car must beat, on held-out data, the
measurement explanations that gain as much (a channel's gain, polarity or delay, an input channel's calibration);
where two explanations gain alike within the held-out scatter, the measurement one is named, and the report names
both, says the records cannot separate them and names the test that would (``Cause.separated_by``).

The held-out scatter is measured on the held-out data itself: its compared part cut into SEGMENTS pieces, each
model's TDDI on each piece, and Student's t on the paired log ratios (two models scored on the same pieces share the
pieces' own difficulty, so their ratio is far steadier than either score; a cause's improvement is a factor, larger
where its effect is larger, so ratios, not differences). Two models are alike when the mean log ratio lies within
its 95 % interval of zero, or within 10 % (PRACTICAL: a model that scores within a tenth of another's is no ground
for adding a body to a car, however steady the pieces). A paired t-test on differences, as first written, took a
bench's friction (held-out gain 0.95) and a weak actuator's force constant (0.30) for alike: the friction's
improvement was concentrated in a few pieces, and the differences' scatter with it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import t as student

from rig.causes import Cause
from rig.diagnosis.core.validation import mean_tddi

SEGMENTS = 16
PRACTICAL = float(np.log(1.1))  # held-out TDDIs within this log ratio are alike, whatever the scatter


def by_measurement(cause: Cause) -> bool:
    """Whether the cause explains a discrepancy by the measurement chain rather than by the car: a sensor's fault, an
    input channel's calibration."""
    return cause.subsystem == "sensor" or bool(cause.input_quantities)


@dataclass(frozen=True)
class Comparison:
    """How a model scores against another on the held-out data: the mean over the pieces of the log of its TDDI over
    the other's (negative: better), and the half-width of that mean's 95 % interval."""

    log_ratio: float
    spread: float

    @property
    def alike(self) -> bool:
        return abs(self.log_ratio) <= max(self.spread, PRACTICAL)



def compare(measured: np.ndarray, simulated: np.ndarray, other: np.ndarray) -> Comparison:
    """``simulated`` against ``other`` on ``measured`` (samples x channels, the held-out data as compared)."""
    pieces = np.array_split(np.arange(measured.shape[0]), SEGMENTS)
    ratios = np.log([mean_tddi(measured[p], simulated[p]) / mean_tddi(measured[p], other[p]) for p in pieces])
    spread = student.ppf(0.975, SEGMENTS - 1) * np.std(ratios, ddof=1) / np.sqrt(SEGMENTS)
    return Comparison(float(np.mean(ratios)), float(spread))


def alike_statement(named: str, other: str, gains: tuple[float, float], comparison: Comparison, test: str) -> str:
    """What the report says of two explanations the records cannot separate."""
    low, high = np.exp(comparison.log_ratio - comparison.spread), np.exp(comparison.log_ratio + comparison.spread)
    return (f"{named} and {other} gain alike ({gains[0]:.3f} and {gains[1]:.3f} of the held-out TDDI; {other}'s model "
            f"scores {np.exp(comparison.log_ratio):.3g} times {named}'s, {low:.3g} to {high:.3g} within the held-out "
            f"scatter): these records cannot separate them, and {named}, the measurement's explanation, is named"
            + (f"; {test} would separate them" if test else ""))
