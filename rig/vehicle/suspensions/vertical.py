"""``vertical``: the baseline ride model's corner (docs/contracts.md), the wheel on a vertical slide joint in the world
below its station, spring || parasitic rate and damper as one tendon from the body site to the hub (its stiffness and
its damping: rig/elements/tendons.py ``damper_of``). The template assets/mjcf/ride_car.xml holds its structure; this
fills in the numbers."""

from __future__ import annotations

from rig.vehicle.suspensions._base import Suspension


class _Vertical(Suspension):
    name = "vertical"
    truck_axle = True

    def build_corner(self, car, vehicle, corner):
        x, y = vehicle.corner_position(corner)
        axle = vehicle.axle(corner)
        wheel = car.body(f"{corner}/wheel")
        wheel.pos = [x, y, vehicle.wheel_radius]
        wheel.mass = axle.unsprung_mass
        wheel.ipos = [0.0, 0.0, 0.0]
        wheel.inertia = [1.0, 1.0, 1.0]  # vertical slide only: rotary inertia never enters
        wheel.explicitinertial = True
        car.geom(f"{corner}/wheel").size = [vehicle.wheel_radius, 0.1, 0]
        line = car.tendon(f"{corner}/suspension")
        line.stiffness = [axle.suspension_rate, 0.0, 0.0]  # rest: template length
        line.damping = [axle.damping, 0.0, 0.0]


SUSPENSION = _Vertical()
