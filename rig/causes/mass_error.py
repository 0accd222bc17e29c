"""``mass_error``: the sprung mass, CG and inertia differ from the data sheet (a payload).

    [mass_error]   # payload: kg at (x forward, y left) m from the sprung CG
    mass = 80.0
    x = -0.9
    y = 0.2
    pitch_inertia = 0.0   # kg m^2, optional: the payload's own inertia about its centre (a load spread out)
    roll_inertia = 0.0

Realised in the sprung body's inertial: total mass, shifted CG and the inertia of body and payload about the
new CG (parallel-axis theorem), with the product of inertia that a payload off both centre lines adds (it couples
pitch and roll; without it, a 180 kg payload 1 m behind and 0.2 m left of the CG missed the exact point mass by a
held-out TDDI of 2.6e-4, three times a 2 % noise floor). The fit starts from the payload the body's measured mass
properties imply, where the data give them, else from what the recalibration's sprung-mass factor took up (hint
``sprung_mass_factor``, beyond 3 %); its refined form adds the payload's own pitch and roll inertia.

A truck's payload is fitted on a truck's scale: its mass from -15 % to +40 % of the sprung mass (a car's bounds,
-200 to 400 kg, are a tenth of a laden truck's load) and where it sits along the frame, within what keeps the loaded
frame's CG where its mass can be spread (rig/elements/frame.py: the middle third of the frame).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import CarCause, FitParameter, Shape, car_scale, with_extension
from rig.elements.parameters import param
from rig.vehicle.truck_mjcf import frame_of


@dataclass(frozen=True)
class MassError:
    mass: float = field(metadata=param("kg", -1e4, 5e4, "added to the sprung mass (negative: lighter)"))
    x: float = field(default=0.0, metadata=param("m", -6.0, 6.0, "forward of the sprung CG"))
    y: float = field(default=0.0, metadata=param("m", -1.5, 1.5, "left of the sprung CG"))
    pitch_inertia: float = field(default=0.0, metadata=param("kg m^2", 0.0, 1e5, "the payload's own, about its centre"))
    roll_inertia: float = field(default=0.0, metadata=param("kg m^2", 0.0, 1e5, "the payload's own, about its centre"))


TRUCK_PAYLOAD = (-0.15, 0.4)  # a truck's payload error: shares of its sprung mass
RIGID_FRAME_REACH = 1.5       # m: how far from the CG a payload on a rigid truck frame is sought


class _MassError(CarCause):
    name = "mass_error"
    subsystem = "car"
    linear = True
    values = MassError
    order = 5  # the payload's CG shift is taken against the data-sheet mass
    meaning = "sprung mass / CG / inertia differ (e.g. payload)"
    signature = "heave, pitch and roll frequencies shift together; static loads move by the payload's moment"
    owns = ("sprung_mass",)  # the body's mass is the payload's, not the recalibration's, where this is named
    evidence = (Shape.SPRUNG_MASS, Shape.CG_X, Shape.CG_Y, Shape.PITCH_INERTIA, Shape.ROLL_INERTIA)

    def adjust_sprung(self, vehicle, mass, com, inertia):
        payload = vehicle.extensions[self.name]
        total = mass + payload.mass
        offset = np.array([payload.x, payload.y, 0.0])
        com = com + payload.mass * offset / total
        inertia = inertia.copy()
        for point_mass, point in ((payload.mass, offset - com), (mass, -com)):  # both about the new CG
            inertia += point_mass * np.array([point[1] ** 2, point[0] ** 2, point[0] ** 2 + point[1] ** 2])
        inertia += [payload.roll_inertia, payload.pitch_inertia, payload.roll_inertia + payload.pitch_inertia]
        return total, com, inertia

    def fit_parameters(self, vehicle, hints=None):
        behind = -0.5 if vehicle.layout_type.pitches_and_rolls else 0.0  # no pitch or roll to place it behind

        def setter(key):
            return self.field_setter(key, MassError(0.0, behind, 0.0))

        if vehicle.layout_type.axle_list:
            return _truck_payload(vehicle, setter, _payload_from_body((hints or {}).get("body"), vehicle))
        scale = car_scale(vehicle)
        hints = hints or {}
        recalibrated = (hints.get("sprung_mass_factor", 1.0) - 1) * vehicle.sprung_mass  # what the recalibration took
        start = _payload_from_body(hints.get("body"), vehicle) or MassError(
            recalibrated if abs(recalibrated) >= 0.03 * vehicle.sprung_mass else 20.0 * scale, behind, 0.0)
        low, high = -200.0 * scale, 400.0 * scale
        mass = [FitParameter("mass", float(np.clip(start.mass, low, high)), low, high, setter("mass"),
                             unit="kg")]
        if not vehicle.layout_type.pitches_and_rolls:
            return mass
        return [*mass, FitParameter("x", float(np.clip(start.x, -2.0, 1.5)), -2.0, 1.5, setter("x"), unit="m"),
                FitParameter("y", float(np.clip(start.y, -0.6, 0.6)), -0.6, 0.6, setter("y"), unit="m")]

    def build(self, car, vehicle):
        """The product of inertia about the body's CG (set from ``adjust_sprung``) of the payload and the rest of the
        sprung body, taken at the data sheet's CG."""
        payload = vehicle.extensions[self.name]
        body = car.body("body")
        cg = np.array(body.ipos)
        rest = body.mass - payload.mass
        product = -(payload.mass * (payload.x - cg[0]) * (payload.y - cg[1]) + rest * cg[0] * cg[1])
        principal = np.array(body.inertia).tolist()
        body.inertia = [0.0, 0.0, 0.0]  # unset: the full tensor replaces the diagonal one
        body.fullinertia = [*principal, product, 0.0, 0.0]

    def refined_parameters(self, vehicle, hints=None):
        plain = self.fit_parameters(vehicle, hints)
        if not vehicle.layout_type.pitches_and_rolls:
            return plain
        setter = self.field_setter
        return [*plain, FitParameter("pitch_inertia", 20.0, 0.0, 400.0, setter("pitch_inertia", MassError(0.0)),
                                     unit="kg m^2"),
                FitParameter("roll_inertia", 10.0, 0.0, 200.0, setter("roll_inertia", MassError(0.0)), unit="kg m^2")]

    def hidden(self, truth, rng):  # two rear passengers and luggage; a truck's load a tonne or more off
        if truth.layout_type.axle_list:
            low, high = _payload_x_bounds(truth)
            payload = MassError(mass=rng.uniform(0.1, 0.3) * truth.sprung_mass, x=rng.uniform(0.6 * low, 0.6 * high))
        else:
            payload = MassError(mass=rng.uniform(120.0, 220.0), x=rng.uniform(-1.3, -0.7), y=rng.uniform(-0.3, 0.3))
        return with_extension(truth, self.name, payload)


