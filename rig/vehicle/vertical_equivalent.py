"""The vertical car equivalent to a car with linkage corners: what the linkage is in the ride model's coordinates.

In the vertical ride model's coordinates (body heave z, pitch theta, roll phi, and each wheel's travel q relative
to the body), a linkage corner is linear about design with these masses, from the kinetic energy of its parts
(rig/vehicle/suspensions/linkage.py: each part's mass m_i, CG r_i from the sprung CG, inertia I_i, and its CG
velocity u_i and angular velocity s_i per m of travel), the body frozen or the travel held:

- the wheel's vertical momentum per travel, c = sum m_i u_iz (kg): the mass whose weight the wheel carries and
  which moves with the wheel centre for the body's vertical motion;
- its kinetic mass, m_eq = sum (m_i |u_i|^2 + s_i . I_i s_i) (kg): the vehicle file's ``unsprung_mass`` by
  construction of the parts;
- the rest, b = m_eq - c (kg): kinetic energy the wheel's sideways motion (track change) and rotation (camber
  change) store without loading the body vertically. It acts on the travel alone, 1/2 b (dq/dt)^2: an INERTER
  between body and wheel (force b d2q/dt2, equal and opposite on both);
- the car frozen (q held) is one rigid body: the file's sprung body, less what the builder takes off it (each
  corner's parts' mass beyond ``unsprung_mass`` at the wheel centre), plus every part at its place with its own
  inertia.

So the equivalent vertical car has unsprung mass c per corner, an inerter b between its body site and hub, and a
sprung body whose heave mass, pitch and roll inertia are the frozen car's less c at each hub (whose vertical
motion the vertical wheel carries): sprung mass = file's + sum (unsprung_mass - c). Its rates, damping and tyres
are the file's (the linkage builder makes them the rates at the wheel at design). In the vertical model's
coordinates the equivalent car's inertia is the linkage car's to first order in heave and pitch; left out are the
frozen body's heave-pitch product (fs_car: 0.01 kg m), the parts' fore-aft share in the pitch coupling (0.03 %)
and their share in the roll coupling beyond c y (sideways motion and rotation about x: fs_car's is 1.8 % more), and
bushings' own modes (the parts are taken as rigid). No vertical car without an inerter matches: with
``unsprung_mass`` at the wheel fs_car's body acceleration is 2.4 % off at 20 Hz (b w over the damping: 0.40 kg x
126 rad/s / 2000 N s/m = 2.5 %), with c there the wheel's is 2.45 % off; with the inerters, 0.1 % and 0.4 %
(tests/test_kinematics_dynamics.py). An inerter is a body of mass b on a vertical slide, gravity compensated so that
it carries no weight, held by a tendon equality at the travel: slide = hub height - (heave - x pitch + y roll), the
body site's vertical motion for small angles (MuJoCo's tendon armature would be the natural inerter, but it keeps
only the inertia terms within one kinematic tree, and the vertical template's wheels hang in the world).

Written here: the kinetic-energy sums; MuJoCo's constrained inertia checks them (tests/test_kinematics_dynamics.py).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import mujoco
import numpy as np

from rig.io.channels import corner_axle
from rig.vehicle.suspensions import kinematics_of, suspension_of
from rig.vehicle.suspensions.linkage import BODY_SITE_HEIGHT, CornerFrame
from rig.vehicle.suspensions.links import CONSTRAINT_SOLIMP, CONSTRAINT_SOLREF
from rig.vehicle.parts import Vehicle

INERTER = "{corner}/inerter"  # body, joint, tendon and equality of a corner's inerter in the assembled spec


@dataclass(frozen=True)
class CornerInertia:
    """A corner's masses in the ride model's coordinates (kg; rigid in kg and kg m^2 about the sprung CG)."""

    vertical_mass: float     # c: vertical momentum of the corner's parts per m/s of travel
    kinetic_mass: float      # m_eq: twice their kinetic energy per (m/s of travel)^2
    rigid_mass: float        # the parts' mass less what the builder took off the sprung body for them
    rigid_pitch: float       # their pitch inertia about the sprung CG (frozen), less that taken off
    rigid_roll: float        # their roll inertia about the sprung CG (frozen), less that taken off

    @property
    def inerter(self) -> float:
        """b = m_eq - c, kg: the inertance between body and wheel the vertical model lacks."""
        return self.kinetic_mass - self.vertical_mass


@dataclass(frozen=True)
class VerticalEquivalent:
    """The equivalent vertical car (``vehicle``: no kinematics tables) and the inerters it needs (kg per corner)."""

    vehicle: Vehicle
    corners: dict[str, CornerInertia]

    @property
    def inerters(self) -> dict[str, float]:
        return {c: inertia.inerter for c, inertia in self.corners.items()}

    def add_inerters(self, spec: mujoco.MjSpec) -> None:
        """Add each corner's inerter to the assembled spec of ``vehicle`` (build_model's ``extend``)."""
        for corner, inertance in self.inerters.items():
            if inertance > 0:
                _add_inerter(spec, corner, inertance, self.vehicle.corner_position(corner))


def corner_inertia(vehicle: Vehicle, corner: str) -> CornerInertia:
    """A corner's masses in the ride model's coordinates: from its parts at design for a linkage; a vertical corner's
    wheel is all unsprung mass (c = m_eq), frozen with the body it moves with its station."""
    axle = vehicle.axle(corner)
    kinematics = kinematics_of(vehicle, corner)
    if kinematics is None:
        x, y = vehicle.corner_position(corner)
        mass = axle.unsprung_mass
        return CornerInertia(mass, mass, mass, mass * x**2, mass * y**2)
    frame = CornerFrame(corner, kinematics, vehicle.corner_position(corner)[0], vehicle.cg_height)
    parts = suspension_of(vehicle, corner).design(kinematics, frame.side, axle.unsprung_mass,
                                                  vehicle.wheel_radius).parts.values()
    excess = sum(p.mass for p in parts) - axle.unsprung_mass
    centre = frame.body_point("wheel_centre")
    pitch = sum(p.mass * (r[0] ** 2 + r[2] ** 2) + p.inertia[1, 1] for p in parts
                for r in [frame.axle_to_body(p.cg)]) - excess * (centre[0] ** 2 + centre[2] ** 2)
    roll = sum(p.mass * (r[1] ** 2 + r[2] ** 2) + p.inertia[0, 0] for p in parts
               for r in [frame.axle_to_body(p.cg)]) - excess * (centre[1] ** 2 + centre[2] ** 2)
    return CornerInertia(vertical_mass=sum(p.mass * p.velocity[2] for p in parts),
                         kinetic_mass=sum(p.kinetic_mass for p in parts), rigid_mass=axle.unsprung_mass,
                         rigid_pitch=float(pitch), rigid_roll=float(roll))


def vertical_equivalent(vehicle: Vehicle) -> VerticalEquivalent:
    """The vertical car equivalent to ``vehicle`` about design (module docstring): sprung mass and inertias of the
    frozen car less each wheel's vertical momentum at its hub, unsprung mass c per axle, and the inerters b; its body
    raised BODY_SITE_HEIGHT above the wheel centres if lower, so that the vertical template's springs (from a site at
    the CG's height to the hub) stay clear of zero length (its height does not enter the vertical model's dynamics)."""
    corners = {c: corner_inertia(vehicle, c) for c in vehicle.corners}
    positions = {c: np.array(vehicle.corner_position(c)) for c in vehicle.corners}
    sprung = vehicle.sprung_mass + sum(i.rigid_mass - i.vertical_mass for i in corners.values())
    pitch = vehicle.pitch_inertia + sum(i.rigid_pitch - i.vertical_mass * positions[c][0] ** 2
                                        for c, i in corners.items())
    roll = vehicle.roll_inertia + sum(i.rigid_roll - i.vertical_mass * positions[c][1] ** 2
                                      for c, i in corners.items())
    twin = vehicle
    for corner, inertia in corners.items():  # an axle's corners are mirror images: one sets the axle
        axle = twin.axle(corner)
        twin = twin.with_axle(corner_axle(corner), dataclasses.replace(axle, kinematics=None,
                                                                       unsprung_mass=inertia.vertical_mass))
    height = max([vehicle.cg_height] + [k.point("wheel_centre")[2] + BODY_SITE_HEIGHT for k in
                                        (kinematics_of(vehicle, c) for c in vehicle.corners) if k is not None])
    twin = dataclasses.replace(twin, sprung_mass=sprung, pitch_inertia=pitch, roll_inertia=roll, cg_height=height)
    return VerticalEquivalent(twin, corners)


def _add_inerter(spec: mujoco.MjSpec, corner: str, inertance: float, station: tuple[float, float]) -> None:
    """A gravity-compensated body of mass ``inertance`` on a vertical slide in the world, held by a tendon equality at
    the corner's travel (hub height less the body site's, small angles): kinetic energy 1/2 b (dq/dt)^2."""
    name = INERTER.format(corner=corner)
    body = spec.worldbody.add_body(name=name, gravcomp=1.0)
    body.mass, body.ipos, body.inertia, body.explicitinertial = inertance, [0.0, 0.0, 0.0], [1e-6] * 3, True
    body.add_joint(name=name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0.0, 0.0, 1.0])
    x, y = station
    tendon = spec.add_tendon(name=name)
    for joint, coefficient in ((name, 1.0), (f"car.{corner}/wheel", -1.0), ("car.heave", 1.0), ("car.pitch", -x),
                               ("car.roll", y)):
        if spec.joint(joint) is not None:  # a quarter car has no pitch or roll
            tendon.wrap_joint(joint, coefficient)
    equality = spec.add_equality(name=name, type=mujoco.mjtEq.mjEQ_TENDON, objtype=mujoco.mjtObj.mjOBJ_TENDON,
                                 name1=name)
    equality.data[:5] = [0.0, 1.0, 0.0, 0.0, 0.0]  # the tendon's length stays at its value at qpos0
    equality.solref, equality.solimp = list(CONSTRAINT_SOLREF), list(CONSTRAINT_SOLIMP)
