"""Replay speed: the project's replay against raw ``mujoco.rollout`` of the same model and controls.

Prints, for a 60 s four-corner random drive on proton_x at 512 Hz:
- replay time / raw rollout time (target <= 1.2): everything the project adds (model build, settling,
  limit checks, input interpolation, output record) over the bare C rollout, both on one thread;
- the real-time factor of the replay;
- the throughput of a batch of 16 replays on 2 threads (simulated seconds per wall second);
- on ideal posts (a diagnosis's fits), a raw rollout with MuJoCo's constraint stage on against off, as the model is
  built where it has nothing to solve (rig/vehicle/mjcf.py ``without_idle_constraint_solver``), CPU time, best of 5;
- on ideal posts, a raw rollout with the profiler clock MuJoCo's Python bindings install on against off, as the
  project's rollouts run (rig/sim/cores.py ``clock_off``), CPU time, best of 5.
Every raw rollout but the clock's "on" runs with that clock off, as the project's do, so the ratios compare like with
like.
Run: python benchmarks/replay.py
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable

import mujoco
import numpy as np
from mujoco import rollout

from rig.sim.broadband import broadband_drive
from rig.sim.cores import clock_off
from rig.sim.replay import replay, replay_batch
from rig.sim.simulate import Simulator
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle
from timing import best_of

DURATION = 60.0


def main() -> None:
    vehicle = load_vehicle("proton_x")
    drive = broadband_drive(vehicle.corners, DURATION, seed=7)
    sim = Simulator.create(build_model(vehicle, drive.rate, "servo"))
    ctrl = sim.controls(drive.quantity("drive")[None])
    data = [mujoco.MjData(sim.rig.model)]

    def raw_rollout(*args) -> Callable[[], object]:
        def run():
            with clock_off():
                return rollout.rollout(*args)
        return run

    raw = best_of(raw_rollout(sim.rig.model, data, sim.static.state[None], ctrl))
    project = best_of(lambda: replay(vehicle, drive, nthread=1))
    print(f"60 s drive at {drive.rate:g} Hz, {ctrl.shape[1]} RK4 steps of {sim.rig.timestep * 1e3:.4f} ms")
    print(f"raw mujoco.rollout:        {raw:.3f} s")
    print(f"project replay:            {project:.3f} s")
    print(f"replay / raw rollout:      {project / raw:.3f}   (target <= 1.2)")
    print(f"real-time factor (replay): {DURATION / project:.1f}x")

    drives = [broadband_drive(vehicle.corners, DURATION, seed=s) for s in range(16)]
    batch = best_of(lambda: replay_batch(vehicle, drives, nthread=2), repeats=1)
    raw_batch = best_of(raw_rollout(sim.rig.model, [mujoco.MjData(sim.rig.model) for _ in range(2)],
                                    sim.static.state[None], np.repeat(ctrl, 16, axis=0)), repeats=1)
    print(f"batch of 16 on 2 threads:  {batch:.2f} s = {16 * DURATION / batch:.0f} simulated s per s "
          f"({batch / raw_batch:.3f} x raw rollout of the same batch)")

    ideal = Simulator.create(build_model(vehicle, drive.rate, "ideal", longest=2e-3))
    model, heights = ideal.rig.model, ideal.controls(drive.quantity("drive")[None])
    stage = int(mujoco.mjtDisableBit.mjDSBL_CONSTRAINT)
    assert model.opt.disableflags & stage

    def rollout_with(flags: int, clock_on: bool = False) -> float:
        model.opt.disableflags = flags
        args = (model, [mujoco.MjData(model)], ideal.static.state[None], heights)
        return best_of(functools.partial(rollout.rollout, *args) if clock_on else raw_rollout(*args), repeats=5,
                       clock=time.process_time)

    built = model.opt.disableflags
    solved, skipped = rollout_with(built & ~stage), rollout_with(built)
    print(f"ideal posts, constraint stage on / off (as built): {solved:.3f} s / {skipped:.3f} s CPU = "
          f"{solved / skipped:.3f}")
    timed = rollout_with(built, clock_on=True)
    print(f"ideal posts, MuJoCo's profiler clock on / off (as run): {timed:.3f} s / {skipped:.3f} s CPU = "
          f"{timed / skipped:.3f}")


if __name__ == "__main__":
    main()