def _truck_payload(vehicle, setter, measured: MassError | None) -> list[FitParameter]:
    """A truck's payload: its mass and where it sits along the frame (TRUCK_PAYLOAD, ``_payload_x_bounds``), started
    from the body's measured mass properties where the data give them."""
    low, high = (share * vehicle.sprung_mass for share in TRUCK_PAYLOAD)
    x_low, x_high = _payload_x_bounds(vehicle)
    start = measured or MassError(0.05 * vehicle.sprung_mass, 0.0, 0.0)
    return [FitParameter("mass", float(np.clip(start.mass, low, high)), low, high, setter("mass"),
                         typical=0.1 * vehicle.sprung_mass, unit="kg"),
            FitParameter("x", float(np.clip(start.x, x_low, x_high)), x_low, x_high, setter("x"), typical=0.5,
                         unit="m")]


def _payload_x_bounds(vehicle) -> tuple[float, float]:
    """Where along a truck's frame (m forward of the sprung CG) a payload within TRUCK_PAYLOAD keeps the loaded CG
    where the frame's mass can be spread: inside the frame's middle third, with a tenth of it to spare (a rigid frame:
    RIGID_FRAME_REACH either way)."""
    frame = frame_of(vehicle)  # the frame as the vehicle's causes give it (a flexible frame's): length, front_overhang
    if frame is None:
        return -RIGID_FRAME_REACH, RIGID_FRAME_REACH
    middle = vehicle.cg_to_front_axle + frame.front_overhang - frame.length / 2  # from the CG, forward
    ahead, behind = middle + 0.9 * frame.length / 6, middle - 0.9 * frame.length / 6  # the CG may move this far
    m = vehicle.sprung_mass
    lighter, heavier = (share * m for share in TRUCK_PAYLOAD)
    # the CG moves by dm x / (m + dm): forward for a heavier load ahead or a lighter one behind, and so on
    high = min(ahead * (m + heavier) / heavier, behind * (m + lighter) / lighter)
    low = max(ahead * (m + lighter) / lighter, behind * (m + heavier) / heavier)
    return float(low), float(high)


def _payload_from_body(body, vehicle) -> MassError | None:
    """The point payload that explains the body's measured mass properties (rig/diagnosis/rig_test/force_laws.py:
    total mass, CG offset from the data sheet's), when the mass differs by more than 3 %; else None."""
    if body is None:
        return None
    added = body.mass[0] - vehicle.sprung_mass
    if abs(added) < 0.03 * vehicle.sprung_mass:
        return None
    return MassError(added, body.cg_x[0] * body.mass[0] / added, body.cg_y[0] * body.mass[0] / added)


CAUSE = _MassError()
