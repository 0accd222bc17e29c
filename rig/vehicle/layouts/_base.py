"""What a layout is: one object per layout module, ``LAYOUT``, that says what the code would otherwise ask of the
vehicle file's ``layout`` name: how many corners an axle has, whether the axles come from ``[[axles]]``, whether the
body has a wheelbase and tracks, its motions in the closed-form ride model and whether it rides on a frame."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Layout:
    """One layout; code asks it (``Vehicle.layout_type``), never compares the vehicle's ``layout`` name."""

    name: str  # the vehicle file's ``layout`` value (docs/contracts.md)
    corners_per_axle: int  # 1: a quarter car's one corner; 2: left and right
    axle_list: bool  # axles from ``[[axles]]`` at their own positions and tracks (rig/vehicle/truck_file.py), each
    # corner a post of its own; else ``[front]`` (and ``[rear]``) on the template car's corners
    footprint: bool  # the body has a wheelbase and tracks (``[geometry]``, pitch and roll inertia, the MJCF body's
    # pitch and roll joints); without one its corner sits under the CG
    #: the body's motions in the closed-form ride model (rig/vehicle/ride_model.py) and in what writes a corner's
    #: compression or places a mass on the body from them: a full car's heave, pitch and roll, else heave
    ride_motions: tuple[str, ...]
    frame: bool  # the body is a ladder frame (rigid or flexible, rig/elements/frame.py) carrying mounted bodies

    @property
    def pitches_and_rolls(self) -> bool:
        """Whether the ride model's body pitches and rolls: a mass on it has an x and y, an axle a roll coupling."""
        return "pitch" in self.ride_motions and "roll" in self.ride_motions
