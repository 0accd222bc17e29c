"""``anti_roll_bar``: roll stiffness coupling the left and right wheels of an axle.

    [anti_roll_bar.front]   # N/m of wheel force per m of left-right travel difference
    rate = 15000.0

Realised as a fixed tendon whose length is the left minus the right compression, linearised, with the bar's rate
as its stiffness: on the roll and wheel joints of vertical corners (track x roll - z_left + z_right), on the lower
arms' pivots of linkage corners (each arm's angle times the travel per radian at design, which the linkage's builder
keeps in the pivot joint's userdata, rig/vehicle/suspensions/linkage.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape
from rig.elements.parameters import param
from rig.io.channels import axle_corners


@dataclass(frozen=True)
class AntiRollBar:
    rate: float = field(metadata=param("N/m", 0.0, 5e5, "wheel force per m of left-right travel difference"))


def compression_terms(car, vehicle, corner: str) -> dict[str, float]:
    """Joint -> coefficient whose weighted sum is the corner's compression (m) relative to the body, linearised."""
    arm = car.joint(f"{corner}/lower_arm")
    if arm is not None:  # a linkage corner
        return {f"{corner}/lower_arm": float(arm.userdata[0])}
    x, y = vehicle.corner_position(corner)
    body = {"heave": 1.0, "pitch": -x, "roll": y} if vehicle.layout_type.pitches_and_rolls else {"heave": 1.0}
    return {**body, f"{corner}/wheel": -1.0}


class _AntiRollBar(AxleCause):
    name = "anti_roll_bar"
    subsystem = "car"
    linear = True
    values = AntiRollBar
    needs_both_sides = True
    meaning = "roll stiffness coupling left and right of an axle"
    signature = "the residual follows the left-right travel difference: roll and warp inputs, not heave"
    evidence = (Shape.COUPLED,)

    def build(self, car, vehicle):
        for axle, bar in vehicle.extensions.get(self.name, {}).items():
            left, right = axle_corners(axle)
            coefficients = compression_terms(car, vehicle, left)
            for joint, coefficient in compression_terms(car, vehicle, right).items():
                coefficients[joint] = coefficients.get(joint, 0.0) - coefficient
            tendon = car.add_tendon(name=f"{axle}/anti_roll_bar")
            for joint, coefficient in coefficients.items():
                if coefficient != 0.0:
                    tendon.wrap_joint(joint, coefficient)
            tendon.stiffness = [bar.rate, 0.0, 0.0]

    def fit_parameters(self, vehicle, hints=None):
        if not vehicle.layout_type.pitches_and_rolls:
            return []
        measured = (hints or {}).get("axle_coupling", {})  # from the measured force laws
        return [FitParameter(f"{a}_rate", min(max(measured.get(a, 2000.0), 0.0), 5e4), 0.0, 5e4,
                             lambda v, k, a=a: self.on_axle(v, a, AntiRollBar(k)), unit="N/m")
                for a in ("front", "rear")]

    def hidden(self, truth, rng):
        front, rear = AntiRollBar(rng.uniform(10000.0, 20000.0)), AntiRollBar(rng.uniform(5000.0, 10000.0))
        return self.on_axle(self.on_axle(truth, "front", front), "rear", rear)


CAUSE = _AntiRollBar()
