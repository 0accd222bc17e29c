"""The measurement chain of a test's inputs, checked from the records before any model is fitted: each input
channel's gain on the responses.

To first order a rig test's responses are the sum of each input's own response, y = sum_i H_i u_i (a post's
displacement, an actuator's force between body and wheel). The data sheet's model gives each H_i u_i (the model
moved by one input at a time, the others held still: ``Experiment.each_input_alone``), and least squares of the
measured responses on them gives each input's gain g_i: 1 where the channel records what moved the car, -1 where
its polarity is reversed, 3.5 where the record's force is 3.5 times too small. The model need not be right: masses
and rates off by a few percent move each g_i by a few percent; a reversed or badly scaled channel moves it by its
sign or its factor. So a polarity is found from evidence (a reversed force does work for the motion it is recorded
against), not as a gain bounded above zero, with a 95 % interval from the regression's residual (counted as the
2 B T independent values of a band of B Hz over T s per channel, as the fits count them).

A gain whose interval lies below zero is a reversed polarity; one off 1 by MIN_ERROR or more (its interval
excluding 1) is a scale fault; a reversed one, or one beyond GROSS times or under 1 / GROSS, is gross: no linear
recalibration of masses and rates can take it up, so the diagnosis corrects it before it recalibrates
(rig/diagnosis/rig_test/candidates.py ``Run``), and names it. Written here: the regression is NumPy's least squares;
what
is new is what it is run on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import OptimizeResult

from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.fitting import independent_samples, intervals
from rig.vehicle.vehicle_file import Vehicle

MIN_ERROR = 0.1  # a gain this far from 1 is an input's fault, not the data sheet's few percent
GROSS = 3.0      # beyond this factor (or reversed), no recalibration takes a fault up: corrected before it
#               (a lab bench's body friction halved its force's gain in the chain: 0.48 for a force constant of 0.8)


@dataclass(frozen=True)
class InputChain:
    """Each input channel's gain on the measured responses (1: right; negative: polarity reversed), with 95 %
    intervals, and the share of the responses' variance the inputs so weighted explain."""

    gains: dict[str, float]
    intervals: dict[str, tuple[float, float]]
    explained: float

    def reversed(self, name: str) -> bool:
        return self.intervals[name][1] < 0

    def off(self, name: str) -> bool:
        """Whether the channel's gain is an input's fault: reversed, or off 1 by MIN_ERROR with 1 outside its
        interval."""
        low, high = self.intervals[name]
        return self.reversed(name) or (abs(self.gains[name] - 1) >= MIN_ERROR and not low <= 1 <= high)

    def gross(self, name: str) -> bool:
        """A fault no recalibration takes up: reversed, or beyond GROSS times (or under 1 / GROSS)."""
        size = abs(self.gains[name])
        return self.off(name) and (self.reversed(name) or not 1 / GROSS <= size <= GROSS)

    @property
    def faults(self) -> dict[str, float]:
        """The gains of the channels that are off (``off``)."""
        return {n: g for n, g in self.gains.items() if self.off(n)}

    def lines(self) -> list[str]:
        """Each input channel's finding, in words."""
        lines = []
        for name, gain in self.gains.items():
            low, high = self.intervals[name]
            said = ("polarity reversed" + (f" and scaled by {abs(gain):.3g}" if abs(abs(gain) - 1) >= MIN_ERROR
                                          else "") if self.reversed(name)
                    else f"scaled by {gain:.3g}" if self.off(name) else "as recorded")
            lines.append(f"{name}: acts on the responses with {gain:.3g} ({low:.3g} to {high:.3g}) times its "
                         f"recorded value: {said}")
        return lines

    def to_json(self) -> dict:
        return {"gains": self.gains, "intervals": {k: list(v) for k, v in self.intervals.items()},
                "explained": self.explained, "faults": list(self.faults)}


def input_chain(experiment: Experiment, vehicle: Vehicle) -> InputChain:
    """The gain of each of ``experiment``'s input channels on its measured car channels, against the responses of
    ``vehicle`` (the data sheet's) to each input alone (module docstring)."""
    responses = experiment.each_input_alone(vehicle)
    names = list(responses)
    scale = np.sqrt(np.mean(experiment.measured**2, axis=0))
    scale[scale == 0] = 1.0
    regressors = np.column_stack([(responses[n] / scale).ravel() for n in names])
    measured = (experiment.measured / scale).ravel()
    gains, *_ = np.linalg.lstsq(regressors, measured, rcond=None)
    residual = measured - regressors @ gains
    result = OptimizeResult(x=gains, jac=regressors, fun=residual,
                            independent=independent_samples(experiment, experiment.measured.shape[1]))
    spread = intervals(result, names)
    explained = 1 - float(residual @ residual) / float(measured @ measured)
    return InputChain({n: float(g) for n, g in zip(names, gains)}, dict(zip(names, spread)), explained)
