"""A truck: two or more ``[[axles]]`` at their own positions and tracks (rig/vehicle/truck_file.py), a corner per wheel
station each on a post of its own, the body a ladder frame carrying a cab and a driveline. The closed-form ride model
is a car's: its body heaves only here (rig.vehicle.statics.settle solves a truck's loads)."""

from rig.vehicle.layouts._base import Layout

LAYOUT = Layout(name="truck", corners_per_axle=2, axle_list=True, footprint=True, ride_motions=("heave",),
                frame=True)
