"""The nonlinear car of the drive-estimation tests and benchmark, measured by the independent simulator.

proton_x with dampers 2.2 times stiffer in rebound than in compression (their mean the data sheet's) and a
progressive spring (cubic, 1e8 N/m^3: at 20 mm of travel it adds 800 N to the linear 580 N), simulated by
tests/independent_rig.py (not the project's simulator). Records: a 60 s pink-noise identification run
(8 mm RMS per post: training data) and an unseen 20 s target, the road under each wheel of an ISO 8608 class
C road at 20 m/s, with measurement noise of 0.5 % of each response's RMS (white: below 1 Hz it swamps the
displacement the accelerations say, so the drive error there grows with it). The same car as a vehicle file
(the ``damper_asymmetry`` and ``progressive_spring`` sections) is the virtual rig iteration runs on.

The independent large-event case (``independent_large_event_records``), built as the issue on generalisation
describes a case the project did not tune on: dampers at 0.6 of the data sheet's in compression and 1.5 in rebound,
a cubic spring of 1.5e8 N/m^3, 1 % noise, a 60 s identification run of pink noise alone (6 mm RMS per post,
0.3-40 Hz: no events) and an unseen 20 s target with six large road events: the target takes the suspension where
the identification never went.

The large-event case (``large_event_records``): the same car, 1 % noise, and both records a broadband drive with
six large road events (``large_event_drive``: pink noise, 4 mm RMS per post, 0.3-40 Hz, and half-sine bumps and
holes of 24-40 mm over 0.1-0.25 s on single posts, axles and sides): a 60 s training run and an unseen 20 s
target, whose events lift the tyres off the posts and compress the springs to 25-34 mm, where the cubic term is
more than twice the linear.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from independent_rig import Car, Hidden, Simulator, rig_records

from rig.causes.damper_asymmetry import split
from rig.causes.progressive_spring import ProgressiveSpring
from rig.io.record import Record
from rig.road.roads import iso8608_road
from rig.signal.filters import band_limited_noise, band_pass, fade_window
from rig.vehicle.vehicle_file import Vehicle

RATE = 512.0
RATIO = 2.2        # rebound / compression damping
CUBIC = 1.0e8      # N/m^3
SPEED = 20.0       # m/s


def nonlinear_vehicle(baseline: Vehicle) -> Vehicle:
    """``baseline`` with the asymmetric dampers and progressive springs of the independent simulator's car."""
    extensions = {"damper_asymmetry": {"front": split(baseline.front.damping, RATIO),
                                       "rear": split(baseline.rear.damping, RATIO)},
                  "progressive_spring": {axle: ProgressiveSpring(cubic=CUBIC) for axle in ("front", "rear")}}
    return dataclasses.replace(baseline, name=f"{baseline.name}_progressive_asymmetric", extensions=extensions)


def road_drive(vehicle: Vehicle, duration: float, seed: int) -> np.ndarray:
    """Post drives (samples x corners, m): an ISO 8608 class C road under each wheel at SPEED, in 0.5-40 Hz,
    faded in and out over 1 s (a rig test starts and ends at rest)."""
    road = iso8608_road("C", SPEED * duration + vehicle.wheelbase + 20.0, seed=seed)
    distance = SPEED * np.arange(int(round(duration * RATE))) / RATE + vehicle.wheelbase + 10.0
    fronts = [np.interp(distance, road.distance, road.track(side)) for side in ("left", "right")]
    rears = [np.interp(distance - vehicle.wheelbase, road.distance, road.track(side)) for side in ("left", "right")]
    drive = band_pass(np.column_stack(fronts + rears), RATE, (0.5, 40.0))
    return drive * fade_window(drive.shape[0], int(RATE))[:, None]


def measured_records(baseline: Vehicle, seed: int = 0, noise: float = 0.005,
                     nonlinear: bool = True) -> tuple[Record, Record]:
    """(training record: 60 s pink noise, target: 20 s of road), both with drives, measured by the
    independent simulator on the nonlinear car (or on ``baseline`` itself)."""
    hidden = Hidden(cubic_spring=CUBIC, damper_ratio=RATIO) if nonlinear else Hidden()
    sim = Simulator(Car.from_vehicle(baseline), hidden)
    rng = np.random.default_rng(seed)
    train = band_limited_noise(60.0, RATE, (0.3, 40.0), 0.008, 4, seed=seed, slope=1.0)
    target = road_drive(baseline, 20.0, seed + 1)
    return tuple(rig_records(sim, [train, target], RATE, rng, noise))


def large_event_drive(duration: float, seed: int, rms: float = 0.004, events: int = 6,
                      amplitude: float = 0.04) -> np.ndarray:
    """Post drives (samples x corners, m): pink noise (``rms`` per post, 0.3-40 Hz) with ``events`` half-sine bumps
    and holes of 0.6-1 times ``amplitude`` on single posts, an axle or a side, faded in and out over 1 s."""
    rng = np.random.default_rng(seed)
    drive = band_limited_noise(duration, RATE, (0.3, 40.0), rms, 4, seed, slope=1.0)
    time = np.arange(drive.shape[0]) / RATE
    for start in np.linspace(1.5, duration - 2.0, events) + rng.uniform(-0.5, 0.5, events):
        width = rng.uniform(0.1, 0.25)
        height = rng.choice([-1, 1]) * rng.uniform(0.6, 1.0) * amplitude
        hit = [[0], [1], [2], [3], [0, 1], [2, 3], [0, 2], [1, 3]][int(rng.integers(8))]
        drive[:, hit] += (height * np.sin(np.pi * np.clip((time - start) / width, 0, 1)))[:, None]
    return drive * fade_window(drive.shape[0], int(RATE))[:, None]


def large_event_records(baseline: Vehicle, seed: int = 0, noise: float = 0.01) -> tuple[Record, Record]:
    """(training record: 60 s, target: 20 s), both broadband drives with six large road events, measured by the
    independent simulator on the nonlinear car with ``noise`` (of each response's RMS)."""
    sim = Simulator(Car.from_vehicle(baseline), Hidden(cubic_spring=CUBIC, damper_ratio=RATIO))
    rng = np.random.default_rng(seed)
    return tuple(rig_records(sim, [large_event_drive(60.0, seed), large_event_drive(20.0, seed + 1)], RATE, rng, noise))


INDEPENDENT_CUBIC = 1.5e8           # N/m^3
INDEPENDENT_FACTORS = (0.6, 1.5)    # compression, rebound damping over the data sheet's


def independent_large_event_records(baseline: Vehicle, seed: int = 0, noise: float = 0.01,
                                    cubic: float = INDEPENDENT_CUBIC,
                                    factors: tuple[float, float] = INDEPENDENT_FACTORS) -> tuple[Record, Record]:
    """(identification run: 60 s of pink noise, target: 20 s with six large road events), measured by the
    independent simulator on the car with asymmetric dampers (``factors``: compression, rebound) and a cubic spring
    (``cubic``, N/m^3), with ``noise``."""
    sim = Simulator(Car.from_vehicle(baseline), Hidden(cubic_spring=cubic, damper_factors=factors))
    rng = np.random.default_rng(seed)
    identification = band_limited_noise(60.0, RATE, (0.3, 40.0), 0.006, 4, seed=seed + 7, slope=1.0)
    return tuple(rig_records(sim, [identification, large_event_drive(20.0, seed + 11)], RATE, rng, noise))
