"""What linkage corners cost: fs_car (double wishbones, rig/vehicle/suspensions/) against its vertical equivalent, and
the K&C tests' wall time.

Prints, measured in one run on this machine:
- replay of a 60 s four-corner random drive at 512 Hz (best of 3, one thread): the linkage car's time over the
  vertical car's (rig/vehicle/vertical_equivalent.py, without its inerters: the plain vertical ride model);
- where a step's time goes, both cars (MuJoCo's own timers over 4000 steps from static ride height, best of 3):
  the tree's kinematics, inertia and velocity stages, and the equality constraints' (making, projecting, solving);
- MuJoCo options against the linkage car's defaults (its step time, best of 15, interleaved): the CG solver, dense
  and sparse Jacobians, one solver iteration, a looser tolerance, no warm start, 10 noslip iterations;
- ``rig kc`` on fs_car: every test (travel, roll, steer, lateral, longitudinal, aligning) with its kc.csv and plots,
  as the command writes them, and their total (the issue's target: under 30 s on two cores).
Run: python benchmarks/kinematics.py
"""

from __future__ import annotations

import argparse
import copy
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
from rig.vehicle.vertical_equivalent import vertical_equivalent
from timing import best_of

DURATION = 60.0
REPEATS = 3
STEPS = 4000
OPTION_REPEATS = 15



STAGES = ("pos_kinematics", "pos_inertia", "velocity", "pos_make", "pos_project", "constraint")
OPTIONS = {
    "CG solver": {"solver": mujoco.mjtSolver.mjSOL_CG},
    "dense Jacobians": {"jacobian": mujoco.mjtJacobian.mjJAC_DENSE},
    "sparse Jacobians": {"jacobian": mujoco.mjtJacobian.mjJAC_SPARSE},
    "1 iteration": {"iterations": 1},
    "tolerance 1e-6": {"tolerance": 1e-6},
    "no warm start": {"disableflags": mujoco.mjtDisableBit.mjDSBL_WARMSTART},
    "noslip 10": {"noslip_iterations": 10},
}


def step_profile(model: mujoco.MjModel, state, repeats: int = 3, steps: int = STEPS) -> dict[str, float]:
    """Seconds per step in MuJoCo's timers (a timer callback on), from ``state`` (static ride height), posts held;
    the best of ``repeats`` runs of ``steps`` steps."""
    best: dict[str, float] = {}
    for _ in range(repeats):
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        mujoco.set_mjcb_time(time.perf_counter)
        try:
            for _ in range(steps):
                mujoco.mj_step(model, data)
        finally:
            mujoco.set_mjcb_time(None)
        seconds = {name: data.timer[getattr(mujoco.mjtTimer, f"mjTIMER_{name.upper()}")].duration / steps
                   for name in ("step", *STAGES)}
        if not best or seconds["step"] < best["step"]:
            best = seconds
    best["nv"], best["nefc"], best["niter"] = model.nv, data.nefc, int(data.solver_niter[0])
    return best


def with_options(model: mujoco.MjModel, options: dict) -> mujoco.MjModel:
    changed = copy.deepcopy(model)
    for name, value in options.items():
        setattr(changed.opt, name, getattr(changed.opt, name) | value if name == "disableflags" else value)
    return changed


def print_profiles(linkage, vertical) -> None:
    for sim, label in ((linkage, "linkage"), (vertical, "vertical")):
        p = step_profile(sim.rig.model, sim.static.state)
        constraints = p["pos_make"] + p["pos_project"] + p["constraint"]
        stages = ", ".join(f"{name} {p[name] * 1e6:.1f}" for name in STAGES)
        print(f"{label} step ({p['nv']} DOF, {p['nefc']} constraint rows): {p['step'] * 1e6:.1f} us; {stages} us; "
              f"equality constraints (make, project, solve) {100 * constraints / p['step']:.0f} %")


def print_options(linkage) -> None:
    """Each option's linkage step time over the defaults', interleaved, best of OPTION_REPEATS runs of 1000 steps
    (short runs, many: on a shared machine the best of many is the closest to the work itself), and the solver's
    iterations in the last step."""
    models = {"defaults": linkage.rig.model} | {name: with_options(linkage.rig.model, o) for name, o in OPTIONS.items()}
    best, iterations = dict.fromkeys(models, float("inf")), {}
    for _ in range(OPTION_REPEATS):
        for name, model in models.items():
            profile = step_profile(model, linkage.static.state, 1, 1000)
            best[name], iterations[name] = min(best[name], profile["step"]), profile["niter"]
    print("MuJoCo options, linkage step time over the defaults' (Newton, auto Jacobians, 100 iterations, 1e-8):")
    for name in models:
        print(f"  {name:18s} {best[name] / best['defaults']:.3f}  (solver iterations in a step: {iterations[name]})")


def main() -> None:
    linkage = load_vehicle("fs_car")
    vertical = vertical_equivalent(linkage).vehicle
    drive = broadband_drive(linkage.corners, DURATION, seed=7)
    times = {car.name + (" (vertical)" if car is vertical else ""):
             best_of(lambda car=car: replay(car, drive, nthread=1), REPEATS) for car in (linkage, vertical)}
    (linkage_name, linkage_time), (vertical_name, vertical_time) = times.items()
    print(f"replay of a {DURATION:g} s random drive at {drive.rate:g} Hz, one thread, best of {REPEATS}:")
    print(f"  {linkage_name:22s} {linkage_time:.2f} s ({DURATION / linkage_time:.0f}x real time)")
    print(f"  {vertical_name:22s} {vertical_time:.2f} s ({DURATION / vertical_time:.0f}x real time)")
    print(f"  linkage / vertical:    {linkage_time / vertical_time:.2f}")

    models = [Simulator.create(build_model(car, 512.0)) for car in (linkage, vertical)]
    print_profiles(*models)
    print_options(models[0])

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
