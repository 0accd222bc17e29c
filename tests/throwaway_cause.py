"""A throwaway cause, one module and nothing else (tests/test_registries.py registers it): ``ballast``, a mass
carried at the sprung body's CG, in a section of its own:

    [ballast]
    mass = 50.0   # kg
"""

from dataclasses import dataclass, field

from rig.causes import CarCause
from rig.elements.parameters import param


@dataclass(frozen=True)
class Ballast:
    mass: float = field(metadata=param("kg", 0.0, 1e4, "carried at the sprung body's CG"))


class _Ballast(CarCause):
    name = "ballast"
    subsystem = "car"
    values = Ballast
    meaning = "the body carries a mass at its CG"
    signature = "heave frequency falls; static loads rise alike at every wheel"

    def adjust_sprung(self, vehicle, mass, com, inertia):
        added = vehicle.extensions[self.name].mass
        return mass + added, com * mass / (mass + added), inertia


CAUSE = _Ballast()
