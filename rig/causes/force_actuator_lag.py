"""``force_actuator_lag``: the force actuator between body and wheel lags its record: a first-order lag of bandwidth
``bandwidth`` (Hz, its -3 dB point) after a transport delay ``delay`` (s), as a current loop, an amplifier or a valve
make it; the record holds the force asked for (or measured where it is not applied).

    [force_actuator_lag.front]
    bandwidth = 15.0   # Hz
    delay = 0.004      # s

Realised inside ``mj_step`` on the force actuators (rig/vehicle/mjcf.py): MuJoCo's ``filter`` dynamics (tau = 1 /
(2 pi bandwidth), integrated with the rest of the state) and its control delay, which the input's own late reading
is added to.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import mujoco

from rig.causes._base import AxleCause, FitParameter, axles_of
from rig.elements.parameters import param
from rig.vehicle.mjcf import ACTIVE_FORCE
from rig.vehicle.mjcf import LONGEST_FORCE_DELAY as LONGEST_DELAY


@dataclass(frozen=True)
class ForceActuatorLag:
    bandwidth: float = field(metadata=param("Hz", 0.5, 500.0, "-3 dB point of the force's first-order lag"))
    delay: float = field(default=0.0, metadata=param("s", 0.0, LONGEST_DELAY, "transport delay before the lag"))


class _ForceActuatorLag(AxleCause):
    name = "force_actuator_lag"
    subsystem = "car"  # the actuator sits between body and wheel; the diagnosis fits it by simulation
    needs = ("active_force",)
    values = ForceActuatorLag
    meaning = "the force actuator between body and wheel lags its record (bandwidth, delay)"
    signature = "the responses to the actuator's force lag and fall increasingly with frequency"

    def build_corner(self, car, corner, value):
        actuator = car.actuator(ACTIVE_FORCE.format(corner=corner))
        actuator.dyntype = mujoco.mjtDyn.mjDYN_FILTER
        actuator.dynprm[0] = 1.0 / (2 * math.pi * value.bandwidth)
        actuator.delay = value.delay

    def fit_parameters(self, vehicle, hints=None):
        def setter(axle, key):
            def apply(v, value):
                current = v.extensions.get(self.name, {}).get(axle, ForceActuatorLag(50.0, 0.0))
                return self.on_axle(v, axle, dataclasses.replace(current, **{key: value}))
            return apply

        return [parameter for a in axles_of(vehicle) for parameter in (
            FitParameter(f"{a}_bandwidth", 50.0, 2.0, 200.0, setter(a, "bandwidth"), typical=10.0, unit="Hz"),
            FitParameter(f"{a}_delay", 0.001, 0.0, 0.03, setter(a, "delay"), typical=0.002, unit="s"))]

    def hidden(self, truth, rng):
        lag = ForceActuatorLag(rng.uniform(6.0, 12.0), rng.uniform(0.003, 0.008))
        return self.on_every_axle(truth, lambda a: lag)


CAUSE = _ForceActuatorLag()
