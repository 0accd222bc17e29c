"""Evidence that does not depend on a cause's law, from the recalibrated model's held-out residual:
residual RMS per channel, per-channel gain and time shift, and the residual body acceleration against
suspension compression and its rate (stiffening shows as a slope change with travel, damping asymmetry
as one with the sign of the rate, friction as a step at zero rate)."""

from __future__ import annotations

import numpy as np

from rig.diagnosis.experiment import Experiment
from rig.io.channels import channel
from rig.signal.alignment import channel_delays, channel_gains


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
    for low, high in zip(edges[:-1], edges[1:]):
        inside = (x >= low) & (x < high)
        centres.append(float(np.mean(x[inside])))
        means.append(float(np.mean(y[inside])))
    return {"x": centres, "residual": means}
