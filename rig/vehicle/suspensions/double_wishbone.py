"""``double_wishbone``: lower and upper wishbones hinged on the body, the upright on the lower ball joint (three
hinges), the upper ball joint a ``connect`` to the upper wishbone, the tie rod to the rack or the body
(rig/vehicle/suspensions/linkage.py). The spring line's lower end moves with the lower wishbone."""

from __future__ import annotations

import numpy as np

from rig.vehicle.suspensions import bushings
from rig.vehicle.suspensions.linkage import HINGE_AXES, Arm, Linkage, connect
from rig.vehicle.suspensions.links import add_link_geom, add_part_body


class _DoubleWishbone(Linkage):
    name = "double_wishbone"
    rows = ("lower_outer", "lower_outer", "upper_outer", "upper_outer", "tie_rod_outer")
    kingpin = ("lower_ball", "upper_ball")
    spring_carrier = "lower_arm"
    upright_top = "upper_outer"
    upright_origin = "lower_outer"

    def arms(self, kinematics):
        return (Arm("lower_arm", "lower_front", "lower_rear", "lower_outer"),
                Arm("upper_arm", "upper_front", "upper_rear", "upper_outer"))

    def residuals(self, kinematics, side, coordinates, rack):
        lower, upper = self.arms(kinematics)
        return np.column_stack([*self.arm_residuals(kinematics, side, coordinates, lower),
                                *self.arm_residuals(kinematics, side, coordinates, upper),
                                self.tie_rod_residual(kinematics, side, coordinates, rack)])

    def add_upright(self, car, frame, arms, design):
        import mujoco

        point = frame.kinematics.point
        origin = point("lower_outer", frame.side)
        upright = add_part_body(arms["lower_arm"], frame.name("upright"), origin - point("lower_front", frame.side),
                                design.parts["upright"], origin)
        bushings.add_slides(upright, frame.name("lower_outer"),
                            bushings.ball_slides(frame.kinematics, "lower_outer", frame.side))
        for axis, label in zip(np.eye(3), HINGE_AXES):
            upright.add_joint(name=frame.name(f"upright_{label}"), type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(axis))
        upper = point("upper_outer", frame.side) - origin
        upright.add_site(name=frame.name("lower_ball"), pos=[0.0, 0.0, 0.0])
        upright.add_site(name=frame.name("upper_ball"), pos=list(upper))
        bushings.bushed_site(arms["upper_arm"], frame.name("upper_ball_arm"),
                             point("upper_outer", frame.side) - point("upper_front", frame.side),
                             bushings.ball_slides(frame.kinematics, "upper_outer", frame.side),
                             frame.name("upper_outer"))
        connect(car, frame.name("upper_ball"), frame.name("upper_ball_arm"))
        add_link_geom(upright, np.zeros(3), upper)
        add_link_geom(upright, np.zeros(3), point("tie_rod_outer", frame.side) - origin)
        add_link_geom(upright, upper, point("wheel_centre", frame.side) - origin)
        return upright

    def upright_joints(self, corner):
        return tuple(f"{corner}/upright_{label}" for label in HINGE_AXES)


SUSPENSION = _DoubleWishbone()
