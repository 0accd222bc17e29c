"""``progressive_spring``: the spring stiffens with travel, the neuro-model paper's F = K0 x + Kn x^2 (+ cubic) about
static ride height (eq. 3; x compression from equilibrium).

    [progressive_spring.front]
    quadratic = 40000.0   # N/m^2
    cubic = 0.0           # N/m^3

Realised as a polynomial spring tendon beside the linear spring, MuJoCo's f = -(a y + b y^2 + c y^3) with
y = -x, so b = -Kn and c = cubic, centred on the static length.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import AxleCause, FitParameter, Shape, param, spring_beside_suspension, spring_reference

_REFERENCE_TRAVEL = 0.05  # m: the fitted stiffening is stated per this much compression


@dataclass(frozen=True)
class ProgressiveSpring:
    quadratic: float = field(default=0.0, metadata=param("N/m^2", -1e7, 1e7, "Kn of F = K0 x + Kn x^2"))
    cubic: float = field(default=0.0, metadata=param("N/m^3", -1e9, 1e9, "coefficient of x^3"))


class _ProgressiveSpring(AxleCause):
    name = "progressive_spring"
    subsystem = "car"
    values = ProgressiveSpring
    meaning = "the spring stiffens with travel (the neuro-model paper: K0 + Kn x, or cubic)"
    signature = "the residual curves with travel, growing with compression"
    evidence = (Shape.STIFFENS_IN_COMPRESSION, Shape.STIFFENS_IN_REBOUND, Shape.STIFFENS_BOTH_WAYS,
                Shape.SOFTENS_IN_COMPRESSION, Shape.SOFTENS_IN_REBOUND)

    def build_corner(self, car, corner, spring):
        spring_beside_suspension(car, f"{corner}/progressive_spring", corner, [0.0, -spring.quadratic, spring.cubic])

    def at_static_corner(self, model, data, corner, spring):
        spring_reference(model, data, f"{corner}/progressive_spring")

    def fit_parameters(self, vehicle, hints=None):
        """One-sided (quadratic) and symmetric (cubic) stiffening, each as the share of the linear rate the
        tangent stiffness gains at 50 mm of compression: 2 Kn x = share K0, 3 k3 x^2 = share K0; started from the
        stiffening the measured corner laws show, where the data give them."""
        def current(v, axle):
            return v.extensions.get(self.name, {}).get(axle, ProgressiveSpring())

        def quadratic(v, share):
            return self.on_every_axle(v, lambda a: dataclasses.replace(
                current(v, a), quadratic=share * getattr(v, a).suspension_rate / (2 * _REFERENCE_TRAVEL)))

        def cubic(v, share):
            return self.on_every_axle(v, lambda a: dataclasses.replace(
                current(v, a), cubic=share * getattr(v, a).suspension_rate / (3 * _REFERENCE_TRAVEL**2)))
        start = _shares_from_laws((hints or {}).get("measured_laws"), vehicle) or (0.1, 0.1)
        return [FitParameter("quadratic_share_at_50mm", float(np.clip(start[0], -1.2, 4.0)), -1.2, 4.0, quadratic),
                FitParameter("cubic_share_at_50mm", float(np.clip(start[1], -0.5, 20.0)), -0.5, 20.0, cubic)]

    def hidden(self, truth, rng):
        share = rng.uniform(0.3, 0.5)  # stiffness 30-50 % up at 25 mm of compression: 2 Kn x = share x K0
        return self.on_every_axle(truth, lambda a: ProgressiveSpring(
            quadratic=share * getattr(truth, a).suspension_rate / _REFERENCE_TRAVEL))


def _shares_from_laws(laws, vehicle) -> tuple[float, float] | None:
    """The quadratic and cubic shares (as ``fit_parameters`` states them) of the stiffening in the measured corner
    laws (rig/causes/measured_law.py, per axle): Kn x^2 + k3 x^3 fitted to each law's departure from its centre
    slope over the travel it covers, averaged over the axles; None without measured laws."""
    from rig.causes.measured_law import ramp_force

    shares = []
    for axle, law in (laws or {}).items():
        reach = max(abs(law.travel_knots[0]), abs(law.travel_knots[-1])) * 4 / 3
        travel = np.linspace(-reach, reach, 81)
        force = ramp_force(law, travel, np.zeros_like(travel))
        (kn, k3), *_ = np.linalg.lstsq(np.column_stack([travel**2, travel**3]), force, rcond=None)
        rate = getattr(vehicle, axle).suspension_rate
        shares.append((2 * kn * _REFERENCE_TRAVEL / rate, 3 * k3 * _REFERENCE_TRAVEL**2 / rate))
    return tuple(np.mean(shares, axis=0)) if shares else None


CAUSE = _ProgressiveSpring()
