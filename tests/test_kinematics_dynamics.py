"""Linkage cars in motion: loop closure over a random replay, the ride against the equivalent vertical car, and a
cause realised on a linkage corner with the same effect at the wheel as on a vertical one."""

from __future__ import annotations

import tomllib

import mujoco
import numpy as np
import pytest
from scipy import signal
from scipy.linalg import null_space

from support.linkage_cars import MACPHERSON_CAR, parallel_arm_car

from rig.signal.filters import band_limited_noise
from rig.sim.kc import run_kc
from rig.sim.replay import Replayer
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle, vehicle_from_dict
from rig.vehicle.vertical_equivalent import vertical_equivalent
from rig.causes.bump_stop import BumpStop, CAUSE as BUMP_STOP

RATE = 512.0


def test_loops_stay_closed_over_a_random_replay():
    """20 s of 0.5-25 Hz random post drives (8 mm RMS, wheels lifting off): every ball joint, tie rod and pushrod of
    the linkage stays closed within 2e-6 m, and no worse at the end than at the start. Measured: the rear pushrods
    1.2e-6 m (the most loaded link, on the light rocker: a soft constraint yields by its force times the bodies'
    inverse mass), the tie rods and ball joints 3.7e-7 m."""
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
    assert violation.max() < 2e-6, violation.max()
    second = int(RATE)
    assert violation[-second:].max() < 2 * violation[:5 * second].max()  # no drift


def test_the_vertical_equivalent_has_the_linkage_cars_inertia():
    """vertical_equivalent's kinetic-energy sums against MuJoCo's own inertia of the compiled linkage car: its mass
    matrix at design projected onto the loops' closed motions (the null space of the equality constraints) in the
    vertical model's coordinates (heave, pitch, roll, each wheel's travel relative to the body). There the
    equivalent car has the frozen car's inertia, sprung + c at each hub, on the body's diagonal, c + b at the wheels
    (the vehicle file's unsprung mass), c (heave), -c x (pitch) and c y (roll) between body and wheel. fs_car: c = 9.60
    kg and b = 0.40 kg front, 9.53 and 0.47 kg rear (where the rocker turns: its kinetic energy is all in b)."""
    vehicle = load_vehicle("fs_car")
    equivalent = vertical_equivalent(vehicle)
    twin = equivalent.vehicle
    vertical = np.array([equivalent.corners[c].vertical_mass for c in vehicle.corners])
    model = build_model(vehicle, RATE, posts="ideal").model
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    inertia = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, inertia)
    closed = null_space(data.efc_J.reshape(data.nefc, model.nv)[data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY])
    rows = [np.eye(model.nv)[model.joint(f"car.{j}").dofadr[0]] for j in ("heave", "pitch", "roll", "front/rack")]
    for corner in vehicle.corners:
        hub, body = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, hub, None, model.site(f"car.{corner}/hub").id)
        mujoco.mj_jacSite(model, data, body, None, model.site(f"car.{corner}/body").id)
        rows.append(hub[2] - body[2])  # travel: the hub's height relative to the body (level at design)
    to_joints = closed @ np.linalg.inv(np.array(rows) @ closed)
    reduced = to_joints.T @ inertia @ to_joints
    x = np.array([vehicle.corner_position(c)[0] for c in vehicle.corners])
    y = np.array([vehicle.corner_position(c)[1] for c in vehicle.corners])
    frozen = [twin.sprung_mass + vertical.sum(), twin.pitch_inertia + vertical @ x**2,
              twin.roll_inertia + vertical @ y**2]
    assert np.allclose(np.diag(reduced)[:3], frozen, rtol=0.0, atol=1.1e-3)  # but the rack's own 1e-3 kg m^2
    assert np.allclose(np.diag(reduced)[4:], vehicle.front.unsprung_mass, rtol=1e-5)  # c + b (design: 1 mm differences)
    assert np.allclose(reduced[0, 4:], vertical, rtol=1e-5)
    assert np.allclose(reduced[1, 4:], -vertical * x, rtol=0.005)  # the parts' fore-aft motion aside
    assert np.allclose(reduced[2, 4:], vertical * y, rtol=0.025)  # not in the equivalent: 1.8 % more, 1.9 % rear
    inerters = np.array(list(equivalent.inerters.values()))
    assert np.allclose(inerters, [0.403, 0.403, 0.474, 0.474], atol=1e-3)


