"""``damper_preload``: a gas damper's preload. The gas pressure on the rod's area pushes the rod out with a force that
does not depend on the rod's speed: a constant force between body and wheel, pushing the body up and the wheel down,
that the car carries statically. It settles higher by the force over the suspension's rate at the wheel, its tyre
loads as they were (the force is internal to the car). A dynamometer shows it as the force at zero speed (``rig
dyno``'s ``+preload``, written here by ``--write``); a rig test, whose motions are measured from static ride height,
does not (``seen_on``), so the diagnosis does not fit it.

    [damper_preload.front]
    force = 105.0    # N at the wheel: the dyno's preload times the motion ratio (damper over wheel travel)

Realised as an actuator on the damper's tendon with a constant force (an affine bias, no input), so that it acts
where the damper does: along the damper's line (at the wheel at design on a linkage, whose damper tendon is divided
to the wheel), through a top mount in series (which it presses).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco

from rig.causes._base import AxleCause
from rig.elements.parameters import param
from rig.elements.tendons import damper_of


@dataclass(frozen=True)
class DamperPreload:
    force: float = field(metadata=param("N", -1e5, 1e5, "constant force at the wheel pushing body and wheel apart "
                                                        "(a gas damper's preload)"))


class _DamperPreload(AxleCause):
    name = "damper_preload"
    damper_line = "law"
    damper_part = "preload"
    subsystem = "car"
    seen_on = "dyno"
    values = DamperPreload
    meaning = "a gas damper pushes its rod out with a constant force: the car settles higher on its springs"
    signature = ("none in a rig test measured from static ride height; on a dynamometer the force at zero speed, "
                 "and a static ride height higher by the force over the wheel rate")

    def build_corner(self, car, corner, preload):
        actuator = car.add_actuator(name=f"{corner}/damper_preload", target=damper_of(car, corner).name)
        actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
        actuator.gainprm[0] = 0.0
        actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        actuator.biasprm[:3] = [preload.force, 0.0, 0.0]  # a positive force lengthens the tendon: body and wheel apart


CAUSE = _DamperPreload()
