"""``mass_error``: the sprung mass, CG and inertia differ from the data sheet (a payload).

    [mass_error]   # payload: kg at (x forward, y left) m from the sprung CG
    mass = 80.0
    x = -0.9
    y = 0.2

Realised in the sprung body's inertial: total mass, shifted CG and the inertia of body and point payload
about the new CG (parallel-axis theorem). The fit starts from the payload the body's measured mass
properties imply, where the data give them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import CarCause, FitParameter, car_scale, param, with_extension


@dataclass(frozen=True)
class MassError:
    mass: float = field(metadata=param("kg", -500.0, 2000.0, "added to the sprung mass (negative: lighter)"))
    x: float = field(default=0.0, metadata=param("m", -3.0, 3.0, "forward of the sprung CG"))
    y: float = field(default=0.0, metadata=param("m", -1.5, 1.5, "left of the sprung CG"))


class _MassError(CarCause):
    name = "mass_error"
    subsystem = "car"
    values = MassError
    order = 5  # the payload's CG shift is taken against the data-sheet mass
    meaning = "sprung mass / CG / inertia differ (e.g. payload)"
    signature = "heave, pitch and roll frequencies shift together; static loads move by the payload's moment"
    evidence = ("sprung mass", "CG x", "CG y", "pitch inertia", "roll inertia")

    def adjust_sprung(self, vehicle, mass, com, inertia):
        payload = vehicle.extensions[self.name]
        total = mass + payload.mass
        offset = np.array([payload.x, payload.y, 0.0])
        com = com + payload.mass * offset / total
        inertia = inertia.copy()
        for point_mass, point in ((payload.mass, offset - com), (mass, -com)):  # both about the new CG
            inertia += point_mass * np.array([point[1] ** 2, point[0] ** 2, point[0] ** 2 + point[1] ** 2])
        return total, com, inertia

    def fit_parameters(self, vehicle, hints=None):
        def setter(key):
            return self.field_setter(key, MassError(0.0, -0.5, 0.0))

        scale = car_scale(vehicle)
        start = _payload_from_body((hints or {}).get("body"), vehicle) or MassError(20.0 * scale, -0.5, 0.0)
        low, high = -200.0 * scale, 400.0 * scale
        mass = [FitParameter("mass", float(np.clip(start.mass, low, high)), low, high, setter("mass"))]
        if vehicle.layout != "full":
            return mass
        return [*mass, FitParameter("x", float(np.clip(start.x, -2.0, 1.5)), -2.0, 1.5, setter("x")),
                FitParameter("y", float(np.clip(start.y, -0.6, 0.6)), -0.6, 0.6, setter("y"))]

    def hidden(self, truth, rng):  # two rear passengers and luggage
        payload = MassError(mass=rng.uniform(120.0, 220.0), x=rng.uniform(-1.3, -0.7), y=rng.uniform(-0.3, 0.3))
        return with_extension(truth, self.name, payload)


def _payload_from_body(body, vehicle) -> MassError | None:
    """The point payload that explains the body's measured mass properties (rig/diagnosis/force_laws.py:
    total mass, CG offset from the data sheet's), when the mass differs by more than 3 %; else None."""
    if body is None:
        return None
    added = body.mass[0] - vehicle.sprung_mass
    if abs(added) < 0.03 * vehicle.sprung_mass:
        return None
    return MassError(added, body.cg_x[0] * body.mass[0] / added, body.cg_y[0] * body.mass[0] / added)


CAUSE = _MassError()
