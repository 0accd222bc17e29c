"""``anti_roll_bar``: roll stiffness coupling the left and right wheels of an axle.

    [anti_roll_bar.front]   # N/m of wheel force per m of left-right travel difference
    rate = 15000.0

Realised as a fixed tendon on the roll and wheel joints whose length is the left minus the right
compression (linearised: track x roll - z_left + z_right), with the bar's rate as its stiffness.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rig.causes._base import AxleCause, FitParameter, Shape, param


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
    evidence = (Shape.COUPLED,)

    def build(self, car, vehicle):
        for axle, bar in vehicle.extensions.get(self.name, {}).items():
            left, right = ("FL", "FR") if axle == "front" else ("RL", "RR")
            track = vehicle.track_front if axle == "front" else vehicle.track_rear
            tendon = car.add_tendon(name=f"{axle}/anti_roll_bar")
            tendon.wrap_joint("roll", track)
            tendon.wrap_joint(f"{left}/wheel", -1.0)
            tendon.wrap_joint(f"{right}/wheel", 1.0)
            tendon.stiffness = [bar.rate, 0.0, 0.0]

    def fit_parameters(self, vehicle, hints=None):
        if vehicle.layout != "full":
            return []
        measured = (hints or {}).get("axle_coupling", {})  # from the measured force laws
        return [FitParameter(f"{a}_rate", min(max(measured.get(a, 2000.0), 0.0), 5e4), 0.0, 5e4,
                             lambda v, k, a=a: self.on_axle(v, a, AntiRollBar(k)), unit="N/m")
                for a in ("front", "rear")]

    def hidden(self, truth, rng):
        front, rear = AntiRollBar(rng.uniform(10000.0, 20000.0)), AntiRollBar(rng.uniform(5000.0, 10000.0))
        return self.on_axle(self.on_axle(truth, "front", front), "rear", rear)


CAUSE = _AntiRollBar()
