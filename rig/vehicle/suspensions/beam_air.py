"""``beam_air``: a beam axle on air springs (rig/vehicle/suspensions/beam.py), each F = p A(x) with a polytropic gas
from ``[axles.air_spring]`` (rig/elements/air_spring.py), no level valve: a cubic about the design height (the spring
tendon's polynomial stiffness and a constant-force actuator ``<corner>/air_spring``). The air spring stands at design
height when its pressure carries the static load; a ``parasitic_rate`` (bushings, links) acts in parallel."""

from __future__ import annotations

from rig.elements.air_spring import AirSpring, add_air_spring
from rig.vehicle.suspensions.beam import BeamAxle


class _BeamAir(BeamAxle):
    name = "beam_air"
    law = ("air_spring", AirSpring, True)

    def law_rate(self, law):
        return None if law is None else law.rate  # linearised at design: what a linear model of the axle would use

    def spring(self, car, vehicle, corner, tendon, length):
        axle = vehicle.axle(corner)
        add_air_spring(car, f"{corner}/air_spring", tendon, axle.law, length)
        tendon.stiffness = [tendon.stiffness[0] + axle.parasitic_rate, tendon.stiffness[1], tendon.stiffness[2]]


SUSPENSION = _BeamAir()
