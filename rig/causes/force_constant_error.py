"""``force_constant_error``: an actuator's force constant is off: it applies ``factor`` times the force its record
says (``<corner>/active_force``: a force worked out from the motor current and a data-sheet force constant, or from
a load cell with a wrong calibration); a negative factor is a force channel whose polarity is reversed. A sensor
fault of an input: the record's force is wrong, the motion it caused is real, so the model must apply the true force
to follow it.

    [force_constant_error.front]   # the axle's force actuators
    factor = 0.85                  # force applied over force recorded (size 0.2..5; negative: polarity reversed)

Realised as the gain of the force actuators between body and wheel (rig/vehicle/mjcf.py), inside ``mj_step``. The
fit starts from the records' own evidence where it is clear (rig/diagnosis/rig_test/input_chain.py): a force reversed,
or off
by more than a factor of three, starts there, on its side of zero; else from 1, as the chain's size of a force's gain is
only as good as the data sheet's resonances (a lightly damped bench 3 % off its data sheet moved it to 1.22 on a
bench whose force was right), while its sign is not.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import AxleCause, axles_of, refuse_factor
from rig.elements.parameters import param
from rig.vehicle.mjcf import ACTIVE_FORCE
from rig.causes.input_gain import signed_factor
from rig.io.channels import corner_axle, split_channel

#: a factor this close to 1 is the data sheet's common scale of masses, rates and damping: scaling them all by a scales
#: every response to the force by 1 / a and none to the road, so no record tells the two apart
SCALE_TOLERANCE = 0.05


@dataclass(frozen=True)
class ForceConstant:
    factor: float = field(metadata=param("-", -5.0, 5.0, "force the actuator applies over the force its record says "
                                                          "(size 0.2..5; negative: polarity reversed)"))


class _ForceConstantError(AxleCause):
    name = "force_constant_error"
    subsystem = "car"  # the actuator sits between body and wheel; the diagnosis fits it by simulation
    needs = ("active_force",)
    input_quantities = ("active_force",)
    values = ForceConstant
    meaning = "an actuator's force constant is off: it applies another force than its record says"
    signature = "the responses to the actuator's force are scaled by one factor, those to the posts are not"
    separated_by = "a run with the force actuator off, or a static push of known force read on its channel"

    def parse(self, section, where, axles):
        value = super().parse(section, where, axles)
        for axle, constant in value.items():
            refuse_factor(constant.factor, f"{where}: [{self.name}.{axle}] factor")
        return value

    def build_corner(self, car, corner, value):
        car.actuator(ACTIVE_FORCE.format(corner=corner)).gainprm[0] = value.factor

    def fit_parameters(self, vehicle, hints=None):
        """Each axle's factor, started as the module docstring says (hints ``input_gains``: channel -> the input
        chain's gain; ``gross_inputs``: the channels it found reversed or off by more than threefold)."""
        gains, gross = (hints or {}).get("input_gains", {}), (hints or {}).get("gross_inputs", ())
        params = []
        for a in axles_of(vehicle):
            found = [g for n, g in gains.items() if n in gross and split_channel(n)[1] == "active_force"
                     and corner_axle(split_channel(n)[0]) == a]
            start = float(np.mean(found)) if found else 1.0
            params.append(signed_factor(f"{a}_factor", start, lambda v, f, a=a: self.on_axle(v, a, ForceConstant(f)),
                                        typical=0.1))
        return params

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
