"""``beam_leaf``: a beam axle on leaf springs (rig/vehicle/suspensions/beam.py), each a linear rate (``spring_rate``,
plus ``parasitic_rate``) with Fancher's inter-leaf friction from ``[axles.leaf_spring]`` (rig/elements/leaf_spring.py):
a LuGre/Dahl actuator on the spring's tendon, inside ``mj_step``. Without the table the springs are frictionless."""

from __future__ import annotations

from rig.elements.leaf_spring import LeafFriction, add_leaf_friction
from rig.vehicle.suspensions.beam import BeamAxle


class _BeamLeaf(BeamAxle):
    name = "beam_leaf"
    law = ("leaf_spring", LeafFriction, False)

    def spring(self, car, vehicle, corner, tendon, length):
        axle = vehicle.axle(corner)
        tendon.stiffness = [axle.suspension_rate, 0.0, 0.0]
        tendon.springlength = [length, length]  # drawn unloaded: the static solve presses the spring
        if axle.law is not None and axle.law.friction > 0:
            add_leaf_friction(car, f"{corner}/leaf_friction", tendon.name, axle.law)


SUSPENSION = _BeamLeaf()
