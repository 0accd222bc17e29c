"""``air_spring_law``: an axle's springs follow another air-spring law than modelled (or are air springs where the
model has linear ones): F = p A(x), p V^n constant (rig/elements/air_spring.py).

    [air_spring_law.rear]
    area = 0.07              # m^2, effective area at design height
    volume = 0.03            # m^3, gas volume at design height
    pressure = 5.5e5         # Pa gauge at design height
    polytropic_index = 1.4   # 1 (isothermal) .. 1.4 (adiabatic)
    area_slope = 0.03        # m^2/m

Realised on the axle's spring tendons (``<corner>/suspension``) as ``beam_air`` realises its springs (a cubic about
the design height and a constant-force actuator ``<corner>/air_spring``), in place of the tendon's own stiffness and
any air spring already there. Trucks' beam axles only.

The diagnosis fits each axle's volume, the polytropic index and the pressure at design height held at the model's. A
rig test's travel determines the spring's rate about its static height, n (p + p_atm) A^2 / V there, and hardly its
curvature, (n + 1) A / V: with both the volume and the index free, a tandem hidden at 0.0283 m^3 and n = 1.12
(the model's 0.040 and 1.4) was fitted at 0.0356 and 1.40, the same rate within 1 % and the same held-out TDDI, 26 %
off in volume. And at a given load the pressure at design height and the volume are one parameter: the static solve
puts the spring where its gas carries the load, p_eq = W / A, and the gas's content (p + p_atm) V^n sets the volume
there; a pressure off by a share shows as the volume that holds the same gas at the model's pressure,
V ((p' + p_atm) / (p + p_atm))^(1/n) (with an area slope, nearly). So a hidden instance is a volume other than the
model's, as a bellows' reservoir or an extra tank makes it.
"""

from __future__ import annotations

import dataclasses

from rig.causes._base import AxleCause, FitParameter, Shape
from rig.elements.air_spring import AirSpring, add_air_spring
from rig.vehicle.suspensions import suspensions
from rig.vehicle.suspensions.beam import BeamAxle

ACTUATOR = "{corner}/air_spring"


def beam_axles(vehicle) -> tuple[str, ...]:
    """The vehicle's beam axles."""
    return tuple(n for n, a in zip(vehicle.axle_names, vehicle.axles)
                 if a.suspension and isinstance(suspensions()[a.suspension], BeamAxle))


class _AirSpringLaw(AxleCause):
    name = "air_spring_law"
    subsystem = "car"
    layouts = ("truck",)
    values = AirSpring
    meaning = "an axle's air springs follow another gas law than modelled (volume, polytropic index, pressure)"
    signature = "the spring force grows progressively with compression: the residual follows travel squared"
    evidence = (Shape.STIFFENS_IN_COMPRESSION, Shape.SOFTENS_IN_REBOUND)

    def check(self, vehicle):
        super().check(vehicle)
        wrong = sorted(set(vehicle.extensions[self.name]) - set(beam_axles(vehicle)))
        if wrong:
            raise ValueError(f"{vehicle.source}: [air_spring_law] {', '.join(wrong)}: not a beam axle "
                             f"(the beam axles: {', '.join(beam_axles(vehicle)) or 'none'})")

    def build(self, car, vehicle):
        for corner in vehicle.corners:
            spring = self.at(vehicle, corner)
            if spring is None:
                continue
            existing = car.actuator(ACTUATOR.format(corner=corner))
            if existing is not None:
                car.delete(existing)
            tendon = car.tendon(f"{corner}/suspension")  # a beam axle's: its reference is the design length
            add_air_spring(car, ACTUATOR.format(corner=corner), tendon, spring, float(tendon.springlength[0]))

    def fit_parameters(self, vehicle, hints=None):
        def current(axle):
            law = vehicle.extensions.get(self.name, {}).get(axle) or vehicle.axle_named(axle).law
            return law if isinstance(law, AirSpring) else None

        def setter(axle, key):  # on the law as the vehicle being built has it (a fit sets its parameters in turn)
            def apply(v, x):
                law = v.extensions.get(self.name, {}).get(axle) or v.axle_named(axle).law
                return self.on_axle(v, axle, dataclasses.replace(law, **{key: x}))
            return apply

        return [FitParameter(f"{a}_volume", current(a).volume, 0.005, 0.2, setter(a, "volume"), typical=0.02,
                             unit="m^3") for a in beam_axles(vehicle) if current(a) is not None]

    def hidden(self, truth, rng):
        axles = [a for a in beam_axles(truth) if isinstance(truth.axle_named(a).law, AirSpring)]
        if not axles:
            raise ValueError(f"{truth.name} has no air-spring axle whose law could differ")
        share = rng.uniform(0.55, 0.75)
        return self.on_every_axle(truth, lambda a: dataclasses.replace(
            truth.axle_named(a).law, volume=share * truth.axle_named(a).law.volume), axles)


CAUSE = _AirSpringLaw()
