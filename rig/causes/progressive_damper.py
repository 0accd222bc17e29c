"""``progressive_damper``: the damper force grows with the square of its velocity, the neuro-model paper's quadratic
damper (its F = C0 v + Cn v^2, here odd in v: F = C0 v + Cn v |v|); C0 is the axle's ``damping``.

    [progressive_damper.front]
    quadratic = 3000.0   # N s^2/m^2, Cn

Realised exactly by the damper tendon's polynomial damping, f = -(a v + b v|v| + c v^3) with b = Cn.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape
from rig.elements.parameters import param
from rig.elements.tendons import damper_of

_REFERENCE_VELOCITY = 0.5  # m/s: the fitted progression is stated as Cn v / C0 at this damper velocity


@dataclass(frozen=True)
class ProgressiveDamper:
    quadratic: float = field(metadata=param("N s^2/m^2", 0.0, 1e6, "Cn of F = C0 v + Cn v |v|"))


class _ProgressiveDamper(AxleCause):
    name = "progressive_damper"
    damper_line = "law"
    damper_part = "quadratic"
    subsystem = "car"
    values = ProgressiveDamper
    meaning = "the damper force grows with the square of its velocity (the neuro-model paper: C0 v + Cn v|v|)"
    signature = "the residual grows faster than linearly with travel velocity, alike in compression and rebound"
    evidence = (Shape.PROGRESSIVE_DAMPING,)

    def build_corner(self, car, corner, damper):
        tendon = damper_of(car, corner)
        tendon.damping = [tendon.damping[0], damper.quadratic, tendon.damping[2]]

    def fit_parameters(self, vehicle, hints=None):
        def apply(v, share):
            return self.on_every_axle(v, lambda a: ProgressiveDamper(share * v.axle_named(a).damping
                                                                     / _REFERENCE_VELOCITY))
        return [FitParameter("progression_at_0.5_m_per_s", 0.1, 0.0, 3.0, apply)]

    def hidden(self, truth, rng):
        share = rng.uniform(0.8, 1.5)
        return self.on_every_axle(truth, lambda a: ProgressiveDamper(share * truth.axle_named(a).damping
                                                                     / _REFERENCE_VELOCITY))


CAUSE = _ProgressiveDamper()
