"""Beam axles of a truck (layout ``truck``): what ``beam_leaf`` and ``beam_air`` share.

The axle is one body across the vehicle, ``<axle>/beam`` (``front/beam``, ``middle/beam``...), on a vertical slide
and a hinge about x at its centre (heave and roll; it is located fore and aft and laterally by its springs or links,
which a vertical ride model leaves rigid). It weighs twice the axle's ``unsprung_mass`` (the mass at each wheel
station) and has the axle's ``roll_inertia`` (default: those masses at the stations). At each end a wheel station,
the corner's contract (rig/vehicle/suspensions/_base.py): body ``<corner>/wheel`` fixed to the beam with the site
``<corner>/hub`` at the wheel centre; the spring ``<corner>/suspension``, a vertical tendon from the frame to the beam
at half the ``spring_track`` from the centre line, and the damper ``<corner>/damper`` likewise at ``damper_track``;
the travel sensors measure the hub's distance below a frame site above the station (as a linkage corner's).

Both corners of an axle are built when its first corner is: the beam is made then, and each station gets its
elements. Rates: ``spring_rate`` and ``damping`` are each spring's and each damper's own, vertical where they sit; in
heave they are the rates at the wheel, in roll the wheel feels them by (spring_track / track)^2.
"""

from __future__ import annotations

from typing import ClassVar

import mujoco
import numpy as np

from rig.io.channels import axle_corners, corner_axle, corner_side
from rig.vehicle.suspensions._base import Suspension
from rig.vehicle.truck_mjcf import SPRING_COLOR, WHEEL_COLOR, add_frame_site

BEAM_COLOR = [0.45, 0.45, 0.50, 1.0]
BEAM_RADIUS = 0.06       # m, drawn
MIN_SPRING_LENGTH = 0.1  # m: the spring and damper lines run from the axle up to the frame's level
_SITE = mujoco.mjtObj.mjOBJ_SITE
_DOWN = [np.sqrt(0.5), 0.0, np.sqrt(0.5), 0.0]  # a site turned so that its x axis points down


def design_length(vehicle) -> float:
    """m: a spring's (and damper's) vertical line at design, from the axle's centre height to the frame's level."""
    length = vehicle.cg_height - vehicle.wheel_radius
    if length < MIN_SPRING_LENGTH:
        raise ValueError(f"{vehicle.name}: [geometry] cg_height ({vehicle.cg_height:g} m) must stand at least "
                         f"{MIN_SPRING_LENGTH:g} m above wheel_radius ({vehicle.wheel_radius:g} m) on a beam axle")
    return length


