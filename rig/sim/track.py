"""Virtual test-track runs: the car driven over a road profile at constant speed.

Each wheel sees the road under its own contact point: the wheels behind the front axle the same track as the
fronts, as far behind as their axle (one wheelbase for a car's rear wheels; a truck's middle axles between). The
run replays those road heights on ideal posts (rig/sim/replay.py), so the responses come from the same model and
solver as a rig test, and the record carries the ``road`` channels next to the responses (an iteration target and
the ground truth for drive recovery).

What a track run ignores: longitudinal dynamics (no braking, traction or speed change, no pitch from
longitudinal forces), tyre slip and lateral forces, the tyre's contact-patch geometry beyond an optional
moving-average enveloping filter, road deformation, and steering (the car drives straight along the
profile). The car starts at rest at static ride height with its front wheels at the start of the road,
on flat ground; heights are taken relative to the road's start (mean of both tracks) and the road fades
in over ``fade_in`` metres so that the start is not a step.

The wheels roll: each corner's record carries its ``wheel_angle`` (rad, unwrapped, 0 with the wheel's mark at
the top, growing in the rolling direction), speed / rolling radius times time from the mark's angle at the
start. Rolling radii may differ per corner (tyre wear and pressure part them by a few tenths of a percent),
so the wheels turn at slightly different speeds; a wheel that can turn in the model (an unbalance,
rig/causes/wheel_unbalance.py) turns with its angle, already rolling at the start.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from rig.io.channels import channel
from rig.io.record import Record
from rig.road.roads import RoadError, RoadProfile
from rig.signal.filters import fade_window
from rig.sim.replay import ReplayResult, replay_batch
from rig.vehicle.vehicle_file import Vehicle


def envelope(track: np.ndarray, spacing: float, base: float) -> np.ndarray:
    """Moving average of ``track`` over ``base`` m: the simplest tyre-enveloping filter (odd window)."""
    width = max(1, int(round(base / spacing)))
    width += 1 - width % 2
    if width == 1:
        return track.copy()
    padded = np.pad(track, width // 2, mode="edge")
    return np.convolve(padded, np.ones(width) / width, mode="valid")


def check_speed(speed: float) -> None:
    """Refuse a speed that is not a positive number of m/s (RoadError)."""
    if not speed > 0:
        raise RoadError(f"speed must be positive (m/s), got {speed}")


def wheel_road_heights(vehicle: Vehicle, road: RoadProfile, speed: float, duration: float, rate: float,
                       envelope_base: float = 0.0, fade_in: float = 2.0) -> dict[str, np.ndarray]:
    """Road height (m) under each corner's contact point at ``rate`` Hz, front axle starting at distance 0."""
    check_speed(speed)
    samples = int(round(duration * rate))
    if samples < 2:
        raise RoadError(f"duration {duration} s gives fewer than two samples at {rate:g} Hz")
    if duration * speed > road.length + 1e-9:
        raise RoadError(f"road is {road.length:.2f} m long: at {speed:g} m/s it lasts {road.length / speed:.2f} s, "
                        f"not {duration:g} s")
    fade = fade_window(road.left.size, int(round(fade_in / road.spacing)), fade_out=False)
    datum = (road.left[0] + road.right[0]) / 2  # profiles carry absolute heights (a scan at 2.1 m, a survey at 583 m)
    front_distance = np.arange(samples) / rate * speed
    heights = {}
    for corner in vehicle.corners:
        side = "left" if corner.endswith("L") else "right"
        track = road.track(side) - datum
        if envelope_base > 0:
            track = envelope(track, road.spacing, envelope_base)
        offset = vehicle.cg_to_front_axle - vehicle.corner_position(corner)[0]  # m behind the front axle
        heights[corner] = np.interp(front_distance - offset, road.distance, track * fade, left=0.0)
    return heights


