"""``bearing_friction``: a lab bench's linear bearings rub: its body and wheel plates slide along guides fixed to the
ground, and each bearing's friction acts on its plate's own motion (not, as a strut's, on the travel between them).

    [bearing_friction]   # layout "quarter": a bench
    body = 0.6           # N, the body plate's bearing
    wheel = 0.0          # N, the wheel plate's bearing (optional)
    velocity = 0.0       # m/s, optional: viscous below this rate (0: ideal Coulomb friction)

Ideal Coulomb friction (``velocity`` 0) is friction loss on the body's heave joint and on the wheel's slide joint,
with a stiff impedance and the shortest time constant MuJoCo allows (twice the physics step): with the default
0.02 s the plates crept while they should stick, and the bench's displacements missed those of an independent
solver of the same Coulomb law by 7.8 % RMS (0.8 % with it; tests/lab_rig.py). A smooth law (a bearing that creeps
below a break-away rate) is a saturated damper, F = clip(force x rate / velocity, -force, force): an affine actuator
on the joint clamped to the friction force, its slope kept within what RK4 resolves on the plate at the physics step
(``MAX_SLOPE_STEPS``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco

from rig.causes._base import CarCause, FitParameter, with_extension
from rig.elements.parameters import param
from rig.elements.tendons import rate_damper
from rig.causes.strut_friction import MAX_SLOPE_STEPS, PHYSICS_STEP  # the same RK4 limit, on a plate's mass
from rig.io.units import STANDARD_GRAVITY

_IMPEDANCE = [0.9999, 0.9999, 0.001, 0.5, 2.0]
_TIME_CONSTANT = [2 * PHYSICS_STEP, 1.0]  # s, damping ratio: MuJoCo raises it to twice a finer step by itself


@dataclass(frozen=True)
class BearingFriction:
    body: float = field(metadata=param("N", 0.0, 1e4, "friction force of the body plate's bearing"))
    wheel: float = field(default=0.0, metadata=param("N", 0.0, 1e4, "friction force of the wheel plate's bearing"))
    velocity: float = field(default=0.0, metadata=param("m/s", 0.0, 1.0,
                                                        "viscous below this rate (0: ideal Coulomb friction)"))


class _BearingFriction(CarCause):
    name = "bearing_friction"
    subsystem = "car"
    layouts = ("quarter",)
    values = BearingFriction
    meaning = "a lab bench's linear bearings rub: friction on the body's and the wheel's own motion"
    signature = "the body sticks where it turns and at small amplitudes, whatever the travel does"
    fine_step = True  # the smooth law's slope is sized to the physics step

    def check(self, vehicle):
        super().check(vehicle)
        if vehicle.front.kinematics is not None:
            raise ValueError(f"{vehicle.source}: [bearing_friction] needs the plates on vertical guides (no "
                             f"[front.kinematics])")

    def build(self, car, vehicle):
        friction = vehicle.extensions[self.name]
        for joint, force, mass in (("heave", friction.body, vehicle.sprung_mass),
                                   ("FL/wheel", friction.wheel, vehicle.front.unsprung_mass)):
            if force <= 0:
                continue
            if friction.velocity > 0:
                _saturated_damper(car, joint, force, min(force / friction.velocity,
                                                         MAX_SLOPE_STEPS * mass / PHYSICS_STEP))
            else:
                car.joint(joint).frictionloss = force
                car.joint(joint).solimp_friction = _IMPEDANCE
                car.joint(joint).solref_friction = _TIME_CONSTANT

    def fit_parameters(self, vehicle, hints=None):
        if vehicle.layout not in self.layouts:
            return []
        start = vehicle.extensions.get(self.name, BearingFriction(0.0))
        body_weight = vehicle.sprung_mass * STANDARD_GRAVITY
        weight = body_weight + vehicle.front.unsprung_mass * STANDARD_GRAVITY
        return [FitParameter("body", 0.02 * body_weight, 0.0, 0.3 * body_weight, self.field_setter("body", start),
                             unit="N"),
                FitParameter("wheel", 0.02 * weight, 0.0, 0.3 * weight, self.field_setter("wheel", start),
                             unit="N")]

    def hidden(self, truth, rng):
        if truth.layout not in self.layouts:
            raise ValueError(f"{truth.name}: bearing friction is a lab bench's (layout quarter)")
        body = rng.uniform(0.02, 0.04) * truth.sprung_mass * STANDARD_GRAVITY
        return with_extension(truth, self.name, BearingFriction(body))


def _saturated_damper(car: mujoco.MjSpec, joint: str, force: float, slope: float) -> None:
    """F = -slope x the joint's rate, clamped to +-force: an affine actuator on the joint."""
    rate_damper(car, f"{joint}/bearing_friction", joint, slope, [-force, force], on_joint=True)


CAUSE = _BearingFriction()
