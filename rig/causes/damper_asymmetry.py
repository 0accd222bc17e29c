"""``damper_asymmetry``: rebound and compression damping differ (a bilinear damper).

    [damper_asymmetry.rear]   # N s/m, replace [rear] damping in compression / rebound
    compression = 1800.0
    rebound = 3200.0

Realised as one affine actuator per sign of the damper velocity, each clamped to its own force sign.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape
from rig.elements.parameters import param
from rig.elements.tendons import clamped_damper, damper_of


@dataclass(frozen=True)
class DamperAsymmetry:
    compression: float = field(metadata=param("N s/m", 0.0, 1e5, "damping while the strut shortens"))
    rebound: float = field(metadata=param("N s/m", 0.0, 1e5, "damping while the strut extends"))


def split(damping: float, ratio: float) -> DamperAsymmetry:
    """The asymmetric damper with rebound/compression ``ratio`` whose mean coefficient is ``damping``."""
    return DamperAsymmetry(compression=2 * damping / (1 + ratio), rebound=2 * ratio * damping / (1 + ratio))


class _DamperAsymmetry(AxleCause):
    name = "damper_asymmetry"
    damper_line = "law"
    damper_part = "slopes"
    subsystem = "car"
    values = DamperAsymmetry
    meaning = "rebound and compression damping differ"
    signature = "the residual changes slope with the sign of the travel velocity"
    evidence = (Shape.ASYMMETRIC_DAMPING,)

    def build_corner(self, car, corner, damper):
        tendon = damper_of(car, corner)
        tendon.damping = [0.0, *tendon.damping[1:]]  # the linear part moves to the clamped actuators
        clamped_damper(car, corner, "rebound", damper.rebound, -1)
        clamped_damper(car, corner, "compression", damper.compression, +1)

    def fit_parameters(self, vehicle, hints=None):
        def apply(v, ratio):
            return self.on_every_axle(v, lambda a: split(v.axle_named(a).damping, ratio))
        return [FitParameter("rebound_to_compression", 1.2, 0.5, 5.0, apply)]

    def hidden(self, truth, rng):
        ratio = rng.uniform(2.0, 3.0)
        return self.on_every_axle(truth, lambda a: split(truth.axle_named(a).damping, ratio))


CAUSE = _DamperAsymmetry()