def rolling_radii(vehicle: Vehicle, radius: float | Mapping[str, float] | None = None) -> dict[str, float]:
    """Rolling radius (m) per corner: one for all, one per corner (others: the tyre's), or the vehicle's tyre."""
    if radius is None or isinstance(radius, Mapping):
        given = dict(radius or {})
        unknown = sorted(set(given) - set(vehicle.corners))
        if unknown:
            raise RoadError(f"rolling radius for {', '.join(unknown)}: {vehicle.name} has corners "
                            f"{', '.join(vehicle.corners)}")
        radii = {c: float(given.get(c, vehicle.wheel_radius)) for c in vehicle.corners}
    else:
        radii = {c: float(radius) for c in vehicle.corners}
    bad = {c: r for c, r in radii.items() if not 0.1 <= r <= 1.5}
    if bad:
        raise RoadError("rolling radius must lie in 0.1..1.5 m: " + ", ".join(f"{c} {r:g}" for c, r in bad.items()))
    return radii


def wheel_angles(vehicle: Vehicle, speed: float, samples: int, rate: float,
                 radius: float | Mapping[str, float] | None = None,
                 start: Mapping[str, float] | None = None) -> dict[str, np.ndarray]:
    """Each wheel's angle (rad, unwrapped) at constant ``speed``: ``start`` (the mark's angle at t = 0, default 0)
    plus speed / rolling radius times time."""
    time = np.arange(samples) / rate
    return {c: (start or {}).get(c, 0.0) + speed / r * time for c, r in rolling_radii(vehicle, radius).items()}


def track_run(vehicle: Vehicle, road: RoadProfile, speed: float, duration: float | None = None,
              rate: float = 512.0, envelope_base: float = 0.0, fade_in: float = 2.0,
              nthread: int | None = None, rolling_radius: float | Mapping[str, float] | None = None,
              start_angles: Mapping[str, float] | None = None) -> ReplayResult:
    """Drive ``vehicle`` over ``road`` at ``speed`` m/s; the default duration runs the front axle to the end.

    Returns the record of ``road``, ``wheel_angle`` and response channels per corner (no post channels) and the
    airborne time per tyre. ``envelope_base`` (m) applies a moving-average enveloping filter.
    ``rolling_radius`` (m, one or per corner; default the vehicle's tyre) and ``start_angles`` (rad per corner,
    default 0) set the wheels' angles.
    """
    return track_runs([vehicle], road, speed, duration, rate, envelope_base, fade_in, nthread, rolling_radius,
                      start_angles)[0]


def track_runs(vehicles: Sequence[Vehicle], road: RoadProfile, speed: float, duration: float | None = None,
               rate: float = 512.0, envelope_base: float = 0.0, fade_in: float = 2.0,
               nthread: int | None = None, rolling_radius: float | Mapping[str, float] | None = None,
               start_angles: Mapping[str, float] | None = None) -> list[ReplayResult]:
    """``track_run`` of several variants of one layout over the same road at the same speed, in one rollout."""
    check_speed(speed)
    duration = road.length / speed if duration is None else duration
    inputs, angles = [], []
    for vehicle in vehicles:
        heights = wheel_road_heights(vehicle, road, speed, duration, rate, envelope_base, fade_in)
        inputs.append(Record(rate, {channel(c, "actuator_disp"): h for c, h in heights.items()}))
        turning = wheel_angles(vehicle, speed, inputs[-1].n_samples, rate, rolling_radius, start_angles)
        angles.append(np.column_stack([turning[c] for c in vehicle.corners]))
    results = replay_batch(list(vehicles), inputs, nthread=nthread, limits=False, wheel_angles=np.stack(angles))
    runs = []
    for vehicle, result, turning in zip(vehicles, results, angles):
        channels = {}
        for name, values in result.record.channels.items():
            corner, quantity = name.split("/")
            if quantity == "actuator_disp":
                channels[channel(corner, "road")] = values
            elif quantity != "actuator_force":
                channels[name] = values
        for i, corner in enumerate(vehicle.corners):
            channels[channel(corner, "wheel_angle")] = turning[:, i]
        radii = rolling_radii(vehicle, rolling_radius)
        metadata = {"vehicle": vehicle.name, "test": "track", "speed": f"{speed:g} m/s", "road": road.provenance,
                    "rolling_radius": ", ".join(f"{c} {r:.6g} m" for c, r in radii.items())}
        if envelope_base > 0:
            metadata["envelope"] = f"moving average {envelope_base:g} m"
        runs.append(ReplayResult(Record(rate, channels, metadata=metadata), [], result.qpos, result.model))
    return runs