def _heave_frfs(vehicle, extend=None):
    """Body and wheel FRFs (m/s^2 per m) for 64 s of 0.5-40 Hz random heave at 0.5 mm RMS on ideal posts, the tyres
    never lifting off (in the linear range), and the lowest tyre force (N)."""
    one = band_limited_noise(64.0, RATE, (0.5, 40.0), 0.0005, 1, seed=5)
    record = Replayer(vehicle, RATE, posts="ideal", extend=extend).play(np.repeat(one, 4, axis=1)[None])[0].record
    frequency, input_psd = signal.welch(one[:, 0], fs=RATE, nperseg=4096)
    out = {}
    for name in record.channels:
        if name.endswith(("/sprung_acc", "/unsprung_acc")):
            out[name] = signal.csd(one[:, 0], record[name], fs=RATE, nperseg=4096)[1] / input_psd
    return frequency, out, min(record[f"{c}/tyre_force"].min() for c in vehicle.corners)


def macpherson_car():
    """The MacPherson front and vertical rear of tests/test_kinematics.py."""
    return vehicle_from_dict(tomllib.loads(MACPHERSON_CAR))


@pytest.mark.slow
@pytest.mark.parametrize("vehicle", [parallel_arm_car(), load_vehicle("fs_car"), macpherson_car()],
                         ids=["parallel_arms", "fs_car", "macpherson"])
def test_linkage_ride_matches_the_equivalent_vertical_car(vehicle):
    """Small heave drives, 1-20 Hz: body and wheel FRFs of the linkage car and its vertical equivalent
    (rig/vehicle/vertical_equivalent.py) agree within 2 %: measured 0.08 % (body) and 0.42 % (wheel, at 1.2 Hz)
    on fs_car, 0.07 % on parallel arms, 1.1 % (body) and 0.48 % (wheel) on the MacPherson car. A vertical car
    without the inerters is 2.4 % (body, unsprung_mass at the wheel) or 2.45 % (wheel, c there) off on fs_car."""
    equivalent = vertical_equivalent(vehicle)
    frequency, linkage, lowest = _heave_frfs(vehicle)
    _, vertical, _ = _heave_frfs(equivalent.vehicle, equivalent.add_inerters)
    assert lowest > 0.0  # the tyres never lift off (fs_car's lowest: 545 N): the linear range
    band = (frequency >= 1.0) & (frequency <= 20.0)
    worst = max(np.max(np.abs(linkage[n][band] - vertical[n][band]) / np.abs(vertical[n][band])) for n in linkage)
    assert worst < 0.02, worst


def test_a_bump_stop_acts_at_the_wheel_on_a_linkage_as_on_a_vertical_corner():
    """The bump stop (rig/causes/bump_stop.py) is a tendon from the body site to the hub: on the K&C rig it adds its
    rate at the wheel beyond its gap, on fs_car's linkage as on the vertical twin: within 0.4 % 5 mm into contact,
    1.2 % 15 mm into it (the linkage's hub moves sideways and tilts the tendon)."""
    vehicle = load_vehicle("fs_car")
    stop = BumpStop(gap=0.005, rate=60000.0)
    travel = np.linspace(-0.02, 0.02, 9)
    added = []
    for car in (vehicle, vertical_equivalent(vehicle).vehicle):
        with_stop = BUMP_STOP.on_every_axle(car, lambda axle, stop=stop: stop)
        plain, stopped = (run_kc(c, "travel", half_range=0.02, steps=9) for c in (car, with_stop))
        added.append(stopped.curves["FL/wheel_rate"] - plain.curves["FL/wheel_rate"])
    linkage, vertical = added
    beyond, before = travel > 0.0055, travel < 0.0045
    assert np.allclose(vertical[beyond], 60000.0, rtol=1e-3) and np.allclose(vertical[before], 0.0, atol=1.0)
    assert abs(linkage[beyond][0] / vertical[beyond][0] - 1) < 0.005
    assert np.allclose(linkage[beyond], vertical[beyond], rtol=0.015) and np.allclose(linkage[before], 0.0, atol=1.0)
