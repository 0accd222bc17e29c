"""Running ride metrics of a car under control, and the suspension environments' reward.

Per copy of the environment (arrays over copies x corners), updated one sample at a time from the
initial state on, so that at the end of an episode they equal the metrics of its whole record:

- ``a_w``: ISO 2631-1 Wk-weighted RMS body acceleration (m/s^2), worst corner: the body acceleration is
  run through the Wk filter (rig/signal/comfort.py) sample by sample, from rest;
- ``tyre_load_rms``: RMS of the dynamic tyre load over the static load, worst corner;
- ``travel_rms``: RMS suspension travel from static ride height (m), worst corner;
- ``power_w``: mean power the controller's actuators deliver (W, all corners): the positive part of
  force x extension rate (a semi-active damper never delivers any).

The reward of a step is minus a weighted sum of squared Wk-weighted body acceleration ((m/s^2)^2), squared
relative dynamic tyre load, squared travel beyond ``travel_limit`` (m^2), each averaged over corners, and
the actuator power (W).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.signal.comfort import wk_filter

METRICS = ("a_w", "tyre_load_rms", "travel_rms", "power_w")


@dataclass(frozen=True)
class RewardWeights:
    """Weights of the reward terms: per (m/s^2)^2, per (load/static load)^2, per m^2, per W."""

    comfort: float = 1.0
    tyre_load: float = 10.0
    travel: float = 1e4
    power: float = 1e-4

    def __post_init__(self) -> None:
        for name in ("comfort", "tyre_load", "travel", "power"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0:
                raise ValueError(f"reward weight {name} must be a non-negative number, got {value}")


class RideMetrics:
    """Running metrics of ``copies`` runs of a car with static tyre loads ``static_tyre_force`` (N per corner)."""

    def __init__(self, rate: float, static_tyre_force: np.ndarray, copies: int, travel_limit: float,
                 weights: RewardWeights):
        self.sos = wk_filter(rate)
        self.static = np.asarray(static_tyre_force, float)
        self.travel_limit, self.weights = travel_limit, weights
        corners = self.static.size
        self.zi = np.zeros((self.sos.shape[0], 2, copies, corners))  # per section, its two delays
        self.sums = {name: np.zeros((copies, corners)) for name in ("comfort", "tyre_load", "travel", "power")}
        self.count = np.zeros(copies)

    def reset(self, ids: np.ndarray) -> None:
        self.zi[:, :, ids] = 0.0
        for total in self.sums.values():
            total[ids] = 0.0
        self.count[ids] = 0

    def update(self, sprung_acc: np.ndarray, tyre_force: np.ndarray, travel: np.ndarray,
               power: np.ndarray) -> np.ndarray:
        """Add one sample per copy (arrays copies x corners); returns the reward per copy."""
        weighted = self._wk_sample(sprung_acc)
        comfort = weighted**2
        tyre_load = ((tyre_force - self.static) / self.static) ** 2
        beyond = np.maximum(np.abs(travel) - self.travel_limit, 0.0) ** 2
        delivered = np.maximum(power, 0.0)
        self.sums["comfort"] += comfort
        self.sums["tyre_load"] += tyre_load
        self.sums["travel"] += travel**2
        self.sums["power"] += delivered
        self.count += 1
        w, corners = self.weights, self.static.size
        return -((w.comfort * comfort.sum(-1) + w.tyre_load * tyre_load.sum(-1) + w.travel * beyond.sum(-1)) / corners
                 + w.power * delivered.sum(-1))

    def _wk_sample(self, x: np.ndarray) -> np.ndarray:
        """One sample through the Wk sections, transposed direct form II, as ``scipy.signal.sosfilt`` computes it
        (the same operations in the same order), without its per-call overhead."""
        for (b0, b1, b2, _, a1, a2), (z0, z1) in zip(self.sos, self.zi):
            y = b0 * x + z0
            z0[...] = b1 * x - a1 * y + z1
            z1[...] = b2 * x - a2 * y
            x = y
        return x

    def summary(self) -> dict[str, np.ndarray]:
        """The metrics so far (METRICS), each an array over copies."""
        s = {k: v / np.maximum(self.count, 1)[:, None] for k, v in self.sums.items()}
        return {"a_w": np.sqrt(s["comfort"].max(-1)), "tyre_load_rms": np.sqrt(s["tyre_load"].max(-1)),
                "travel_rms": np.sqrt(s["travel"].max(-1)), "power_w": s["power"].sum(-1)}
