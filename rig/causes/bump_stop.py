"""``bump_stop``: extra stiffness beyond a compression gap from static ride height (a dead-band spring).

    [bump_stop.front]   # gap: m of compression from static ride height to contact; rate: N/m in contact
    gap = 0.030
    rate = 150000.0
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, param, spring_beside_suspension, spring_reference


@dataclass(frozen=True)
class BumpStop:
    gap: float = field(metadata=param("m", 0.0, 0.3, "compression from static ride height to contact"))
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "rate in contact"))


class _BumpStop(AxleCause):
    name = "bump_stop"
    subsystem = "car"
    values = BumpStop
    meaning = "extra stiffness beyond a compression gap"
    signature = "the residual body acceleration changes slope beyond a compression, on the compression side only"
    evidence = (Shape.STIFFENS_IN_COMPRESSION,)

    def build_corner(self, car, corner, stop):
        spring_beside_suspension(car, f"{corner}/bump_stop", corner, [stop.rate, 0.0, 0.0])

    def at_static_corner(self, model, data, corner, stop):
        spring_reference(model, data, f"{corner}/bump_stop", below=stop.gap, dead_band=True)

    def fit_parameters(self, vehicle, hints=None):
        def current(v):
            return v.extensions.get(self.name, {}).get("front", BumpStop(0.02, 1e5))

        return [FitParameter("gap", 0.02, 0.003, 0.05,
                             lambda v, g: self.on_every_axle(v, lambda a: BumpStop(g, current(v).rate)), unit="m"),
                FitParameter("rate", 5e4, 1e3, 1e6,
                             lambda v, k: self.on_every_axle(v, lambda a: BumpStop(current(v).gap, k)), unit="N/m")]

    def hidden(self, truth, rng):
        gap, rate = rng.uniform(0.012, 0.018), rng.uniform(1e5, 2e5)
        return self.on_every_axle(truth, lambda a: BumpStop(gap, rate))


CAUSE = _BumpStop()
