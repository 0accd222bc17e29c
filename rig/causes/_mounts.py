"""The mounts of a truck's body on mounts (its cab or its driveline: rig/elements/mounted_body.py) as a cause: each of
the four mounts softer, stiffer or damped otherwise than modelled. ``cab_mounts`` and ``driveline_mounts`` are one of
these each; they share the realisation, the fit and the hidden instance written here."""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import CarCause, FitParameter, with_extension
from rig.elements.parameters import param


@dataclass(frozen=True)
class Mounts:
    stiffness: float = field(metadata=param("N/m", 1e3, 1e8, "vertical rate of each mount"))
    damping: float = field(metadata=param("N s/m", 0.0, 1e6, "vertical damping of each mount"))


class MountsCause(CarCause):
    """Mounts of the body ``body``: realised on its mount tendons (``<body>/<mount>_mount``) in place of the vehicle
    file's stiffness and damping (a body on air springs keeps their force at design height, the spring then linear
    about it); fitted from the vehicle's own mounts."""

    body: str
    subsystem = "car"
    layouts = ("truck",)
    values = Mounts

    def check(self, vehicle):
        super().check(vehicle)
        if getattr(vehicle, self.body) is None:
            raise ValueError(f"{vehicle.source}: [{self.name}] needs a [{self.body}] on mounts")

    def build(self, car, vehicle):
        mounts = vehicle.extensions[self.name]
        for tendon in car.tendons:
            if tendon.name.startswith(f"{self.body}/") and tendon.name.endswith("_mount"):
                tendon.stiffness, tendon.damping = [mounts.stiffness, 0.0, 0.0], [mounts.damping, 0.0, 0.0]

    def fit_parameters(self, vehicle, hints=None):
        body = getattr(vehicle, self.body)
        if body is None:
            return []
        start = vehicle.extensions.get(self.name) or Mounts(body.stiffness, body.damping)
        return [FitParameter("stiffness", start.stiffness, 0.1 * start.stiffness, 10 * start.stiffness,
                             self.field_setter("stiffness", start), unit="N/m"),
                FitParameter("damping", start.damping, 0.0, 10 * start.damping + 100.0,
                             self.field_setter("damping", start), unit="N s/m")]

    def hidden(self, truth, rng):
        body = getattr(truth, self.body)
        if body is None:
            raise ValueError(f"{truth.name} has no {self.body} on mounts")
        return with_extension(truth, self.name, Mounts(body.stiffness * rng.uniform(0.45, 0.7),
                                                       body.damping * rng.uniform(0.5, 0.8)))
