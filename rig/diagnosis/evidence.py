"""Evidence that does not depend on a cause's law, from the recalibrated model's held-out residual:
residual RMS per channel, per-channel gain and time shift, the residual body acceleration against
suspension compression and its rate (stiffening shows as a slope change with travel, damping asymmetry
as one with the sign of the rate, friction as a step at zero rate), and where the residual lives
(channels, band, amplitude dependence) when no cause explains it."""

from __future__ import annotations

import numpy as np
from scipy.signal import welch

from rig.constants import ANALYSIS_BAND
from rig.diagnosis.experiment import Experiment
from rig.io.channels import channel
from rig.signal.alignment import channel_delays, channel_gains
from rig.signal.metrics import tddi
import itertools


def residual_evidence(test: Experiment, simulated: np.ndarray) -> dict:
    """Evidence from held-out car channels (band-passed, samples x ``test.car_channels``)."""
    measured = test.measured
    car = test.car_channels
    residual = measured - simulated
    share = np.sqrt(np.mean(residual**2, axis=0) / np.mean(measured**2, axis=0))
    evidence = {"residual_rms_share": dict(zip(car, map(float, share))),
                "channel_gain": dict(zip(car, map(float, channel_gains(measured, simulated)))),
                "channel_delay_s": dict(zip(car, map(float, channel_delays(measured, simulated, test.record.rate))))}
    travel_names = [channel(c, "susp_travel") for c in test.corners]
    sprung_names = [channel(c, "sprung_acc") for c in test.corners]
    if all(n in car for n in travel_names + sprung_names):
        travel = measured[:, [car.index(n) for n in travel_names]]
        rate = np.gradient(travel, axis=0) * test.record.rate
        body = residual[:, [car.index(n) for n in sprung_names]]
        evidence["residual_vs_travel"] = _binned(travel, body)
        evidence["residual_vs_travel_rate"] = _binned(rate, body)
    return evidence


def _binned(x: np.ndarray, y: np.ndarray, bins: int = 9) -> dict:
    edges = np.quantile(x, np.linspace(0.02, 0.98, bins + 1))
    centres, means = [], []
    for low, high in itertools.pairwise(edges):
        inside = (x >= low) & (x < high)
        centres.append(float(np.mean(x[inside])))
        means.append(float(np.mean(y[inside])))
    return {"x": centres, "residual": means}


def locate_residual(test: Experiment, measured: np.ndarray, simulated: np.ndarray, floors: np.ndarray,
                    beyond: float) -> dict:
    """Where a model's held-out residual lives (samples x ``test.names`` arrays; ``floors``: each channel's
    noise-floor TDDI): the channels whose TDDI exceeds ``beyond`` times their floor (worst first), the band
    holding 10-90 % of their residual power above the noise, its peak, and the amplitude dependence (residual
    share in the loudest third of the record over that in the quietest: 1 for a linear model error)."""
    rate = test.record.rate
    scores = np.array([tddi(measured[:, i], simulated[:, i]) for i in range(measured.shape[1])])
    excess = scores / np.maximum(floors, 1e-12)
    order = [i for i in np.argsort(-scores) if excess[i] > beyond]
    channels = [i for i in order if scores[i] >= 0.3 * scores[order[0]]] if order else []
    if not channels:
        return {"channels": [], "band_hz": [], "peak_hz": None, "amplitude_dependence": None}
    residual = measured[:, channels] - simulated[:, channels]
    frequency, psd = welch(residual, rate, nperseg=min(residual.shape[0], int(4 * rate)), axis=0)
    power = np.sum(psd / np.mean(measured[:, channels] ** 2, axis=0), axis=1)  # each channel relative to its size
    inside = (frequency >= ANALYSIS_BAND[0]) & (frequency <= ANALYSIS_BAND[1])
    power = np.where(inside, power, 0.0)
    cumulative = np.cumsum(power) / np.sum(power)
    low, high = frequency[np.searchsorted(cumulative, 0.1)], frequency[np.searchsorted(cumulative, 0.9)]
    window = max(1, int(0.5 * rate))
    loudness = np.sqrt(np.convolve(np.sum(measured[:, channels] ** 2, axis=1), np.ones(window) / window, "same"))
    quiet, loud = loudness <= np.quantile(loudness, 1 / 3), loudness >= np.quantile(loudness, 2 / 3)

    def share(part):
        return np.sqrt(np.sum(residual[part] ** 2) / np.sum(measured[part][:, channels] ** 2))

    return {"channels": [test.names[i] for i in channels], "band_hz": [float(low), float(high)],
            "peak_hz": float(frequency[np.argmax(power)]), "amplitude_dependence": float(share(loud) / share(quiet))}
