"""``rebound_stop``: extra stiffness beyond a rebound gap from static ride height (the strut's rebound
spring or the damper's hydraulic rebound stop, a dead-band spring acting in extension).

    [rebound_stop.front]   # gap: m of extension from static ride height to contact; rate: N/m in contact
    gap = 0.030
    rate = 150000.0
    quadratic = 0.0   # N/m^2, optional: a stop that stiffens as it is pressed (F = rate d + quadratic d^2)
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import Shape
from rig.elements.parameters import param
from rig.elements.tendons import spring_beside_suspension, spring_reference
from rig.causes._stop import StopCause


@dataclass(frozen=True)
class ReboundStop:
    gap: float = field(metadata=param("m", 0.0, 0.3, "extension from static ride height to contact"))
    rate: float = field(metadata=param("N/m", 1e3, 1e8, "rate in contact"))
    quadratic: float = field(default=0.0, metadata=param("N/m^2", 0.0, 1e10, "stiffening in contact: + quadratic d^2"))


class _ReboundStop(StopCause):
    name = "rebound_stop"
    values = ReboundStop
    meaning = "extra stiffness beyond a rebound gap"
    signature = "the measured stiffness rises beyond an extension, on the rebound side only"
    evidence = (Shape.STIFFENS_IN_REBOUND,)

    def build_corner(self, car, corner, stop):
        spring_beside_suspension(car, f"{corner}/rebound_stop", corner, [stop.rate, stop.quadratic, 0.0])

    def at_static_corner(self, model, data, corner, stop):
        spring_reference(model, data, f"{corner}/rebound_stop", above=stop.gap)


CAUSE = _ReboundStop()
