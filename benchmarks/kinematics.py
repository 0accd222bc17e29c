"""What linkage corners cost: fs_car (double wishbones, rig/vehicle/suspensions/) against its vertical twin, and the
K&C tests' wall time.

Prints, measured in one run on this machine:
- replay of a 60 s four-corner random drive at 512 Hz (best of 3, one thread): the linkage car's time over the
  vertical twin's (the same vehicle file without its kinematics tables);
- where a linkage step's time goes (MuJoCo's own timers over 4000 steps from static ride height): the equality
  constraints' share (making, projecting and solving them) and the rest of the position stage;
- ``rig kc`` on fs_car: every test (travel, roll, steer, lateral, longitudinal, aligning) with its kc.csv and plots,
  as the command writes them, and their total (the issue's target: under 30 s on two cores).
Run: python benchmarks/kinematics.py
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
import time

import mujoco

from rig.cli import kc
from rig.io.kc_record import TESTS
from rig.sim.broadband import broadband_drive
from rig.sim.replay import replay
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle
from timing import best_of

DURATION = 60.0
REPEATS = 3
STEPS = 4000



def vertical_twin(vehicle):
    """The vehicle without kinematics tables; its body site raised clear of the hub (the vertical template puts it
    at the CG's height, which on fs_car is barely above the wheel centre)."""
    return dataclasses.replace(vehicle, cg_height=0.55, front=dataclasses.replace(vehicle.front, kinematics=None),
                               rear=dataclasses.replace(vehicle.rear, kinematics=None))


def step_profile(vehicle) -> dict[str, float]:
    """Seconds per step in MuJoCo's timers (a timer callback on), from static ride height, posts held."""
    sim = Simulator.create(build_model(vehicle, 512.0))
    model, data = sim.rig.model, mujoco.MjData(sim.rig.model)
    mujoco.mj_setState(model, data, sim.static.state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    mujoco.set_mjcb_time(time.perf_counter)
    try:
        for _ in range(STEPS):
            mujoco.mj_step(model, data)
    finally:
        mujoco.set_mjcb_time(None)
    timer = mujoco.mjtTimer
    seconds = {name: data.timer[getattr(timer, f"mjTIMER_{name.upper()}")].duration / STEPS
               for name in ("step", "position", "pos_make", "pos_project", "constraint")}
    seconds["nv"], seconds["nefc"] = model.nv, data.nefc
    return seconds


def main() -> None:
    linkage = load_vehicle("fs_car")
    vertical = vertical_twin(linkage)
    drive = broadband_drive(linkage.corners, DURATION, seed=7)
    times = {car.name + (" (vertical)" if car is vertical else ""):
             best_of(lambda car=car: replay(car, drive, nthread=1), REPEATS) for car in (linkage, vertical)}
    (linkage_name, linkage_time), (vertical_name, vertical_time) = times.items()
    print(f"replay of a {DURATION:g} s random drive at {drive.rate:g} Hz, one thread, best of {REPEATS}:")
    print(f"  {linkage_name:22s} {linkage_time:.2f} s ({DURATION / linkage_time:.0f}x real time)")
    print(f"  {vertical_name:22s} {vertical_time:.2f} s ({DURATION / vertical_time:.0f}x real time)")
    print(f"  linkage / vertical:    {linkage_time / vertical_time:.2f}")

    for car, label in ((linkage, "linkage"), (vertical, "vertical")):
        p = step_profile(car)
        constraints = p["pos_make"] + p["pos_project"] + p["constraint"]
        print(f"{label} step ({p['nv']} DOF, {p['nefc']} constraint rows): {p['step'] * 1e6:.1f} us, of which "
              f"equality constraints (make, project, solve) {constraints * 1e6:.1f} us = "
              f"{100 * constraints / p['step']:.0f} %, the rest of the position stage "
              f"{(p['position'] - p['pos_make'] - p['pos_project']) * 1e6:.1f} us")

    total = 0.0
    with tempfile.TemporaryDirectory() as folder:
        for test in TESTS:
            args = argparse.Namespace(vehicle="fs_car", test=test, out=f"{folder}/{test}", range=None, steps=41,
                                      fit=None, free=None, method="lm")
            start = time.perf_counter()
            kc.run(args)
            elapsed = time.perf_counter() - start
            total += elapsed
    print(f"rig kc on fs_car, all {len(TESTS)} tests with kc.csv and plots: {total:.1f} s (target < 30 s)")


if __name__ == "__main__":
    main()
