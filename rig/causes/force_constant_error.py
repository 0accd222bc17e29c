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

#: a factor this close to 1 is the data sheet's common scale of masses, rates and damping: scaling them all by a scales
#: every response to the force by 1 / a and none to the road, so no record tells the two apart
SCALE_TOLERANCE = 0.05


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

    def indistinct(self, params):
        worst = max(params.values(), key=lambda f: abs(f - 1))
        if abs(worst - 1) > SCALE_TOLERANCE:
            return None
        return (f"a factor of {worst:.3f} is within {SCALE_TOLERANCE:.0%} of 1, where the masses, rates and damping "
                f"scaled together (known to a few percent) change the force's responses alike")

    def hidden(self, truth, rng):
        factor = 1 + rng.choice([-1, 1]) * rng.uniform(0.15, 0.25)
        return self.on_every_axle(truth, lambda a: ForceConstant(factor))


CAUSE = _ForceConstantError()
