"""``secondary_mass``: an unmodelled subsystem (engine, battery pack, cab, spare wheel) resonating on its
mounts: part of the sprung mass on a vertical spring and damper at a point of the body.

    [secondary_mass]      # kg taken from the sprung mass at (x forward, y left) m from the sprung CG
    mass = 150.0
    x = 1.2
    y = 0.0
    frequency = 11.0      # Hz, natural frequency of the mass on its mounts
    damping_ratio = 0.08

Realised as a body on a vertical slide joint of the sprung body (stiffness m (2 pi f)^2, damping
2 zeta m 2 pi f); the sprung body loses the point mass (parallel-axis theorem), so the total mass, CG and
static loads stay those of the data sheet. The generic resonator the diagnosis fits where the residual
shows a resonance no other cause explains; its initial frequency is the residual's peak.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import CarCause, FitParameter, car_scale, with_extension
from rig.elements.parameters import param


@dataclass(frozen=True)
class SecondaryMass:
    mass: float = field(metadata=param("kg", 0.01, 1000.0, "taken from the sprung mass onto its own mounts"))
    frequency: float = field(metadata=param("Hz", 1.0, 60.0, "natural frequency on the mounts"))
    damping_ratio: float = field(default=0.1, metadata=param("-", 0.005, 1.0, "damping ratio of the mounts"))
    x: float = field(default=0.0, metadata=param("m", -3.0, 3.0, "forward of the sprung CG"))
    y: float = field(default=0.0, metadata=param("m", -1.5, 1.5, "left of the sprung CG"))


def _point_inertia(mass: float, offset: np.ndarray) -> np.ndarray:
    """Principal inertia (roll, pitch, yaw) of a point mass at ``offset`` (x, y, z) m."""
    return mass * np.array([offset[1] ** 2, offset[0] ** 2, offset[0] ** 2 + offset[1] ** 2])


class _SecondaryMass(CarCause):
    name = "secondary_mass"
    subsystem = "car"
    linear = True
    values = SecondaryMass
    order = 6  # after a payload, which is taken against the data-sheet mass
    meaning = "an unmodelled subsystem (engine, battery, cab) resonating on its mounts"
    signature = "a resonance of the residual body acceleration at the mount frequency, strongest near the mass"

    def adjust_sprung(self, vehicle, mass, com, inertia):
        sub = vehicle.extensions[self.name]
        point = np.array([sub.x, sub.y, 0.0])
        rest = mass - sub.mass
        new_com = (mass * com - sub.mass * point) / rest
        about_com = inertia - _point_inertia(sub.mass, point - com)
        return rest, new_com, about_com - _point_inertia(rest, new_com - com)

    def build(self, car, vehicle):
        import mujoco

        sub = vehicle.extensions[self.name]
        omega = 2 * math.pi * sub.frequency
        body = car.body("body").add_body(name="secondary_mass", pos=[sub.x, sub.y, 0.0])
        body.add_joint(name="secondary_mass", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1],
                       stiffness=sub.mass * omega**2, damping=2 * sub.damping_ratio * sub.mass * omega)
        body.mass, body.ipos, body.inertia, body.explicitinertial = sub.mass, [0, 0, 0], [1e-3] * 3, True

    def fit_parameters(self, vehicle, hints=None):
        peak = (hints or {}).get("peak_hz") or 12.0

        scale = car_scale(vehicle)

        def setter(key):
            return self.field_setter(key, SecondaryMass(mass=50.0 * scale, frequency=peak))

        heaviest = min(400.0 * scale, 0.5 * vehicle.sprung_mass)  # of the body it is taken from, at most half
        params = [FitParameter("mass", 50.0 * scale, 5.0 * scale, heaviest, setter("mass"), unit="kg"),
                  FitParameter("frequency", float(np.clip(peak, 3.0, 40.0)), 2.0, 45.0, setter("frequency"),
                            unit="Hz"),
                  FitParameter("damping_ratio", 0.1, 0.02, 0.6, setter("damping_ratio"))]
        if not vehicle.layout_type.pitches_and_rolls:
            return params
        return [*params, FitParameter("x", 0.0, -2.0, 2.0, setter("x"), unit="m"),
                FitParameter("y", 0.0, -0.8, 0.8, setter("y"), unit="m")]

    def hidden(self, truth, rng):  # an engine on its mounts, ahead of the CG
        return with_extension(truth, self.name, SecondaryMass(
            mass=rng.uniform(100.0, 200.0), frequency=rng.uniform(9.0, 14.0), damping_ratio=rng.uniform(0.05, 0.12),
            x=rng.uniform(1.0, 1.5), y=rng.uniform(-0.1, 0.1)))


CAUSE = _SecondaryMass()
