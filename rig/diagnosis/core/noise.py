"""The accuracy target of a diagnosis: the discrepancy a perfect model would still show on this record.

Forsén (1999) argues that the experimental scatter is the accuracy a model can be
asked for. Two parts are measured from the record itself, per compared channel, as Forsén's TDDI:
- measurement noise on the compared channel, from its PSD in NOISE_BAND (where a car on the rig barely
  responds), over the analysis band; a record sampled too slowly to hold that band gets its noise from the
  band between the analysis band and its Nyquist frequency, where the car still responds: the floor is then an
  upper bound (``noise_band`` says which);
- measurement noise on the post displacements that drive the model: the same level of white noise is
  added to the posts once more and the model's response to it is simulated (the model is linear enough
  in it that a second realisation shows what the first one costs).
"""

from __future__ import annotations

import numpy as np
from scipy.signal import welch

from rig.diagnosis.core.experiment import Experiment
from rig.signal.metrics import tddi
from rig.vehicle.vehicle_file import Vehicle

NOISE_BAND = (100.0, 200.0)  # Hz: above the vehicle's response, where a record holds only its noise
DETECTION_FACTOR = 5.0       # a model is called right within this multiple of the noise floor (the detection limit)
NYQUIST_SHARE = 0.45         # the noise band ends below this share of the sample rate


def noise_band(rate: float, top: float) -> tuple[tuple[float, float], bool]:
    """The band (Hz) a record at ``rate`` Hz measures its noise in, and whether the car still responds there (the
    floor is then an upper bound): NOISE_BAND below the Nyquist frequency, else what lies above ``top``, the
    analysis band's top."""
    high = min(NOISE_BAND[1], NYQUIST_SHARE * rate)
    if high > NOISE_BAND[0] * 1.1:
        return (NOISE_BAND[0], high), False
    return (top, NYQUIST_SHARE * rate), True


def noise_level(values: np.ndarray, rate: float, top: float = NOISE_BAND[0]) -> float:
    """One-sided PSD level (unit^2/Hz) of a channel's white noise, from ``noise_band(rate, top)``."""
    (low, high), _ = noise_band(rate, top)
    frequency, psd = welch(values, rate, nperseg=min(1024, values.size))
    inside = (frequency >= low) & (frequency <= high)
    return float(np.mean(psd[inside] if inside.any() else psd[-1:]))


def measurement_floor(experiment: Experiment) -> np.ndarray:
    """Per compared channel: the TDDI of the measured channel against its noise-free self."""
    record, measured, (low, high) = experiment.record, experiment.measured_all(), experiment.band
    floors = []
    for i, name in enumerate(experiment.names):
        noise_power = noise_level(record[name], record.rate, high) * (high - low)
        floors.append(noise_power / (2 * np.mean(measured[:, i] ** 2)))
    return np.array(floors)


def input_floor(experiment: Experiment, vehicle: Vehicle, reference: np.ndarray, seed: int = 0) -> np.ndarray:
    """Per compared channel: the TDDI that the post-displacement noise leaves on ``vehicle``'s simulation
    (``reference``: its simulation on the measured posts, samples x car channels)."""
    record, corners = experiment.record, experiment.corners
    levels = [noise_level(record[f"{c}/actuator_disp"], record.rate, experiment.band[1]) for c in corners]
    rng = np.random.default_rng(seed)
    noise = rng.standard_normal((record.n_samples, len(corners))) * np.sqrt(np.array(levels) * record.rate / 2)
    noisy = experiment.with_post_noise(noise).simulate_car([vehicle])[0]
    floors = np.zeros(len(experiment.names))
    floors[:reference.shape[1]] = [tddi(reference[:, i], noisy[:, i]) for i in range(reference.shape[1])]
    return floors
