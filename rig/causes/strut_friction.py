"""``strut_friction``: dry friction in the strut, Coulomb or smooth.

    [strut_friction.front]   # N, friction force of the strut
    force = 120.0
    velocity = 0.01          # m/s, optional: the rate below which the friction is viscous (0: ideal Coulomb)

Ideal Coulomb friction (``velocity`` 0) is friction loss on the suspension tendon with a stiff impedance
(MuJoCo's default lets it creep). A smooth law (a seal's friction, which creeps below a break-away rate) is a
saturated damper: F = clip(force x rate / velocity, -force, force), an affine actuator on the tendon clamped to
the friction force, inside ``mj_step``. Its viscous slope is kept within what RK4 resolves on the wheel at the
physics step (``MAX_SLOPE_STEPS``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, axles_of
from rig.elements.parameters import param
from rig.elements.tendons import PHYSICS_STEP, rate_damper

#: the smooth law's viscous slope at most this many unsprung masses per physics step (RK4 is stable to 2.8)
MAX_SLOPE_STEPS = 1.5


@dataclass(frozen=True)
class StrutFriction:
    force: float = field(metadata=param("N", 0.0, 5e3, "friction force of the strut"))
    velocity: float = field(default=0.0, metadata=param("m/s", 0.0, 1.0,
                                                        "viscous below this rate (0: ideal Coulomb friction)"))


class _StrutFriction(AxleCause):
    name = "strut_friction"
    damper_line = "mount"
    damper_part = "friction"
    subsystem = "car"
    layouts = ("full", "quarter")  # a truck's beam axles have no strut: their friction is leaf_friction's
    values = StrutFriction
    meaning = "Coulomb (dry) friction in the strut"
    signature = "a step in the residual at zero travel velocity; the suspension sticks at small amplitudes"
    evidence = (Shape.FRICTION_STEP,)
    fine_step = True  # the smooth law's slope is sized to the physics step

    def build(self, car, vehicle):
        for corner in vehicle.corners:
            friction = self.at(vehicle, corner)
            if friction is None or friction.force == 0:  # no friction: nothing to realise (a fit at its bound)
                continue
            if friction.velocity > 0:
                _smooth(car, corner, friction, vehicle.axle(corner).unsprung_mass)
            else:
                spring = car.tendon(f"{corner}/suspension")
                spring.frictionloss = friction.force
                spring.solimp_friction = [0.9999, 0.9999, 0.001, 0.5, 2.0]

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter(f"{a}_force", 30.0, 0.0, 800.0, lambda v, f, a=a: self._with(v, a, force=f), unit="N")
                for a in axles_of(vehicle)]

    def refined_parameters(self, vehicle, hints=None):
        """The smooth law: each axle's force and one break-away rate shared by the axles."""
        def shared(v, rate):
            for axle in axles_of(v):
                v = self._with(v, axle, velocity=rate)
            return v
        return [*self.fit_parameters(vehicle, hints),
                FitParameter("velocity", 0.01, 0.002, 0.1, shared, unit="m/s")]

    def _with(self, vehicle, axle, **values):
        current = vehicle.extensions.get(self.name, {}).get(axle, StrutFriction(0.0))
        return self.on_axle(vehicle, axle, StrutFriction(**{"force": current.force, "velocity": current.velocity,
                                                             **values}))

    def hidden(self, truth, rng):
        return self.on_every_axle(truth, lambda a: StrutFriction(rng.uniform(150.0, 300.0)))


def _smooth(car, corner: str, friction: StrutFriction, unsprung_mass: float) -> None:
    """The saturated damper on the suspension tendon: F = -slope x rate, clamped to +-force."""
    slope = min(friction.force / friction.velocity, MAX_SLOPE_STEPS * unsprung_mass / PHYSICS_STEP)
    rate_damper(car, f"{corner}/strut_friction", f"{corner}/suspension", slope, [-friction.force, friction.force])


CAUSE = _StrutFriction()