class BeamAxle(Suspension):
    """A beam axle; subclasses realise its springs' law (``spring``)."""

    truck_axle: ClassVar[bool] = True
    # the two stations are one body: a station's force law (its wheel's equilibrium, the force against the station's
    # own travel) misreads the beam's roll, with springs, dampers and tyres at three tracks about it. On truck_6x4 with
    # nothing hidden it showed coupling, a lagging and progressive damping and a stiffening in rebound, and departures
    # of every rate: none of it a cause.
    corner_law: ClassVar[bool] = False
    own_keys: ClassVar[tuple[str, ...]] = ("spring_track", "damper_track", "roll_inertia")

    def complete_axle(self, values, label):
        if "spring_track" not in values:
            raise ValueError(f"{label} a beam axle needs spring_track (m between its springs)")
        values.setdefault("damper_track", values["spring_track"])
        values.setdefault("roll_inertia", 2 * values["unsprung_mass"] * (values["track"] / 2) ** 2)
        return values

    def build_corner(self, car, vehicle, corner):
        axle_name = corner_axle(corner)
        if corner != axle_corners(axle_name)[0]:
            return  # built with the axle's left corner
        beam = _add_beam(car, vehicle, axle_name)
        for station in axle_corners(axle_name):
            self._add_station(car, vehicle, station, beam)

    def _add_station(self, car, vehicle, corner: str, beam) -> None:
        axle = vehicle.axle(corner)
        x, y = vehicle.corner_position(corner)
        side = corner_side(corner)
        _remove_template_station(car, corner)
        wheel = beam.add_body(name=f"{corner}/wheel", pos=[0.0, y, 0.0])
        wheel.add_geom(name=f"{corner}/wheel", type=mujoco.mjtGeom.mjGEOM_CYLINDER, rgba=WHEEL_COLOR,
                       size=[vehicle.wheel_radius, 0.1 if axle.tyres == "single" else axle.dual_spacing, 0],
                       euler=[np.pi / 2, 0, 0], contype=0, conaffinity=0, mass=0.0)
        wheel.add_site(name=f"{corner}/hub")
        length = design_length(vehicle)
        for part, track in (("spring", axle.spring_track), ("damper", axle.damper_track)):
            beam.add_site(name=f"{corner}/{part}_lower", pos=[0.0, side * track / 2, 0.0])
            add_frame_site(car, vehicle, f"{corner}/{part}_upper", x, side * track / 2, 0.0)
        spring = _line(car, f"{corner}/suspension", f"{corner}/spring_upper", f"{corner}/spring_lower", SPRING_COLOR)
        self.spring(car, vehicle, corner, spring, length)
        damper = _line(car, f"{corner}/damper", f"{corner}/damper_upper", f"{corner}/damper_lower",
                       [0.3, 0.3, 0.3, 0.0])
        damper.damping = [axle.damping, 0.0, 0.0]
        add_frame_site(car, vehicle, f"{corner}/travel", x, y, 0.0)
        car.site(f"{corner}/travel").quat = _DOWN
        car.add_sensor(name=f"{corner}/unsprung_acc", type=mujoco.mjtSensor.mjSENS_FRAMELINACC, objtype=_SITE,
                       objname=f"{corner}/hub")
        for quantity, kind in (("suspension_length", mujoco.mjtSensor.mjSENS_FRAMEPOS),
                               ("suspension_rate", mujoco.mjtSensor.mjSENS_FRAMELINVEL)):
            car.add_sensor(name=f"{corner}/{quantity}", type=kind, objtype=_SITE, objname=f"{corner}/hub",
                           reftype=_SITE, refname=f"{corner}/travel")

    def spring(self, car, vehicle, corner: str, tendon, length: float) -> None:
        """Give the spring tendon (vertical, ``length`` m at design) its law."""
        raise NotImplementedError


def _add_beam(car, vehicle, axle_name: str):
    axle = vehicle.axle_named(axle_name)
    left, _ = axle_corners(axle_name)
    x, _ = vehicle.corner_position(left)
    beam = car.worldbody.add_body(name=f"{axle_name}/beam", pos=[x, 0.0, vehicle.wheel_radius])
    beam.add_joint(name=f"{axle_name}/beam_heave", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1])
    beam.add_joint(name=f"{axle_name}/beam_roll", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[1, 0, 0])
    beam.mass, beam.ipos = 2 * axle.unsprung_mass, [0.0, 0.0, 0.0]
    beam.inertia = [axle.roll_inertia, 0.6 * axle.roll_inertia, 0.6 * axle.roll_inertia]  # only roll turns it
    beam.explicitinertial = True
    beam.add_geom(name=f"{axle_name}/beam", type=mujoco.mjtGeom.mjGEOM_CAPSULE, rgba=BEAM_COLOR, mass=0.0,
                  fromto=[0.0, axle.track / 2, 0.0, 0.0, -axle.track / 2, 0.0], size=[BEAM_RADIUS, 0, 0],
                  contype=0, conaffinity=0)
    return beam


def _remove_template_station(car, corner: str) -> None:
    """Delete the template's vertical corner (wheel body, spring tendon, their sensors); keep the frame's site."""
    for quantity in ("unsprung_acc", "suspension_length", "suspension_rate"):
        car.delete(car.sensor(f"{corner}/{quantity}"))
    car.delete(car.tendon(f"{corner}/suspension"))
    car.delete(car.body(f"{corner}/wheel"))


def _line(car, name: str, upper: str, lower: str, rgba: list[float]):
    tendon = car.add_tendon(name=name)
    tendon.wrap_site(upper)
    tendon.wrap_site(lower)
    tendon.width, tendon.rgba = 0.02, rgba
    return tendon
