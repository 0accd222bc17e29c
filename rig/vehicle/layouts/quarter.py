"""A quarter car: one corner (``FL``) of ``[front]`` under the sprung mass, a body that only heaves."""

from rig.vehicle.layouts._base import Layout

LAYOUT = Layout(name="quarter", corners_per_axle=1, axle_list=False, footprint=False, ride_motions=("heave",),
                frame=False)
