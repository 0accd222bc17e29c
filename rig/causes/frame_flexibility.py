"""``frame_flexibility``: a truck's frame bends and twists where the model's is rigid (or stiffer, or softer).

    [frame_flexibility]      # the frame as segments on bending and torsion springs (rig/elements/frame.py)
    length = 7.85            # m
    front_overhang = 1.40    # m ahead of the front axle
    bending_frequency = 8.0  # Hz, first free-free bending mode of the loaded frame
    torsion_frequency = 5.0  # Hz, first free-free torsion mode
    damping_ratio = 0.03
    segments = 8

Realised by the MJCF builder through ``adjust_frame``: the vehicle's frame is this one, read as a ``[frame]`` table
(EI and GJ from the frequencies for its sprung mass and roll inertia spread along the length). Trucks only.

The diagnosis fits the two frequencies from where the data put the modes (rig/diagnosis/rig_test/modes.py): the frame
twists
in the posts' warp pattern and bends in their heave pattern, so the model's torsion frequency times the measured warp
peak over the model's, and its bending frequency times the heave peaks' ratio, start the fit (the measured peaks
themselves where the model's frame is rigid). A fit started at the model's own frame gains nothing: the TDDI of a
resonance at the wrong frequency has minima on either side of the right one. The recalibration, fitted before any
cause, bends the linear factors to absorb a frame it lacks, so the frame is fitted jointly with them from the data
sheet's values (``measured_start``): from the recalibrated ones, four evaluations left 30 times the noise floor
(bending at 11.05 Hz for 11.15) and a spurious resonator was named beside the frame.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rig.causes._base import CarCause, FitParameter, with_extension
from rig.elements.parameters import param


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
    layouts = ("truck",)
    values = FrameFlexibility
    order = 5
    fine_step = True  # a stiffer frame's zig-zag chain modes outrun a longer step (rig/sim/step_size.py)
    measured_start = True  # the recalibration bent the linear factors to absorb the frame: refitted from the sheet's
    meaning = "the frame bends and twists: modes the rigid (or stiffer) frame of the model lacks"
    signature = "resonances of the residual body accelerations at the frame's torsion and bending modes, front and "\
                "rear out of phase"

    def adjust_frame(self, vehicle, frame):
        """The frame as a ``[frame]`` table (rig/elements/frame.py reads it)."""
        flex = vehicle.extensions[self.name]
        return {**dataclasses.asdict(flex), "segments": int(flex.segments)}

    def fit_parameters(self, vehicle, hints=None):
        if not vehicle.layout_type.frame:
            return []
        start = vehicle.extensions.get(self.name) or self.from_vehicle(vehicle)
        peaks = (hints or {}).get("pattern_peaks") or {}
        rigid = self.name not in vehicle.extensions and vehicle.frame is None
        torsion, bending = (self.from_peak(peaks.get(pattern), model, rigid) for pattern, model in (
            ("warp", start.torsion_frequency), ("heave", start.bending_frequency)))
        return [FitParameter("torsion_frequency", min(max(torsion, 2.0), 30.0), 2.0, 30.0,
                             self.field_setter("torsion_frequency", start), typical=2.0, unit="Hz"),
                FitParameter("bending_frequency", min(max(bending, 2.0), 40.0), 2.0, 40.0,
                             self.field_setter("bending_frequency", start), typical=2.0, unit="Hz")]

    @staticmethod
    def from_peak(peak, model: float, rigid: bool) -> float:
        """A mode's start (Hz): the model's free-free frequency moved as the measured peak lies from the model's
        (within a factor 2), the measured peak itself where the model's frame is rigid, the model's without a peak."""
        if peak is None:
            return model
        return peak.measured_hz if rigid else model * min(max(peak.ratio, 0.5), 2.0)

    def from_vehicle(self, vehicle) -> FrameFlexibility:
        """The vehicle's own frame as this cause's section (a rigid frame: 30 Hz modes over wheelbase + 2.5 m)."""
        frame = vehicle.frame
        if frame is None:
            return FrameFlexibility(vehicle.wheelbase + 2.5, 1.2, 30.0, 30.0)
        return FrameFlexibility(frame.length, frame.front_overhang, frame.bending_frequency(vehicle.sprung_mass),
                                frame.torsion_frequency(vehicle.roll_inertia), frame.damping_ratio,
                                float(frame.segments))

    def hidden(self, truth, rng):
        if not truth.layout_type.frame:
            raise ValueError(f"{truth.name} is not a truck: it has no frame to flex")
        start = self.from_vehicle(truth)
        return with_extension(truth, self.name, dataclasses.replace(
            start, bending_frequency=rng.uniform(8.0, 12.0), torsion_frequency=rng.uniform(4.5, 8.0)))


CAUSE = _FrameFlexibility()
