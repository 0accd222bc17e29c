"""``anti_roll_bar``: roll stiffness coupling the left and right wheels of an axle.

    [anti_roll_bar.front]   # N/m of wheel force per m of left-right travel difference
    rate = 15000.0

Realised as a fixed tendon whose length is the left minus the right compression, linearised, with the bar's rate
as its stiffness: on the roll and wheel joints of vertical corners (track x roll - z_left + z_right), on the lower
arms' pivots of linkage corners (each arm's angle over its rate per m of travel at design), as the suspension
types give the joints (rig/vehicle/suspensions/).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, param


@dataclass(frozen=True)
class AntiRollBar:
    rate: float = field(metadata=param("N/m", 0.0, 5e5, "wheel force per m of left-right travel difference"))


class _AntiRollBar(AxleCause):
    name = "anti_roll_bar"
    subsystem = "car"
    values = AntiRollBar
    needs_both_sides = True
    meaning = "roll stiffness coupling left and right of an axle"
    signature = "the residual follows the left-right travel difference: roll and warp inputs, not heave"
    evidence = ("coupled to the other side",)

    def build(self, car, vehicle):
        from rig.vehicle.suspensions import travel_terms

        for axle, bar in vehicle.extensions.get(self.name, {}).items():
            left, right = ("FL", "FR") if axle == "front" else ("RL", "RR")
            coefficients = dict(travel_terms(vehicle, left))
            for joint, coefficient in travel_terms(vehicle, right).items():
                coefficients[joint] = coefficients.get(joint, 0.0) - coefficient
            tendon = car.add_tendon(name=f"{axle}/anti_roll_bar")
            for joint, coefficient in coefficients.items():
                if coefficient != 0.0:
                    tendon.wrap_joint(joint, coefficient)
            tendon.stiffness = [bar.rate, 0.0, 0.0]

    def fit_parameters(self, vehicle, hints=None):
        if vehicle.layout != "full":
            return []
        measured = (hints or {}).get("axle_coupling", {})  # from the measured force laws
        return [FitParameter(f"{a}_rate", min(max(measured.get(a, 2000.0), 0.0), 5e4), 0.0, 5e4,
                             lambda v, k, a=a: self.on_axle(v, a, AntiRollBar(k)))
                for a in ("front", "rear")]

    def hidden(self, truth, rng):
        front, rear = AntiRollBar(rng.uniform(10000.0, 20000.0)), AntiRollBar(rng.uniform(5000.0, 10000.0))
        return self.on_axle(self.on_axle(truth, "front", front), "rear", rear)


CAUSE = _AntiRollBar()
