"""``progressive_spring``: the spring stiffens with travel, the neuro-model paper's F = K0 x + Kn x^2 (+ cubic) about
its design position (eq. 3; x compression), where the car sits unless a load the data sheet does not carry (a
payload) has pressed it ``sag`` m into the curve.

    [progressive_spring.front]
    quadratic = 40000.0   # N/m^2
    cubic = 0.0           # N/m^3
    sag = 0.0             # m, optional: how far static ride height sits into the curve from its design position
    sag_left_right = 0.0  # m, optional: the left wheel's sag less the right's (a load off the centre line)

About static ride height (x = 0 there, the design position at x = -sag) the added force is
Kn ((x + s)^2 - s^2) + k3 ((x + s)^3 - s^3) = (2 Kn s + 3 k3 s^2) x + (Kn + 3 k3 s) x^2 + k3 x^3: a progressive spring
under a load is stiffer at ride height as well as curved (its static part is carried, so the static position alone
moves, which nothing measures). Realised as a polynomial spring tendon beside the linear spring, MuJoCo's
f = -(a y + b y^2 + c y^3) with y = -x: a, -b and c are those three coefficients, centred on the static length.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import AxleCause, FitParameter, Shape, axles_of
from rig.elements.parameters import param
from rig.elements.tendons import spring_beside_suspension, spring_reference

_REFERENCE_TRAVEL = 0.05  # m: the fitted stiffening is stated per this much compression


@dataclass(frozen=True)
class ProgressiveSpring:
    quadratic: float = field(default=0.0, metadata=param("N/m^2", -1e7, 1e7, "Kn of F = K0 x + Kn x^2"))
    cubic: float = field(default=0.0, metadata=param("N/m^3", -1e9, 1e9, "coefficient of x^3"))
    sag: float = field(default=0.0, metadata=param("m", -0.2, 0.2, "static ride height's compression from the "
                                                                    "design position"))
    sag_left_right: float = field(default=0.0, metadata=param("m", -0.2, 0.2, "the left wheel's sag less the right's"))

    def about_static(self, left: bool) -> tuple[float, float, float]:
        """Rate (N/m), quadratic (N/m^2) and cubic (N/m^3) coefficients of the added force about static ride
        height of the left or right wheel (module docstring)."""
        s = self.sag + (0.5 if left else -0.5) * self.sag_left_right
        return 2 * self.quadratic * s + 3 * self.cubic * s**2, self.quadratic + 3 * self.cubic * s, self.cubic


class _ProgressiveSpring(AxleCause):
    name = "progressive_spring"
    subsystem = "car"
    values = ProgressiveSpring
    meaning = "the spring stiffens with travel (the neuro-model paper: K0 + Kn x, or cubic)"
    signature = "the residual curves with travel, growing with compression"
    evidence = (Shape.STIFFENS_IN_COMPRESSION, Shape.STIFFENS_IN_REBOUND, Shape.STIFFENS_BOTH_WAYS,
                Shape.SOFTENS_IN_COMPRESSION, Shape.SOFTENS_IN_REBOUND, Shape.SUSPENSION_RATE)

    def build_corner(self, car, corner, spring):
        rate, quadratic, cubic = spring.about_static(left=corner[-1] == "L")
        spring_beside_suspension(car, f"{corner}/progressive_spring", corner, [rate, -quadratic, cubic])

    def at_static_corner(self, model, data, corner, spring):
        spring_reference(model, data, f"{corner}/progressive_spring")

    def fit_parameters(self, vehicle, hints=None):
        """One-sided (quadratic) and symmetric (cubic) stiffening, each as the share of the linear rate the
        tangent stiffness gains at 50 mm of compression: 2 Kn x = share K0, 3 k3 x^2 = share K0, started from the
        stiffening the measured corner laws show, where the data give them; and per axle how far a load has pressed
        ride height into the curve (the sag)."""
        def current(v, axle):
            return v.extensions.get(self.name, {}).get(axle, ProgressiveSpring())

        def quadratic(v, share):
            return self.on_every_axle(v, lambda a: dataclasses.replace(
                current(v, a), quadratic=share * v.axle_named(a).suspension_rate / (2 * _REFERENCE_TRAVEL)))

        def cubic(v, share):
            return self.on_every_axle(v, lambda a: dataclasses.replace(
                current(v, a), cubic=share * v.axle_named(a).suspension_rate / (3 * _REFERENCE_TRAVEL**2)))
        def sag(v, depth, axle):
            return self.on_axle(v, axle, dataclasses.replace(current(v, axle), sag=depth))

        start = _shares_from_laws((hints or {}).get("measured_laws"), vehicle) or (0.1, 0.1)
        return [FitParameter("quadratic_share_at_50mm", float(np.clip(start[0], -1.2, 4.0)), -1.2, 4.0, quadratic),
                FitParameter("cubic_share_at_50mm", float(np.clip(start[1], -0.5, 20.0)), -0.5, 20.0, cubic),
                *[FitParameter(f"{a}_sag", 0.0, -0.04, 0.08, lambda v, d, a=a: sag(v, d, a), unit="m")
                  for a in axles_of(vehicle)]]

    def refined_parameters(self, vehicle, hints=None):
        """With the left wheels' sag apart from the right's (a load off the centre line), shared by the axles."""
        plain = self.fit_parameters(vehicle, hints)
        if not vehicle.layout_type.pitches_and_rolls:
            return plain

        def apart(v, difference):
            return self.on_every_axle(v, lambda a: dataclasses.replace(
                v.extensions.get(self.name, {}).get(a, ProgressiveSpring()), sag_left_right=difference))
        return [*plain, FitParameter("sag_left_right", 0.0, -0.03, 0.03, apart, unit="m")]

    def hidden(self, truth, rng):
        share = rng.uniform(0.3, 0.5)  # stiffness 30-50 % up at 25 mm of compression: 2 Kn x = share x K0
        return self.on_every_axle(truth, lambda a: ProgressiveSpring(
            quadratic=share * truth.axle_named(a).suspension_rate / _REFERENCE_TRAVEL))


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
        rate = vehicle.axle_named(axle).suspension_rate
        shares.append((2 * kn * _REFERENCE_TRAVEL / rate, 3 * k3 * _REFERENCE_TRAVEL**2 / rate))
    return tuple(np.mean(shares, axis=0)) if shares else None


CAUSE = _ProgressiveSpring()
