"""``cab_mounts``: a truck cab's mounts are softer or stiffer, or damped otherwise, than modelled.

    [cab_mounts]             # each of the four mounts (rig/vehicle/mounted_body.py)
    stiffness = 2.0e4        # N/m
    damping = 1200.0         # N s/m

Realised on the cab's mount tendons (``cab/<mount>_mount``), in place of ``[cab]``'s stiffness and damping. Trucks
with a cab only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import CarCause, FitParameter, param, with_extension


@dataclass(frozen=True)
class CabMounts:
    stiffness: float = field(metadata=param("N/m", 1e3, 1e8, "vertical rate of each mount"))
    damping: float = field(metadata=param("N s/m", 0.0, 1e6, "vertical damping of each mount"))


class _CabMounts(CarCause):
    name = "cab_mounts"
    subsystem = "car"
    layouts = ("truck",)
    values = CabMounts
    meaning = "the cab's mounts are softer, stiffer or damped otherwise than modelled"
    signature = "the seat and cab accelerations resonate at another cab bounce, pitch and roll than the model's"

    def check(self, vehicle):
        super().check(vehicle)
        if vehicle.cab is None:
            raise ValueError(f"{vehicle.source}: [cab_mounts] needs a [cab] on mounts")

    def build(self, car, vehicle):
        mounts = vehicle.extensions[self.name]
        for tendon in car.tendons:
            if tendon.name.startswith("cab/") and tendon.name.endswith("_mount"):
                tendon.stiffness, tendon.damping = [mounts.stiffness, 0.0, 0.0], [mounts.damping, 0.0, 0.0]

    def fit_parameters(self, vehicle, hints=None):
        if vehicle.cab is None:
            return []
        start = vehicle.extensions.get(self.name) or CabMounts(vehicle.cab.stiffness, vehicle.cab.damping)
        return [FitParameter("stiffness", start.stiffness, 0.1 * start.stiffness, 10 * start.stiffness,
                             self.field_setter("stiffness", start)),
                FitParameter("damping", start.damping, 0.0, 10 * start.damping + 100.0,
                             self.field_setter("damping", start))]

    def hidden(self, truth, rng):
        if truth.cab is None:
            raise ValueError(f"{truth.name} has no cab on mounts")
        return with_extension(truth, self.name, CabMounts(truth.cab.stiffness * rng.uniform(0.45, 0.7),
                                                          truth.cab.damping * rng.uniform(0.5, 0.8)))


CAUSE = _CabMounts()
