"""``cab_air_spring``: a truck cab's air springs follow another law than modelled (their volume: bellows and
reservoir), or the cab stands on air springs where the model has linear mounts: F = p A(x), p V^n constant
(rig/elements/air_spring.py), as Forsén models the cab's suspension.

    [cab_air_spring]         # each of the cab's four springs
    area = 0.012             # m^2, effective area at design height
    volume = 0.002           # m^3, gas volume at design height
    pressure = 2.66e5        # Pa gauge at design height
    polytropic_index = 1.4
    area_slope = 0.0         # m^2/m

Realised on the cab's mount tendons (``cab/<mount>_mount``) as ``[cab.air_spring]`` is (a cubic fitted over +-40 mm
about the design height and a constant-force actuator ``cab/<mount>_air_spring``), in place of the mounts' own
springs. The diagnosis fits the volume: on a rig test the gas's content (p + p_atm) V^n at the cab's load is what the
data fix, the pressure at design height being the load's (a cab's levelling valve sets it). Trucks with a cab only.
"""

from __future__ import annotations

import dataclasses

from rig.elements.air_spring import MountAirSpring, add_air_spring
from rig.causes._base import CarCause, FitParameter, with_extension


class _CabAirSpring(CarCause):
    name = "cab_air_spring"
    subsystem = "car"
    layouts = ("truck",)
    values = MountAirSpring
    meaning = "the cab's air springs follow another gas law than modelled (their volume), or the cab stands on air " \
              "springs where the model has linear mounts"
    signature = "the seat resonates at another cab bounce, pitch and roll, and the cab's springs stiffen progressively"

    def check(self, vehicle):
        super().check(vehicle)
        if vehicle.cab is None:
            raise ValueError(f"{vehicle.source}: [{self.name}] needs a [cab] on mounts")

    def build(self, car, vehicle):
        spring = vehicle.extensions[self.name]
        for tendon in [t for t in car.tendons if t.name.startswith("cab/") and t.name.endswith("_mount")]:
            name = tendon.name.removesuffix("_mount") + "_air_spring"
            existing = car.actuator(name)
            if existing is not None:
                car.delete(existing)
            add_air_spring(car, name, tendon, spring, 0.0, lengthens=True)

    def fit_parameters(self, vehicle, hints=None):
        start = vehicle.extensions.get(self.name) or (vehicle.cab.air_spring if vehicle.cab is not None else None)
        if start is None:
            return []
        return [FitParameter("volume", start.volume, 0.2 * start.volume, 5 * start.volume,
                             self.field_setter("volume", start), typical=0.2 * start.volume, unit="m^3")]

    def hidden(self, truth, rng):
        if truth.cab is None or truth.cab.air_spring is None:
            raise ValueError(f"{truth.name} has no cab on air springs")
        return with_extension(truth, self.name, dataclasses.replace(truth.cab.air_spring,
                                                                    volume=truth.cab.air_spring.volume
                                                                    * rng.uniform(0.5, 0.75)))


CAUSE = _CabAirSpring()
