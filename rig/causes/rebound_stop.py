"""``rebound_stop``: extra stiffness beyond a rebound gap from static ride height (the strut's rebound
spring or the damper's hydraulic rebound stop, a dead-band spring acting in extension).

    [rebound_stop.front]   # gap: m of extension from static ride height to contact; rate: N/m in contact
    gap = 0.030
    rate = 150000.0
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, param, spring_beside_suspension, spring_reference


@dataclass(frozen=True)
class ReboundStop:
    gap: float = field(metadata=param("m", 0.0, 0.3, "extension from static ride height to contact"))
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "rate in contact"))


class _ReboundStop(AxleCause):
    name = "rebound_stop"
    subsystem = "car"
    values = ReboundStop
    meaning = "extra stiffness beyond a rebound gap"
    signature = "the measured stiffness rises beyond an extension, on the rebound side only"
    evidence = (Shape.STIFFENS_IN_REBOUND,)

    def build_corner(self, car, corner, stop):
        spring_beside_suspension(car, f"{corner}/rebound_stop", corner, [stop.rate, 0.0, 0.0])

    def at_static_corner(self, model, data, corner, stop):
        spring_reference(model, data, f"{corner}/rebound_stop", above=stop.gap)

    def fit_parameters(self, vehicle, hints=None):
        def current(v):
            return v.extensions.get(self.name, {}).get("front", ReboundStop(0.02, 1e5))

        return [FitParameter("gap", 0.02, 0.003, 0.05,
                             lambda v, g: self.on_every_axle(v, lambda a: ReboundStop(g, current(v).rate)), unit="m"),
                FitParameter("rate", 5e4, 1e3, 1e6,
                             lambda v, k: self.on_every_axle(v, lambda a: ReboundStop(current(v).gap, k)), unit="N/m")]

    def hidden(self, truth, rng):
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        return self.on_every_axle(truth, lambda a: ReboundStop(gap, rate))


CAUSE = _ReboundStop()
