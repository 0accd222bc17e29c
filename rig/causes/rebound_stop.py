"""``rebound_stop``: extra stiffness beyond a rebound gap from static ride height (the strut's rebound
spring or the damper's hydraulic rebound stop, a dead-band spring acting in extension).

    [rebound_stop.front]   # gap: m of extension from static ride height to contact; rate: N/m in contact
    gap = 0.030
    rate = 150000.0
    quadratic = 0.0   # N/m^2, optional: a stop that stiffens as it is pressed (F = rate d + quadratic d^2)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, param, spring_beside_suspension, spring_reference


@dataclass(frozen=True)
class ReboundStop:
    gap: float = field(metadata=param("m", 0.0, 0.3, "extension from static ride height to contact"))
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "rate in contact"))
    quadratic: float = field(default=0.0, metadata=param("N/m^2", 0.0, 1e10, "stiffening in contact: + quadratic d^2"))


class _ReboundStop(AxleCause):
    name = "rebound_stop"
    subsystem = "car"
    values = ReboundStop
    meaning = "extra stiffness beyond a rebound gap"
    signature = "the measured stiffness rises beyond an extension, on the rebound side only"
    evidence = (Shape.STIFFENS_IN_REBOUND,)

    def build_corner(self, car, corner, stop):
        spring_beside_suspension(car, f"{corner}/rebound_stop", corner, [stop.rate, stop.quadratic, 0.0])

    def at_static_corner(self, model, data, corner, stop):
        spring_reference(model, data, f"{corner}/rebound_stop", above=stop.gap)

    def fit_parameters(self, vehicle, hints=None):
        return [FitParameter("gap", 0.02, 0.003, 0.05, lambda v, g: self._with(v, gap=g), unit="m"),
                FitParameter("rate", 5e4, 1e3, 1e6, lambda v, k: self._with(v, rate=k), unit="N/m")]

    def refined_parameters(self, vehicle, hints=None):
        """A stop that stiffens as it is pressed (an elastomer's rise): its rate grows by 2 quadratic d."""
        return [*self.fit_parameters(vehicle, hints),
                FitParameter("quadratic", 1e6, 0.0, 5e7, lambda v, q: self._with(v, quadratic=q), unit="N/m^2")]

    def _with(self, vehicle, **values):
        current = vehicle.extensions.get(self.name, {}).get("front", ReboundStop(0.02, 1e5))
        return self.on_every_axle(vehicle, lambda a: dataclasses.replace(current, **values))

    def hidden(self, truth, rng):
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        return self.on_every_axle(truth, lambda a: ReboundStop(gap, rate))


CAUSE = _ReboundStop()
