"""Linkage cars in motion: loop closure over a random replay, the ride against the equivalent vertical car, and a
cause realised on a linkage corner with the same effect at the wheel as on a vertical one."""

from __future__ import annotations

import dataclasses
import tomllib

import mujoco
import numpy as np
import pytest
from scipy import signal

from rig.signal.filters import band_limited_noise
from rig.sim.kc import run_kc
from rig.sim.replay import Replayer
from rig.vehicle.vehicle_file import load_vehicle, resolve_vehicle_path, vehicle_from_dict
from rig.causes.bump_stop import BumpStop, CAUSE as BUMP_STOP

RATE = 512.0


def vertical_twin(vehicle):
    """The equivalent vertical car: the same file without its kinematics tables (rates and unsprung masses are at
    the wheel in both), its body site raised so that the vertical template's spring stays above the hub."""
    return dataclasses.replace(vehicle, cg_height=0.55, front=dataclasses.replace(vehicle.front, kinematics=None),
                               rear=dataclasses.replace(vehicle.rear, kinematics=None))


def parallel_arm_car():
    """fs_car with equal, parallel wishbones 0.2 m apart: a linkage whose wheel moves straight up at design."""
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())
    for axle in ("front", "rear"):
        points = table[axle]["kinematics"]
        for upper, lower in (("upper_front", "lower_front"), ("upper_rear", "lower_rear"),
                             ("upper_outer", "lower_outer")):
            points[upper] = [points[lower][0], points[lower][1], points[lower][2] + 0.2]
        points["tie_rod_inner"] = [points["tie_rod_inner"][0], points["lower_front"][1], points["tie_rod_inner"][2]]
    table["name"] = "fs_car_parallel_arms"
    return vehicle_from_dict(table)


def test_loops_stay_closed_over_a_random_replay():
    """20 s of 0.5-25 Hz random post drives (8 mm RMS, wheels lifting off): every ball joint and tie rod of the
    linkage stays closed within 1e-6 m, and no worse at the end than at the start."""
    vehicle = load_vehicle("fs_car")
    drive = band_limited_noise(20.0, RATE, (0.5, 25.0), 0.008, 4, seed=3)
    player = Replayer(vehicle, RATE)
    result = player.play(drive[None], clip=True)[0]
    assert min(result.record[f"{c}/tyre_force"].min() for c in vehicle.corners) == 0.0  # a hard run: lift-off
    model = player.simulators[0].rig.model
    data = mujoco.MjData(model)
    violation = np.empty(len(result.qpos))
    for k, qpos in enumerate(result.qpos):
        data.qpos[:] = qpos
        mujoco.mj_fwdPosition(model, data)
        violation[k] = np.abs(data.efc_pos[data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY]).max()
    assert violation.max() < 1e-6, violation.max()
    second = int(RATE)
    assert violation[-second:].max() < 2 * violation[:5 * second].max()  # no drift


def _heave_frfs(vehicle):
    one = band_limited_noise(64.0, RATE, (0.5, 40.0), 0.002, 1, seed=5)
    record = Replayer(vehicle, RATE, posts="ideal").play(np.repeat(one, 4, axis=1)[None])[0].record
    frequency, input_psd = signal.welch(one[:, 0], fs=RATE, nperseg=4096)
    out = {}
    for name in record.channels:
        if name.endswith(("/sprung_acc", "/unsprung_acc")):
            out[name] = signal.csd(one[:, 0], record[name], fs=RATE, nperseg=4096)[1] / input_psd
    return frequency, out


@pytest.mark.slow
@pytest.mark.parametrize("vehicle, tolerance", [(parallel_arm_car(), 0.02), (load_vehicle("fs_car"), 0.025)],
                         ids=["parallel_arms", "fs_car"])
def test_linkage_ride_matches_the_equivalent_vertical_car(vehicle, tolerance):
    """Small heave drives, 1-20 Hz: body and wheel FRFs of the linkage car and its vertical twin. Parallel arms
    (no camber or track change) agree within 0.5 %; fs_car within 2.4 % (its wheel centre moves 0.17 m sideways
    per m of travel, and the vertical model has no sideways motion; its FRFs differ most above wheel hop)."""
    frequency, linkage = _heave_frfs(vehicle)
    _, vertical = _heave_frfs(vertical_twin(vehicle))
    band = (frequency >= 1.0) & (frequency <= 20.0)
    worst = max(np.max(np.abs(linkage[n][band] - vertical[n][band]) / np.abs(vertical[n][band])) for n in linkage)
    assert worst < tolerance, worst


def test_a_bump_stop_acts_at_the_wheel_on_a_linkage_as_on_a_vertical_corner():
    """The bump stop (rig/causes/bump_stop.py) is a tendon from the body site to the hub: on the K&C rig it adds its
    rate at the wheel beyond its gap, on fs_car's linkage as on the vertical twin: within 0.4 % 5 mm into contact,
    1.2 % 15 mm into it (the linkage's hub moves sideways and tilts the tendon)."""
    vehicle = load_vehicle("fs_car")
    stop = BumpStop(gap=0.005, rate=60000.0)
    travel = np.linspace(-0.02, 0.02, 9)
    added = []
    for car in (vehicle, vertical_twin(vehicle)):
        with_stop = BUMP_STOP.on_every_axle(car, lambda axle, stop=stop: stop)
        plain, stopped = (run_kc(c, "travel", half_range=0.02, steps=9) for c in (car, with_stop))
        added.append(stopped.curves["FL/wheel_rate"] - plain.curves["FL/wheel_rate"])
    linkage, vertical = added
    beyond, before = travel > 0.0055, travel < 0.0045
    assert np.allclose(vertical[beyond], 60000.0, rtol=1e-3) and np.allclose(vertical[before], 0.0, atol=1.0)
    assert abs(linkage[beyond][0] / vertical[beyond][0] - 1) < 0.005
    assert np.allclose(linkage[beyond], vertical[beyond], rtol=0.015) and np.allclose(linkage[before], 0.0, atol=1.0)
