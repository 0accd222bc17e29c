"""``neuro_law``: the suspension's force law learned as the neuro-model paper's networks; a generic element.

"Neuro Model for Passive Suspension of a Light Car" (paper) models the quarter car's spring and damper by sigmoid
units (its eq. 42, f(net) = e^net / (1 + e^net) - 0.5) beside their linear parts (its K0 x and C0 v). Here a spring
network on the compression x and a damper network on its rate v, trained on the suspension force the data measure
(rig/diagnosis/rig_test/neuro_corner_law.py), each a curve through zero at ride height:

    F_spring(x) = k x + sum_j a_j [f(w_j x + b_j) - f(b_j)],    F_damper(v) = c v + sum_m d_m [f(u_m v + e_m) - f(e_m)]

The law takes the axle's spring and damper over: where it is present, the axle's linear spring (spring + parasitic
rate) and damping are taken off again, so that the corner's spring and damper are the curves (the diagnosis's
recalibration then leaves those rates at the data sheet's: ``owns``). The section holds the networks:

    [neuro_law.front]
    travel_linear = 28500.0             # N/m, k
    travel_weights = [310.0, -95.0]     # 1/m, w_j of the spring units
    travel_biases = [0.4, -0.2]         # -, b_j
    travel_outputs = [-850.0, 120.0]    # N, a_j
    rate_linear = 3900.0                # N s/m, c
    rate_weights = [12.0]               # s/m, of the damper units
    rate_biases = [0.0]
    rate_outputs = [-1300.0]            # N
    travel_reach = [-0.045, 0.03]       # m: the compression the networks were trained over
    rate_reach = [-0.6, 0.6]            # m/s: the rate they were trained over

Separable in travel and rate, the law is realised inside ``mj_step`` as measured_law's is (rig/causes/measured_law.py:
clamped affine ramps, no Python callback): each curve less the axle's linear rate as chords between KNOTS knots per
side spread over REACH_MARGIN times its reach (the rebound side's first knot 0.1 % of that off ride height: a rebound
ramp acts below its knot), and beyond the last knot the slope the curve has there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rig.causes._base import AXLES, FitParameter, ParameterSpec, with_extension
from rig.causes.measured_law import ListedLaw, MeasuredLaw, add_ramps, set_ramp_references
from rig.signal.neuro_network import unit

KNOTS = 16             # chords per side of ride height
REACH_MARGIN = 1.25    # the chords cover this much beyond the trained reach
LIMITS = {"travel_linear": 1e8, "travel_weights": 1e9, "travel_biases": 1e7, "travel_outputs": 1e6,
          "rate_linear": 1e6, "rate_weights": 1e6, "rate_biases": 1e6, "rate_outputs": 1e6, "travel_reach": 0.3,
          "rate_reach": 10.0}
UNITS = {"travel_linear": "N/m", "travel_weights": "1/m", "travel_biases": "-", "travel_outputs": "N",
         "rate_linear": "N s/m", "rate_weights": "s/m", "rate_biases": "-", "rate_outputs": "N", "travel_reach": "m",
         "rate_reach": "m/s"}
SCALARS = ("travel_linear", "rate_linear")


@dataclass(frozen=True)
class NeuroLaw:
    travel_linear: float
    travel_weights: tuple[float, ...]
    travel_biases: tuple[float, ...]
    travel_outputs: tuple[float, ...]
    rate_linear: float
    rate_weights: tuple[float, ...]
    rate_biases: tuple[float, ...]
    rate_outputs: tuple[float, ...]
    travel_reach: tuple[float, float]
    rate_reach: tuple[float, float]

    def travel_force(self, x: np.ndarray) -> np.ndarray:
        """The spring's force on the body (N, up) at compression ``x`` (m) from ride height."""
        return _curve(np.asarray(x, float), self.travel_linear, self.travel_weights, self.travel_biases,
                      self.travel_outputs)

    def rate_force(self, v: np.ndarray) -> np.ndarray:
        """The damper's force on the body (N, up) at compression rate ``v`` (m/s)."""
        return _curve(np.asarray(v, float), self.rate_linear, self.rate_weights, self.rate_biases, self.rate_outputs)

    def scaled(self, stiffness: float, damping: float) -> NeuroLaw:
        """The law with the spring's and the damper's curves scaled."""
        return NeuroLaw(stiffness * self.travel_linear, self.travel_weights, self.travel_biases,
                        tuple(stiffness * a for a in self.travel_outputs), damping * self.rate_linear,
                        self.rate_weights, self.rate_biases, tuple(damping * a for a in self.rate_outputs),
                        self.travel_reach, self.rate_reach)

    def as_ramps(self, rate: float, damping: float) -> MeasuredLaw:
        """The chords that realise the law (module docstring) as measured_law's ramps, on a corner whose linear
        spring + parasitic ``rate`` (N/m) and ``damping`` (N s/m) they take off."""
        travel = _ramps(lambda x: self.travel_force(x) - rate * x, self.travel_reach)
        speed = _ramps(lambda v: self.rate_force(v) - damping * v, self.rate_reach)
        return MeasuredLaw(*travel, *speed)


