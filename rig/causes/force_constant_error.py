"""``force_constant_error``: an actuator's force constant is off: it applies ``factor`` times the force its record
says (``<corner>/active_force``: a force worked out from the motor current and a data-sheet force constant, or from
a load cell with a wrong calibration). A sensor fault of an input: the record's force is wrong, the motion it caused
is real, so the model must apply the true force to follow it.

    [force_constant_error.front]   # the axle's force actuators
    factor = 0.85                  # force applied over force recorded

Realised as the gain of the force actuators between body and wheel (rig/vehicle/mjcf.py), inside ``mj_step``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import ACTIVE_FORCE, AxleCause, FitParameter, axles_of, param


@dataclass(frozen=True)
class ForceConstant:
    factor: float = field(metadata=param("-", 0.2, 5.0, "force the actuator applies over the force its record says"))


class _ForceConstantError(AxleCause):
    name = "force_constant_error"
    subsystem = "car"  # the actuator sits between body and wheel; the diagnosis fits it by simulation
    needs = ("active_force",)
    values = ForceConstant
    meaning = "an actuator's force constant is off: it applies another force than its record says"
    signature = "the responses to the actuator's force are scaled by one factor, those to the posts are not"

    def build_corner(self, car, corner, value):
        car.actuator(ACTIVE_FORCE.format(corner=corner)).gainprm[0] = value.factor

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter(f"{a}_factor", 1.0, 0.3, 3.0, lambda v, f, a=a: self.on_axle(v, a, ForceConstant(f)),
                             typical=0.1)
                for a in axles_of(vehicle)]

    def hidden(self, truth, rng):
        factor = 1 + rng.choice([-1, 1]) * rng.uniform(0.15, 0.25)
        return self.on_every_axle(truth, lambda a: ForceConstant(factor))


CAUSE = _ForceConstantError()
