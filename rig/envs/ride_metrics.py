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

A step costs a fixed number of array operations over all copies and corners, whatever their number: the
Wk sections' outputs are chained one after the other (each needs the one before), and then all their
delays are updated at once. Each value is computed with the operations ``scipy.signal.sosfilt`` applies,
in its order (transposed direct form II), so the filter's output is sosfilt's, bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from rig.envs.sensing import SensorMap
from rig.signal.comfort import wk_filter

_ZERO = np.array(0.0)

#: Rows of the running sums, per copy and corner: the squared travel, then the reward's terms.
TERMS = ("travel", "comfort", "tyre_load", "beyond", "power")


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


@dataclass
class RideSummary:
    """Ride metrics so far, each an array over copies (see the module docstring)."""

    a_w: np.ndarray              # m/s^2
    tyre_load_rms: np.ndarray    # dynamic over static tyre load
    travel_rms: np.ndarray       # m
    power_w: np.ndarray          # W


#: The metrics' names, as ``info`` carries them.
METRICS = tuple(f.name for f in fields(RideSummary))


class RideMetrics:
    """Running metrics of ``copies`` runs of a car with static tyre loads ``static_tyre_force`` (N per corner),
    reading body acceleration, tyre force and travel from the columns ``sensors`` converts."""

    def __init__(self, rate: float, static_tyre_force: np.ndarray, copies: int, travel_limit: float,
                 weights: RewardWeights, sensors: SensorMap):
        sos = wk_filter(rate)
        sections = sos.shape[0]
        self.static = np.asarray(static_tyre_force, float)
        # scalars as 0-d arrays: numpy converts a Python float at every call
        self.travel_limit, self.corners = np.array(float(travel_limit)), np.array(float(self.static.size))
        self.columns = [sensors.slice(q) for q in ("sprung_acc", "tyre_force", "susp_travel")]
        # minus the weights: the reward -(sum) is the sum of the negated terms, bit for bit (negation is exact)
        self._minus_weights = -np.array([[0.0], [weights.comfort], [weights.tyre_load], [weights.travel],
                                         [weights.power]])
        self.sums = np.zeros((len(TERMS), copies, self.static.size))
        self.count = 0  # samples so far: the copies run in lockstep
        # One buffer for the Wk chain (its input and every section's output, rows 0..sections) and the terms
        # (rows sections - 1 on): the last output is the comfort term before it is squared, and the travel
        # term takes the row of the output before it once the delays are updated.
        rows = np.zeros((sections + len(TERMS) - 1, copies, self.static.size))
        self._chain, self._terms = rows[:sections + 1], rows[sections - 1:]
        # The delays z0, z1 of every section, and a third row of -0.0 (adds nothing, not even to a zero's sign),
        # so that z0 = (b1 x - a1 y) + z1 and z1 = (b2 x - a2 y) + (-0.0) update in one addition.
        self._delays = np.zeros((3, sections, copies, self.static.size))
        self._delays[2] = -0.0
        self._scratch = np.empty((2, *self._delays[:2].shape))
        self._b12, self._a12 = sos[:, 1:3].T[:, :, None, None], sos[:, 4:6].T[:, :, None, None]
        self._sections = [(np.array(b0), self._chain[j], self._chain[j + 1], self._delays[0, j])
                          for j, b0 in enumerate(sos[:, 0])]

    def reset(self) -> None:
        self._delays[:2] = 0.0
        self.sums[...] = 0.0
        self.count = 0

    def update(self, k: int, sensed: np.ndarray, power: np.ndarray) -> np.ndarray:
        """Add one sample per copy (``sensed`` as SensorMap converts it, ``power`` W per corner); returns the
        reward per copy. (max(x, 0) as ``fmax``: the same for the finite values MuJoCo gives, and faster.)"""
        columns, terms = self.columns, self._terms  # terms[1] will hold the weighted acceleration
        self._wk_sample(sensed[:, columns[0]])
        travel = sensed[:, columns[2]]
        np.copyto(terms[0], travel)
        np.subtract(sensed[:, columns[1]], self.static, out=terms[2])
        np.divide(terms[2], self.static, out=terms[2])
        np.abs(travel, out=terms[3])
        np.subtract(terms[3], self.travel_limit, out=terms[3])
        np.fmax(terms[3], _ZERO, out=terms[3])
        np.square(terms[:4], out=terms[:4])
        np.fmax(power, _ZERO, out=terms[4])
        np.add(self.sums, terms, out=self.sums)
        self.count += 1
        weighted = np.add.reduce(terms, -1)  # (terms, copies): each term summed over corners, times minus its weight
        np.multiply(weighted, self._minus_weights, out=weighted)
        reward = np.add(weighted[1], weighted[2])
        np.add(reward, weighted[3], out=reward)
        np.divide(reward, self.corners, out=reward)
        return np.add(reward, weighted[4], out=reward)

    def _wk_sample(self, x: np.ndarray) -> None:
        """One sample through the Wk sections (transposed direct form II, as sosfilt computes it): each section's
        output y = b0 x + z0 from its input x, one after the other; then all delays at once, z0 = b1 x - a1 y + z1
        and z1 = b2 x - a2 y. The last output is left in the chain's last row."""
        chain, delays, scratch = self._chain, self._delays, self._scratch
        chain[0] = x
        for b0, section_in, section_out, z0 in self._sections:
            np.multiply(section_in, b0, out=section_out)
            section_out += z0
        np.multiply(chain[:-1], self._b12, out=scratch[0])
        np.multiply(chain[1:], self._a12, out=scratch[1])
        np.subtract(scratch[0], scratch[1], out=scratch[0])
        np.add(scratch[0], delays[1:], out=delays[:2])  # numpy reads delays[1] before it writes it

    def summary(self) -> RideSummary:
        mean = np.divide(self.sums, max(self.count, 1))
        rms = np.sqrt(np.maximum.reduce(mean[:3], -1))  # travel, comfort, tyre load
        return RideSummary(rms[1], rms[2], rms[0], np.add.reduce(mean[4], -1))