def _curve(x: np.ndarray, linear: float, weights, biases, outputs) -> np.ndarray:
    """k x + sum_j a_j [f(w_j x + b_j) - f(b_j)]."""
    total = linear * x
    for w, b, a in zip(weights, biases, outputs):
        total = total + a * (unit(w * x + b) - unit(b))
    return total


def _ramps(curve, reach: tuple[float, float]) -> tuple[tuple[float, ...], ...]:
    """Knots and slope changes of the chords of ``curve`` (zero at zero) per side, its own slope beyond the last."""
    knots, changes = [], []
    for end in (REACH_MARGIN * reach[0], REACH_MARGIN * reach[1]):
        if end == 0:
            continue
        points = end * np.arange(KNOTS + 1) / KNOTS
        points[0] = 1e-3 * end if end < 0 else 0.0
        values = curve(points)
        beyond = (curve(np.array([end * (1 + 1e-4)]))[0] - values[-1]) / (1e-4 * end)
        values[0] = 0.0  # the first chord from ride height itself, where the curve is zero
        slopes = np.append(np.diff(values) / np.diff(points), beyond)
        knots += list(points)
        changes += list(np.diff(slopes, prepend=0.0))  # the change at each knot, going away from ride height
    order = np.argsort(knots)
    return tuple(float(knots[i]) for i in order), tuple(float(changes[i]) for i in order)


class _NeuroLaw(ListedLaw):
    name = "neuro_law"
    damper_line = "law"
    subsystem = "car"
    values = NeuroLaw
    generic = True
    learned = True
    owns = tuple(f"{axle}_{key}" for axle in AXLES for key in ("spring_rate", "damping"))
    meaning = ("the suspension force law differs in shape from the model's (learned by the neuro-model paper's "
               "networks of sigmoid units on travel and on its rate)")
    signature = "the measured restoring force bends away from the model's straight law, in a shape no cause has"

    limits, scalars = LIMITS, SCALARS

    def read(self, table: Any, where: str) -> NeuroLaw:
        values = self.numbers(table, where)
        for group in ("travel", "rate"):
            sizes = {len(values[f"{group}_{part}"]) for part in ("weights", "biases", "outputs")}
            if len(sizes) > 1:
                raise ValueError(f"{where}: {group}_weights, {group}_biases and {group}_outputs must have the same "
                                 f"length")
            reach = values[f"{group}_reach"]
            if len(reach) != 2 or not reach[0] <= 0.0 <= reach[1] or reach[0] == reach[1]:
                raise ValueError(f"{where}: {group}_reach must be [lo, hi] with lo <= 0 <= hi, lo < hi")
        return NeuroLaw(**values)

    def parameters(self):
        meanings = ("the spring's linear rate", "spring units' input weights", "spring units' biases",
                    "spring units' output weights", "the damper's linear rate", "damper units' input weights",
                    "damper units' biases", "damper units' output weights", "compression trained over [lo, hi]",
                    "compression rate trained over [lo, hi]")
        return [ParameterSpec(key, UNITS[key], -limit, limit, meaning)
                for (key, limit), meaning in zip(LIMITS.items(), meanings, strict=True)]

    def build(self, car, vehicle):
        for corner in vehicle.corners:
            law = self.at(vehicle, corner)
            if law is not None:
                axle = vehicle.axle(corner)
                add_ramps(car, corner, law.as_ramps(axle.suspension_rate, axle.damping), self.name)

    def at_static_ride_height(self, model, data, vehicle):
        for corner in vehicle.corners:
            law = self.at(vehicle, corner)
            if law is not None:
                axle = vehicle.axle(corner)
                set_ramp_references(model, data, corner, law.as_ramps(axle.suspension_rate, axle.damping), self.name)

    def fit_parameters(self, vehicle, hints=None):
        """The learned laws (``hints["neuro_laws"]``, per axle) with their spring and damper curves scaled, alike on
        every axle, each share from 1 (as learned)."""
        learned = (hints or {}).get("neuro_laws")
        if not learned:
            return []
        reference = next(iter(learned))

        def share(v, kind: str) -> float:
            law = v.extensions.get(self.name, {}).get(reference)
            first = getattr(learned[reference], kind)
            return 1.0 if law is None else getattr(law, kind) / first if first else 1.0

        def apply(v, stiffness, damping):
            return with_extension(v, self.name, {a: law.scaled(stiffness, damping) for a, law in learned.items()})

        return [FitParameter("stiffness_share", 1.0, 0.0, 2.0, lambda v, s: apply(v, s, share(v, "rate_linear"))),
                FitParameter("damping_share", 1.0, 0.0, 2.0, lambda v, s: apply(v, share(v, "travel_linear"), s))]


CAUSE = _NeuroLaw()
