"""``bump_stop``: extra stiffness beyond a compression gap from static ride height (a dead-band spring).

    [bump_stop.front]   # gap: m of compression from static ride height to contact; rate: N/m in contact
    gap = 0.030
    rate = 150000.0
    quadratic = 0.0   # N/m^2, optional: a stop that stiffens as it is pressed (F = rate d + quadratic d^2)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, param, spring_beside_suspension, spring_reference


@dataclass(frozen=True)
class BumpStop:
    gap: float = field(metadata=param("m", 0.0, 0.3, "compression from static ride height to contact"))
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "rate in contact"))
    quadratic: float = field(default=0.0, metadata=param("N/m^2", 0.0, 1e10, "stiffening in contact: + quadratic d^2"))


class _BumpStop(AxleCause):
    name = "bump_stop"
    subsystem = "car"
    values = BumpStop
    meaning = "extra stiffness beyond a compression gap"
    signature = "the residual body acceleration changes slope beyond a compression, on the compression side only"
    evidence = (Shape.STIFFENS_IN_COMPRESSION,)

    def build_corner(self, car, corner, stop):
        spring_beside_suspension(car, f"{corner}/bump_stop", corner, [stop.rate, -stop.quadratic, 0.0])

    def at_static_corner(self, model, data, corner, stop):
        spring_reference(model, data, f"{corner}/bump_stop", below=stop.gap, dead_band=True)

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter("gap", 0.02, 0.003, 0.05, lambda v, g: self._with(v, gap=g), unit="m"),
                FitParameter("rate", 5e4, 1e3, 1e6, lambda v, k: self._with(v, rate=k), unit="N/m")]

    def refined_parameters(self, vehicle, hints=None):
        """A stop that stiffens as it is pressed (an elastomer's rise): its rate grows by 2 quadratic d."""
        return [*self.fit_parameters(vehicle, hints),
                FitParameter("quadratic", 1e6, 0.0, 5e7, lambda v, q: self._with(v, quadratic=q), unit="N/m^2")]

    def _with(self, vehicle, **values):
        current = vehicle.extensions.get(self.name, {}).get("front", BumpStop(0.02, 1e5))
        return self.on_every_axle(vehicle, lambda a: dataclasses.replace(current, **values))

    def hidden(self, truth, rng):
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        return self.on_every_axle(truth, lambda a: BumpStop(gap, rate))


CAUSE = _BumpStop()
