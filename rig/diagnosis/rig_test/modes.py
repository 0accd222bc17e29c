"""Where the body's modes lie, measured and modelled: the resonance peak of the body's response to each input pattern
of the posts (heave, pitch, roll, warp: rig/diagnosis/core/validation.py) on a rig test's fit data.

A truck's frame twists in the warp pattern and bends in heave: a measured peak away from the model's tells how far
the mode is off, which is where a fit of it starts. A fit started at the model's own frequency does not move: the TDDI
of a resonance at the wrong frequency has minima on either side of the right one (a frame 40 % stiffer in bending than
its model, fitted from the model's frame, gained nothing; the peaks' ratio put the start within 3 % of it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.diagnosis.core.experiment import Experiment
from rig.diagnosis.core.validation import PATTERNS, pattern_frfs, pattern_segment, pattern_weights
from rig.io.channels import channel

BODY_MODES_HZ = (3.0, 30.0)  # searched for peaks: above the body's bounce on its springs, below the wheels' hop


@dataclass(frozen=True)
class PatternPeak:
    """The body's resonance peak (Hz) in one post pattern, measured and as the model has it."""

    measured_hz: float
    model_hz: float

    @property
    def ratio(self) -> float:
        """How far the measured mode lies above the model's (1: where the model has it)."""
        return self.measured_hz / self.model_hz


def pattern_peaks(experiment: Experiment, simulated: np.ndarray) -> dict[str, PatternPeak]:
    """Per post pattern, the peak of the body's pattern response (the body accelerometers combined as the posts are)
    to the pattern's input, between BODY_MODES_HZ, of the measured car channels and of the model's ``simulated`` ones
    (samples x car channels); empty without body accelerometers at every corner."""
    names = [channel(c, "sprung_acc") for c in experiment.corners]
    if not all(n in experiment.car_channels for n in names):
        return {}
    index = [experiment.car_channels.index(n) for n in names]
    weights = pattern_weights(experiment.corners)
    posts = experiment.posts.quantity("actuator_disp", experiment.corners)[experiment.settle:]
    rate = experiment.record.rate
    segment = pattern_segment(posts.shape[0], rate)
    peaks = {}
    for label, response in (("measured", experiment.measured), ("model", simulated)):
        body = response[:, index] @ weights.T
        frequency, h1, _ = pattern_frfs(posts, body, rate, segment, experiment.corners)
        peaks[label] = [peak_frequency(frequency, np.abs(h1[:, k, k])) for k in range(len(weights))]
    return {name: PatternPeak(m, s) for name, m, s in zip(PATTERNS, peaks["measured"], peaks["model"])}


def peak_frequency(frequency: np.ndarray, magnitude: np.ndarray, band: tuple[float, float] = BODY_MODES_HZ) -> float:
    """The frequency (Hz) of the largest ``magnitude`` inside ``band``, between lines by a parabola through the
    logarithms of the peak line and its neighbours."""
    inside = np.flatnonzero((frequency >= band[0]) & (frequency <= band[1]))
    top = inside[np.argmax(magnitude[inside])]
    if top in (0, frequency.size - 1):
        return float(frequency[top])
    left, centre, right = np.log(np.maximum(magnitude[top - 1:top + 2], 1e-300))
    curvature = left - 2 * centre + right
    shift = 0.5 * (left - right) / curvature if curvature < 0 else 0.0
    return float(frequency[top] + shift * (frequency[1] - frequency[0]))
