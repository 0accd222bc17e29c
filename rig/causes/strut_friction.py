"""``strut_friction``: Coulomb (dry) friction in the strut.

    [strut_friction.front]   # N, friction force of the strut
    force = 120.0

Realised as friction loss on the suspension tendon with a stiff impedance (MuJoCo's default lets it creep).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, axles_of, param


@dataclass(frozen=True)
class StrutFriction:
    force: float = field(metadata=param("N", 0.0, 5e3, "Coulomb friction force of the strut"))


class _StrutFriction(AxleCause):
    name = "strut_friction"
    subsystem = "car"
    values = StrutFriction
    meaning = "Coulomb (dry) friction in the strut"
    signature = "a step in the residual at zero travel velocity; the suspension sticks at small amplitudes"
    evidence = ("friction step",)

    def build_corner(self, car, corner, friction):
        spring = car.tendon(f"{corner}/suspension")
        spring.frictionloss = friction.force
        spring.solimp_friction = [0.9999, 0.9999, 0.001, 0.5, 2.0]

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter(f"{a}_force", 30.0, 0.0, 800.0, lambda v, f, a=a: self.on_axle(v, a, StrutFriction(f)))
                for a in axles_of(vehicle)]

    def hidden(self, truth, rng):
        return self.on_every_axle(truth, lambda a: StrutFriction(rng.uniform(150.0, 300.0)))


CAUSE = _StrutFriction()
