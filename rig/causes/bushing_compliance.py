"""``bushing_compliance``: the bushings of a linkage are softer or stiffer than its vehicle file says (a kinematic
cause: seen on K&C compliance tests, rig/sim/kc.py), as the source paper ("Validation of a Suspension Model and its
Elastic Behaviour Demonstrated at the Formula Student Race Car of the University Duisburg-Essen") lumps the parts'
elasticity into the bearings and fits them to measured compliance.

    [bushing_compliance.front.lower_front]   # the rates that replace the file's (N/m; N m/rad)
    radial = 3.2e6

Realised by the suspension types, which build each joint with these rates (rig/vehicle/suspensions/bushings.py); the
K&C diagnosis fits it to compliance records (rig/diagnosis/kc/kinematic_diagnosis.py).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rig.causes._base import Cause, ParameterSpec, with_extension
from rig.elements.bushing_rates import RANGES, RATES, UNITS
from rig.io.channels import corner_axle
from rig.vehicle.suspensions.bushings import joints_of, with_rates


class _BushingCompliance(Cause):
    name = "bushing_compliance"
    subsystem = "car"
    seen_on = "kc"
    layouts = ("full",)
    meaning = "bushing rates of a linkage differ from its vehicle file"
    signature = "compliance steer, camber and wheel-centre motion under lateral, longitudinal and aligning loads off " \
                "the model's, beyond the rig's scatter"

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> dict[str, dict[str, dict[str, float]]]:
        if not isinstance(section, dict) or set(section) - set(axles):
            raise ValueError(f"{where}: [{self.name}] must hold [{self.name}.<axle>.<joint>] tables "
                             f"(axles: {', '.join(axles)})")
        out: dict[str, dict[str, dict[str, float]]] = {}
        for axle, joints in section.items():
            if not isinstance(joints, dict):
                raise ValueError(f"{where}: [{self.name}.{axle}] must hold one table per joint")
            for joint, rates in joints.items():
                table = f"[{self.name}.{axle}.{joint}]"
                if not isinstance(rates, dict) or set(rates) - set(RATES) or not rates:
                    raise ValueError(f"{where}: {table} must give rates among {', '.join(RATES)}")
                out.setdefault(axle, {})[joint] = {rate: _rate(value, f"{where}: {table} {rate}", rate)
                                                   for rate, value in rates.items()}
        return out

    def to_table(self, value: dict) -> dict:
        return {axle: {joint: dict(rates) for joint, rates in joints.items()} for axle, joints in value.items()}

    def check(self, vehicle) -> None:
        super().check(vehicle)
        for axle, joints in vehicle.extensions[self.name].items():
            kinematics = vehicle.axle_named(axle).kinematics
            if kinematics is None:
                raise ValueError(f"{vehicle.source}: [{self.name}.{axle}] needs the linkage's [{axle}.kinematics]")
            unknown = sorted(set(joints) - set(joints_of(kinematics)))
            if unknown:
                raise ValueError(f"{vehicle.source}: [{self.name}.{axle}] {', '.join(unknown)}: not a joint of the "
                                 f"{axle} {kinematics.type} (joints: {', '.join(joints_of(kinematics))})")

    def parameters(self) -> list[ParameterSpec]:
        return [ParameterSpec(f"<joint>.{rate}", UNITS[rate], *RANGES[rate],
                              f"the joint's {rate} rate in place of the vehicle file's") for rate in RATES]

    def adjust_kinematics(self, vehicle, corner, kinematics):
        joints = vehicle.extensions.get(self.name, {}).get(corner_axle(corner), {})
        rates = {(joint, rate): value for joint, values in joints.items() for rate, value in values.items()}
        return with_rates(kinematics, rates) if rates else kinematics

    def hidden(self, truth, rng):
        """The front lower arm's pivots' radial rates scaled by 0.5-2 each (the file must give them)."""
        kinematics = truth.front.kinematics
        pivots = [j for j in ("lower_front", "lower_rear") if kinematics is not None and j in kinematics.bushings
                  and np.isfinite(kinematics.bushings[j].radial)]
        if not pivots:
            raise ValueError(f"[{self.name}] needs bushed pivots of the front lower arm; {truth.name} has none")
        return with_extension(truth, self.name, {"front": {
            j: {"radial": float(kinematics.bushings[j].radial * np.exp(rng.uniform(np.log(0.5), np.log(2.0))))}
            for j in pivots}})


def _rate(value: object, where: str, rate: str) -> float:
    low, high = RANGES[rate]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
        raise ValueError(f"{where} must be a rate within {low:g}..{high:g}, got {value!r}")
    return float(value)


CAUSE = _BushingCompliance()
