"""International Roughness Index (IRI), computed with the project's own quarter-car model.

ASTM E1926 / Sayers' golden quarter car: per unit sprung mass k_t = 653 s^-2, k_s = 63.3 s^-2,
c_s = 6.0 s^-1, unsprung mass 0.15; driven at 80 km/h over the profile smoothed by a 250 mm moving
average; IRI is the average rectified suspension velocity over the speed (slope, m/km). Here the golden
car is a quarter-car vehicle (250 kg sprung mass: the IRI does not depend on it) simulated by
rig/sim/replay.py on ideal posts. The standard's initial state (the car at rest relative to a road of the
slope of the first 11 m) is reproduced by a lead-in ramp of that slope, long enough for the start
transient to die out; like the standard's state-transition solution, the profile runs straight between
samples (linear interpolation: a cubic spline gave 2-3 % more on road_profile_1.txt). The profile is scaled down while
simulating so the tyre never leaves the ground (the golden car is linear), and the IRI scaled back.
"""

from __future__ import annotations

import numpy as np

from rig.io.channels import channel
from rig.io.record import Record
from rig.sim.replay import replay
from rig.sim.track import envelope
from rig.vehicle.vehicle_file import Vehicle, vehicle_from_dict

GOLDEN_SPEED = 80.0 / 3.6  # m/s
_GOLDEN_SPRUNG_MASS = 250.0  # kg, arbitrary: the golden car is defined per unit sprung mass
_SMOOTHING_BASE = 0.25  # m, moving-average tyre filter
_INITIAL_SLOPE_LENGTH = 11.0  # m
_LEAD_IN = 100.0  # m of constant-slope road before the profile: 4.5 s, the start transient decays by e^-13
_SCALE = 0.1  # profile scale while simulating (linear model: keeps the tyre in contact)


def golden_quarter_car() -> Vehicle:
    """The IRI reference quarter car (ASTM E1926) as a quarter-car vehicle file."""
    m = _GOLDEN_SPRUNG_MASS
    return vehicle_from_dict({
        "name": "golden_quarter_car", "layout": "quarter",
        "geometry": {"wheel_radius": 0.30},
        "sprung": {"mass": m},
        "front": {"unsprung_mass": 0.15 * m, "spring_rate": 63.3 * m, "damping": 6.0 * m, "tyre_rate": 653.0 * m},
    }, "golden quarter car (ASTM E1926)")


def iri(elevation: np.ndarray, spacing: float, segment: float = 100.0) -> np.ndarray:
    """IRI in m/km of each full ``segment``-metre section of a longitudinal profile, from its first sample."""
    elevation = np.asarray(elevation, dtype=float)
    per_segment = int(round(segment / spacing))
    if elevation.size < per_segment:
        raise ValueError(f"profile of {elevation.size * spacing:.1f} m is shorter than one {segment:g} m segment")
    smoothed = envelope(elevation, spacing, _SMOOTHING_BASE)
    start = int(round(_INITIAL_SLOPE_LENGTH / spacing))
    slope = (smoothed[start] - smoothed[0]) / (start * spacing)
    lead = np.arange(-int(round(_LEAD_IN / spacing)), 0) * spacing * slope + smoothed[0]
    road = (np.concatenate([lead, smoothed]) - lead[0]) * _SCALE
    rate = GOLDEN_SPEED / spacing
    result = replay(golden_quarter_car(), Record(rate, {channel("FL", "actuator_disp"): road}), limits=False,
                    interpolation="linear")  # the standard's profile is straight between samples
    slope_difference = np.abs(result.record["FL/susp_velocity"][lead.size:]) / GOLDEN_SPEED / _SCALE
    n_segments = elevation.size // per_segment
    return np.array([slope_difference[i * per_segment:(i + 1) * per_segment].mean() for i in range(n_segments)]) * 1e3
