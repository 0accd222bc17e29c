"""``tyre_damping``: the tyre's damping is missing or wrong. It is the ``tyre_damping`` key (N s/m) of
``[front]``/``[rear]``, realised in the baseline tyre actuator (rig/vehicle/mjcf.py)."""

from __future__ import annotations

from rig.causes._base import Cause, FitParameter, ParameterSpec, Shape, axles_of, set_axle


class _TyreDamping(Cause):
    name = "tyre_damping"
    subsystem = "car"
    linear = True
    meaning = "tyre damping missing or wrong"
    signature = "the wheel-hop resonance is lower and wider than the model's"
    evidence = (Shape.TYRE_DAMPING,)

    def has_section(self):
        return False

    def parameters(self):
        return [ParameterSpec("[front]/[rear] tyre_damping", "N s/m", 0.0, 1e4, "tyre damping at the wheel")]

    def present(self, vehicle):
        return any(vehicle.axle_named(a).tyre_damping > 0 for a in axles_of(vehicle))

    def copy(self, source, target):
        for axle in axles_of(target):
            target = set_axle(target, axle, tyre_damping=source.axle_named(axle).tyre_damping)
        return target

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter(f"{a}_tyre_damping", 50.0, 0.0, 2000.0, lambda v, c, a=a: set_axle(v, a, tyre_damping=c),
                             unit="N s/m")
                for a in axles_of(vehicle)]

    def hidden(self, truth, rng):
        for axle in axles_of(truth):
            truth = set_axle(truth, axle, tyre_damping=rng.uniform(200.0, 400.0))
        return truth


CAUSE = _TyreDamping()
