"""Gymnasium environments: vector-env speed against a raw rollout of the same model, and the controller table.

Prints, for proton_x_quarter on an ISO 8608 class C road at 20 m/s (512 Hz control, 2 RK4 substeps), the
load average before and after, and:
- env steps per second of ``FourPoster/ActiveSuspension-v0`` as a vector env of 64 and 256 copies
  (mujoco.batch) on 1 and on 2 threads, against ``mujoco.rollout`` of the same model, controls and copies
  with nothing per step in Python (target ratio >= 0.8; both with MuJoCo's profiler clock off, as the env steps:
  rig/sim/cores.py), each by CPU time (``time.process_time``, which other
  work on a shared machine inflates least) and by the wall clock. Every timing is the best of ``--repeats``
  runs taken in turn, so that a shared machine's changing load falls on all of them alike (load only ever
  slows a run down). Between raw rollout and env, the runs that say where the difference goes:
  the env's rollout calls alone (one call per env step: the batch's per-call work, on two threads with the
  hand-off to the second thread; their substeps leave the sensors out, which the raw rollout computes and
  records at every substep), then with the ``mj_forward`` per env step for the observation at the state the
  step ends in (on the caller's thread; the env's batch calls, without any Python: the ceiling of the
  ratio), then the env (its Python per step). The single env
  (``mj_step`` in a loop) is timed once;
- the controller table: a_w, tyre load, travel, power of every controller of controllers/suspension_laws.py and
  the passive damper, and how far each lies below the passive curve at its own tyre load: the whole curve
  (damper scaled 0.2-1.0, as ``rig control --sweep``) and the acceptance front (0.4-1.0).
Run: python benchmarks/envs.py [--speed] [--copies 64 256] [--repeats 7]   (--speed: without the table)
"""

from __future__ import annotations

import argparse
import copy
import os
import time
from collections.abc import Callable

import gymnasium as gym
import mujoco
import numpy as np
from mujoco import rollout

import rig  # noqa: F401  (registers the environments)
from controllers.suspension_laws import CONTROLLERS, make_controller, needs
from rig.envs.pareto import below_front, passive_front
from rig.envs.policy_run import run_policy
from rig.envs.stepping import BatchStepper
from rig.sim.cores import clock_off

ROAD = "iso8608:class=C,length=500"
STEPS = 500


def best_times(runs: dict[str, Callable[[], None]], repeats: int) -> dict[str, tuple[float, float]]:
    """The shortest wall-clock and the shortest CPU time (s) of ``repeats`` timings of each run, the runs taken
    in turn."""
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in runs}
    for _ in range(repeats):
        for name, run in runs.items():
            wall, cpu = time.perf_counter(), time.process_time()
            run()
            times[name].append((time.perf_counter() - wall, time.process_time() - cpu))
    return {name: (min(t[0] for t in values), min(t[1] for t in values)) for name, values in times.items()}


def speed_runs(copies: int, threads: int) -> dict[str, Callable[[], None]]:
    """Raw rollout, the env's rollout calls, its batch calls (with the observation's forward), the vector env:
    ``STEPS`` env steps each, zero force."""
    envs = gym.make_vec("FourPoster/ActiveSuspension-v0", num_envs=copies, vectorization_mode="vector_entry_point",
                        road=ROAD, nthread=threads)
    plant, actions = envs.unwrapped.plant, np.zeros((copies, 1))
    n = plant.substeps
    controls = np.repeat(plant.inputs[:, :STEPS * n + 1], copies, axis=0)  # the road's inputs, no force
    controls[:, :, plant.action_ctrl] = actions[:, None, :]
    periods = [np.ascontiguousarray(controls[:, k * n:(k + 1) * n + 1]) for k in range(STEPS)]
    stepper = BatchStepper(plant.model, copies, threads)
    datas = [mujoco.MjData(plant.model) for _ in range(threads)]
    initial = np.repeat(plant.sim.static.state[None], copies, axis=0)

    def raw():  # with MuJoCo's profiler clock off, as the env steps (rig/sim/cores.py)
        with clock_off():
            rollout.rollout(plant.model, datas, initial, controls[:, :STEPS * n])

    quiet = copy.copy(plant.model)  # the model with MuJoCo's sensor stage disabled, as in the env's substeps
    quiet.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_SENSOR

    def raw_without_sensors():
        with clock_off():
            rollout.rollout(quiet, datas, initial, controls[:, :STEPS * n])

    def rollout_calls(forward: bool) -> Callable[[], None]:
        def run():
            stepper.reset(plant.sim.static.state, controls[:, 0])
            for period in periods:
                if forward:
                    stepper.advance(period)
                else:
                    stepper.substeps(period[:, :n])
        return run

    def vector_env():
        envs.reset()
        for _ in range(STEPS):
            envs.step(actions)

    return {"raw": raw, "raw without sensors": raw_without_sensors, "rollout calls": rollout_calls(False),
            "batch calls": rollout_calls(True), "vector env": vector_env}


