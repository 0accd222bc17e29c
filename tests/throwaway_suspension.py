"""A throwaway suspension type with a parameter of its own, one module and nothing else (tests/test_registries.py
registers it): ``beam_coil``, a truck's beam axle on coil springs whose rate is given in the axle's own sub-table
``[axles.coil_spring]`` rather than as its ``spring_rate``."""

from dataclasses import dataclass, field

from rig.elements.parameters import param
from rig.vehicle.suspensions.beam import BeamAxle


@dataclass(frozen=True)
class CoilSpring:
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "each coil's rate"))


class _BeamCoil(BeamAxle):
    name = "beam_coil"
    law = ("coil_spring", CoilSpring, True)

    def law_rate(self, law):
        return law.rate

    def spring(self, car, vehicle, corner, tendon, length):
        axle = vehicle.axle(corner)
        tendon.stiffness = [axle.law.rate + axle.parasitic_rate, 0.0, 0.0]
        tendon.springlength = [length, length]  # drawn unloaded: the static solve presses the spring


SUSPENSION = _BeamCoil()
