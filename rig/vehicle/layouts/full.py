"""A full car: two axles ``[front]`` and ``[rear]`` at its ``[geometry]``'s wheelbase and tracks, four corners, a body
that heaves, pitches and rolls (the vehicle file's default layout)."""

from rig.vehicle.layouts._base import Layout

LAYOUT = Layout(name="full", corners_per_axle=2, axle_list=False, footprint=True,
                ride_motions=("heave", "pitch", "roll"), frame=False)
