"""``frame_flexibility``: a truck's frame bends and twists where the model's is rigid (or stiffer, or softer).

    [frame_flexibility]      # the frame as segments on bending and torsion springs (rig/vehicle/frame.py)
    length = 7.85            # m
    front_overhang = 1.40    # m ahead of the front axle
    bending_frequency = 8.0  # Hz, first free-free bending mode of the loaded frame
    torsion_frequency = 5.0  # Hz, first free-free torsion mode
    damping_ratio = 0.03
    segments = 8

Realised by the MJCF builder through ``adjust_frame``: the vehicle's frame is this one (EI and GJ from the
frequencies for its sprung mass and roll inertia spread along the length). Trucks only.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rig.causes._base import CarCause, FitParameter, param, with_extension
from rig.vehicle.frame import Frame, bending_stiffness_for, torsion_stiffness_for


@dataclass(frozen=True)
class FrameFlexibility:
    length: float = field(metadata=param("m", 1.0, 25.0, "frame length"))
    front_overhang: float = field(metadata=param("m", 0.0, 5.0, "frame front end ahead of the front axle"))
    bending_frequency: float = field(metadata=param("Hz", 1.0, 60.0, "first free-free bending mode"))
    torsion_frequency: float = field(metadata=param("Hz", 1.0, 60.0, "first free-free torsion mode"))
    damping_ratio: float = field(default=0.03, metadata=param("-", 0.0, 0.5, "of each kind's first mode"))
    segments: float = field(default=8.0, metadata=param("-", 2.0, 60.0, "number of rigid segments"))


class _FrameFlexibility(CarCause):
    name = "frame_flexibility"
    subsystem = "car"
    seen_on = "truck"
    layouts = ("truck",)
    values = FrameFlexibility
    order = 5
    meaning = "the frame bends and twists: modes the rigid (or stiffer) frame of the model lacks"
    signature = "resonances of the residual body accelerations at the frame's torsion and bending modes, front and "\
                "rear out of phase"

    def check(self, vehicle):
        super().check(vehicle)
        from rig.vehicle.frame import segments_of

        try:
            segments_of(self.adjust_frame(vehicle, vehicle.frame), vehicle.cg_to_front_axle, vehicle.sprung_mass,
                        vehicle.roll_inertia, vehicle.pitch_inertia)
        except ValueError as err:
            raise ValueError(f"{vehicle.source}: [frame_flexibility] {err}") from None

    def adjust_frame(self, vehicle, frame):
        flex = vehicle.extensions[self.name]
        return Frame(length=flex.length, front_overhang=flex.front_overhang,
                     bending_stiffness=bending_stiffness_for(flex.bending_frequency, vehicle.sprung_mass, flex.length),
                     torsion_stiffness=torsion_stiffness_for(flex.torsion_frequency, vehicle.roll_inertia,
                                                             flex.length),
                     segments=int(flex.segments), damping_ratio=flex.damping_ratio)

    def fit_parameters(self, vehicle, hints=None):
        if vehicle.layout != "truck":
            return []
        start = vehicle.extensions.get(self.name) or self.from_vehicle(vehicle)
        peak = (hints or {}).get("peak_hz")
        torsion = min(max(peak, 2.0), 30.0) if peak else start.torsion_frequency
        return [FitParameter("torsion_frequency", torsion, 2.0, 30.0, self.field_setter("torsion_frequency", start),
                             typical=2.0),
                FitParameter("bending_frequency", start.bending_frequency, 2.0, 40.0,
                             self.field_setter("bending_frequency", start), typical=2.0)]

    def from_vehicle(self, vehicle) -> FrameFlexibility:
        """The vehicle's own frame as this cause's section (a rigid frame: 30 Hz modes over wheelbase + 2.5 m)."""
        frame = vehicle.frame
        if frame is None:
            return FrameFlexibility(vehicle.wheelbase + 2.5, 1.2, 30.0, 30.0)
        mass, roll, length = vehicle.sprung_mass, vehicle.roll_inertia, frame.length
        bending = (frame.bending_stiffness / bending_stiffness_for(1.0, mass, length)) ** 0.5
        torsion = (frame.torsion_stiffness / torsion_stiffness_for(1.0, roll, length)) ** 0.5
        return FrameFlexibility(length, frame.front_overhang, bending, torsion, frame.damping_ratio,
                                float(frame.segments))

    def hidden(self, truth, rng):
        if truth.layout != "truck":
            raise ValueError(f"{truth.name} is not a truck: it has no frame to flex")
        start = self.from_vehicle(truth)
        return with_extension(truth, self.name, dataclasses.replace(
            start, bending_frequency=rng.uniform(8.0, 12.0), torsion_frequency=rng.uniform(4.5, 8.0)))


CAUSE = _FrameFlexibility()