def env_speed(copies: int, threads: int, repeats: int) -> None:
    best = best_times(speed_runs(copies, threads), repeats)
    print(f"\n{copies} copies on {threads} thread(s), {STEPS} env steps of 2 RK4 substeps, best of {repeats} in turn")
    print(f"{'':46s} {'CPU time':>22s} {'wall clock':>22s}")
    labels = {"raw": "raw mujoco.rollout", "raw without sensors": "  (for reference: sensors left out)",
              "rollout calls": "the env's rollout calls (one per env step)",
              "batch calls": "  + the observation's mj_forward (no Python)", "vector env": "vector env"}
    for name, (wall, cpu) in best.items():
        ratios = [best["raw"][i] / t for i, t in enumerate((wall, cpu))]
        print(f"{labels[name]:46s} {copies * STEPS / cpu:10.0f}/s ratio {ratios[1]:.2f} "
              f"{copies * STEPS / wall:10.0f}/s ratio {ratios[0]:.2f}")
    raw_cpu = best["raw"][1]
    shares = [best[b][1] / raw_cpu - best[a][1] / raw_cpu
              for a, b in (("raw", "rollout calls"), ("rollout calls", "batch calls"), ("batch calls", "vector env"))]
    print("the env's CPU time beyond the raw rollout's, in raw rollouts: per-call work {:+.3f}, observation's "
          "forward {:+.3f}, Python {:+.3f}".format(*shares))


def single_env_speed() -> None:
    single = gym.make("FourPoster/ActiveSuspension-v0", road=ROAD)

    def run():
        single.reset()
        for _ in range(STEPS):
            single.step(np.zeros(1))

    wall, cpu = best_times({"single": run}, 3)["single"]
    print(f"\nsingle env (mj_step): {STEPS / cpu:8.0f} env steps/s CPU time, {STEPS / wall:8.0f} wall clock")


def controller_table() -> None:
    kwargs = {"road": ROAD, "speed": 20.0, "physical_actions": True}
    front = passive_front(road=ROAD, speed=20.0)
    rows = [(f"passive:scale={p.scale:g}", p.metrics) for p in front if p.scale in (0.4, 0.7, 1.0)]
    for name in CONTROLLERS:
        if name == "passive":
            continue
        if needs(name) == "force":
            env = gym.make("FourPoster/ActiveSuspension-v0", force_limit=5000.0, **kwargs)
        else:
            env = gym.make("FourPoster/SemiActiveSuspension-v0", c_min=1000.0, c_max=8000.0, **kwargs)
        controller = make_controller(name, env)
        controller.reset()
        rows.append((name, run_policy(env, controller).metrics))
    usual = [p for p in front if p.scale >= 0.4]  # the acceptance front: the damper scaled 0.4-1.0
    print(f"\n{'controller':22s} {'a_w m/s2':>9s} {'tyre load':>10s} {'travel mm':>10s} {'power W':>8s} "
          f"{'below 0.2-1.0':>14s} {'below 0.4-1.0':>14s}")
    for name, m in rows:
        gains = (below_front(front, m), below_front(usual, m))
        where = ["-" if gain is None else f"{100 * gain:+.1f} %" for gain in gains]
        print(f"{name:22s} {m['a_w']:9.3f} {m['tyre_load_rms']:10.3f} {1e3 * m['travel_rms']:10.1f} "
              f"{m['power_w']:8.0f} {where[0]:>14s} {where[1]:>14s}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speed", action="store_true", help="the speed only, without the controller table")
    parser.add_argument("--copies", type=int, nargs="+", default=[64, 256])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()
    print("load average (1, 5, 15 min) before: {:.2f} {:.2f} {:.2f} on {} CPUs".format(*os.getloadavg(),
                                                                                      os.cpu_count()))
    for count in args.copies:
        for nthread in (1, 2):
            env_speed(count, nthread, args.repeats)
    single_env_speed()
    print("load average after: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))
    if not args.speed:
        controller_table()
