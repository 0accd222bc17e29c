"""``actuator_lag``: the post dynamics differ: the achieved displacement lags the drive. It is the ``[rig]``
keys ``servo_bandwidth`` (Hz) and ``servo_delay`` (s) of the post servo model (rig/vehicle/rig_config.py)."""

from __future__ import annotations

import dataclasses

from rig.causes._base import Cause, FitParameter, ParameterSpec


def _with_servo(vehicle, **values):
    return dataclasses.replace(vehicle, rig=dataclasses.replace(vehicle.rig, **values))


class _ActuatorLag(Cause):
    name = "actuator_lag"
    subsystem = "rig"
    meaning = "post dynamics: achieved displacement lags the drive (bandwidth, delay)"
    signature = "achieved post displacement lags the drive increasingly with frequency"

    def has_section(self):
        return False

    def parameters(self):
        return [ParameterSpec("[rig] servo_bandwidth", "Hz", 2.0, 200.0, "-3 dB of the post's command lag"),
                ParameterSpec("[rig] servo_delay", "s", 0.0, 0.05, "transport delay of valve and controller")]

    def present(self, vehicle):
        defaults = type(vehicle.rig)()
        return ((vehicle.rig.servo_bandwidth, vehicle.rig.servo_delay)
                != (defaults.servo_bandwidth, defaults.servo_delay))

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter("servo_bandwidth", vehicle.rig.servo_bandwidth, 2.0, 200.0,
                             lambda v, f: _with_servo(v, servo_bandwidth=f), typical=10.0, relative_step=0.02,
                             unit="Hz"),
                FitParameter("servo_delay", vehicle.rig.servo_delay, 0.0, 0.05,
                             lambda v, d: _with_servo(v, servo_delay=d), typical=0.002, relative_step=0.05, unit="s")]

    def copy(self, source, target):
        return _with_servo(target, servo_bandwidth=source.rig.servo_bandwidth, servo_delay=source.rig.servo_delay)

    def hidden(self, truth, rng):
        return _with_servo(truth, servo_bandwidth=rng.uniform(12.0, 20.0), servo_delay=rng.uniform(0.005, 0.009))


CAUSE = _ActuatorLag()
