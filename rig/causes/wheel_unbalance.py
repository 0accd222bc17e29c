"""``wheel_unbalance``: a rolling wheel's unbalance (the transputer paper): a mass m at radius e off the wheel's axis,
which turns with the wheel and pushes the hub with the rotating force m e omega^2.

    [wheel_unbalance]
    corner = "FR"
    unbalance_kgm = 0.008   # kg m: m e
    angle_deg = 40.0        # from the wheel's mark to the unbalance, in the rolling direction

Angles (docs/contracts.md ``wheel_angle``): the wheel's angle is 0 when its mark is at the top of the wheel and grows
in the rolling direction (driving forward, the top of the wheel moves forward). The unbalance sits at
``angle_deg`` beyond the mark, so the vertical force on the hub is m e omega^2 cos(wheel_angle + angle).

Realised inside ``mj_step`` as a rim body of mass m at radius e = ``RIM_RADIUS_SHARE`` x the tyre's radius (a
balancing weight sits on the rim; only m e matters), on a hinge about the wheel's axle. The wheel body loses
the same mass, so the unsprung mass stays the data sheet's. The hinge carries the wheel's polar inertia
(``WHEEL_INERTIA``) and a stiff position servo (``SPIN_FREQUENCY``, critically damped), the actuator
``<corner>/wheel_spin`` that the model builder feeds with the wheel's angle as it feeds the tyres with the
road (rig/vehicle/mjcf.py): the road's grip keeps a real wheel at its rolling speed. On a rig, where nothing
turns the wheel, the unbalance does nothing. A track test shows it (``seen_on``); the identification is in
rig/diagnosis/track/unbalance.py, by order analysis against the wheel's measured angle, not by fitting simulations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any

from rig.causes._base import CarCause, ParameterSpec, with_extension
from rig.elements.parameters import param
from rig.io.channels import CORNERS, axle_corners
from rig.vehicle.mjcf import SPIN_ACTUATOR

RIM_RADIUS_SHARE = 0.64   # rim flange radius over tyre radius (15 in rim in a 195/55 R15 tyre: 0.19 / 0.298 m)
WHEEL_INERTIA = 1.0       # kg m^2: polar inertia of a passenger-car wheel with its tyre
SPIN_FREQUENCY = 25.0     # Hz: the spin servo's natural frequency (critically damped); far above nothing it feeds


@dataclass(frozen=True)
class WheelUnbalance:
    corner: str = field(metadata={"unit": "", "choices": CORNERS, "meaning": "the unbalanced wheel"})
    unbalance_kgm: float = field(metadata=param("kg m", 0.0, 0.2, "m e: unbalance mass times its radius"))
    angle_deg: float = field(default=0.0, metadata=param("deg", -360.0, 360.0,
                                                         "from the wheel's mark, in the rolling direction"))


def spin_gains(inertia: float) -> tuple[float, float]:
    """Position and velocity gains (N m/rad, N m s/rad) of the spin servo on a hinge of ``inertia`` kg m^2."""
    omega = 2 * math.pi * SPIN_FREQUENCY
    return inertia * omega**2, 2 * inertia * omega


class _WheelUnbalance(CarCause):
    name = "wheel_unbalance"
    subsystem = "car"
    seen_on = "track"
    values = WheelUnbalance
    meaning = "a rolling wheel's unbalance (track tests, the transputer paper)"
    signature = "a response at the wheel's own rotation order, growing with the square of its speed"

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> WheelUnbalance:
        if not isinstance(section, dict):
            raise ValueError(f"{where}: [{self.name}] must be a table")
        known = {"corner", "unbalance_kgm", "angle_deg"}
        unknown, missing = sorted(set(section) - known), sorted({"corner", "unbalance_kgm"} - set(section))
        if unknown or missing:
            raise ValueError(f"{where}: [{self.name}] " + "; ".join(
                ([f"unknown key(s) {', '.join(unknown)}"] if unknown else [])
                + ([f"missing {', '.join(missing)}"] if missing else [])) + f" (keys: {', '.join(sorted(known))})")
        corners = tuple(c for a in axles for c in axle_corners(a)) if len(axles) > 1 else ("FL",)
        if section["corner"] not in corners:
            raise ValueError(f"{where}: [{self.name}] corner = {section['corner']!r} is not one of "
                             f"{', '.join(corners)}")
        numbers = {}
        for key in ("unbalance_kgm", "angle_deg"):
            if key not in section:
                continue
            value, meta = section[key], WheelUnbalance.__dataclass_fields__[key].metadata
            number = isinstance(value, (int, float)) and not isinstance(value, bool)
            if not number or not meta["low"] <= value <= meta["high"]:
                raise ValueError(f"{where}: [{self.name}] {key} = {value!r} is outside the plausible range "
                                 f"{meta['low']:g}..{meta['high']:g} {meta['unit']}")
            numbers[key] = float(value)
        return WheelUnbalance(corner=section["corner"], **numbers)

    def parameters(self):
        corner, *numbers = fields(WheelUnbalance)
        return [ParameterSpec("corner", "|".join(corner.metadata["choices"]), math.nan, math.nan,
                              corner.metadata["meaning"])] + [
            ParameterSpec(f.name, f.metadata["unit"], f.metadata["low"], f.metadata["high"], f.metadata["meaning"])
            for f in numbers]

    def build(self, car, vehicle):
        import mujoco

        unbalance = vehicle.extensions[self.name]
        if unbalance.corner not in vehicle.corners:
            raise ValueError(f"[{self.name}] corner {unbalance.corner} is not a wheel of {vehicle.name}")
        radius = RIM_RADIUS_SHARE * vehicle.wheel_radius
        mass = unbalance.unbalance_kgm / radius
        angle = math.radians(unbalance.angle_deg)
        wheel = car.body(f"{unbalance.corner}/wheel")
        wheel.mass -= mass  # the unsprung mass stays the data sheet's
        rim = wheel.add_body(name=f"{unbalance.corner}/unbalance")
        rim.mass, rim.inertia, rim.explicitinertial = max(mass, 1e-9), [1e-9] * 3, True
        rim.ipos = [radius * math.sin(angle), 0.0, radius * math.cos(angle)]
        hinge = rim.add_joint(name=f"{unbalance.corner}/wheel_spin", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 1, 0])
        hinge.armature = WHEEL_INERTIA
        kp, kv = spin_gains(WHEEL_INERTIA + mass * radius**2)
        servo = car.add_actuator(name=SPIN_ACTUATOR.format(corner=unbalance.corner),
                                 target=f"{unbalance.corner}/wheel_spin")
        servo.trntype = mujoco.mjtTrn.mjTRN_JOINT
        servo.gainprm[0] = kp
        servo.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        servo.biasprm[:3] = [0.0, -kp, -kv]
        servo.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE
        rim.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.02, 0, 0], pos=rim.ipos, rgba=[0.9, 0.8, 0.1, 1.0],
                     contype=0, conaffinity=0, mass=0.0)

    def hidden(self, truth, rng):
        return with_extension(truth, self.name, WheelUnbalance(
            corner=str(rng.choice(truth.corners)), unbalance_kgm=rng.uniform(0.003, 0.015),
            angle_deg=rng.uniform(-180.0, 180.0)))


CAUSE = _WheelUnbalance()
