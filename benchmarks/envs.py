"""Gymnasium environments: vector-env speed against a raw rollout of the same model, and the controller table.

Prints, for proton_x_quarter on an ISO 8608 class C road at 20 m/s (512 Hz control, 2 substeps):
- env steps per second of ``FourPoster/ActiveSuspension-v0`` as a vector env of 64 and 256 copies
  (mujoco.batch) and of the single env, on 2 threads by the wall clock and on 1 thread in CPU time (which
  other work on a shared machine does not inflate), against ``mujoco.rollout`` of the same model, controls and copies
  with nothing per step in Python (target ratio >= 0.8), and the env's batch calls alone (the ceiling the
  Python leaves room for). What the env adds: one mj_forward per env step for
  the observation at the state the step ends in (1 of 9 force evaluations with 2 RK4 substeps), and the
  Python per step (metrics, observation), which more copies share;
- the controller table: a_w, tyre load, travel, power of every controller of controllers/suspension.py and
  the passive damper, and how far each lies below the passive curve at its own tyre load: the whole curve
  (damper scaled 0.2-1.0, as ``rig control --sweep``) and the acceptance front (0.4-1.0).
Run: python benchmarks/envs.py
"""

from __future__ import annotations

import time
from collections.abc import Callable

import gymnasium as gym
import mujoco
import numpy as np
from mujoco import rollout

import rig  # noqa: F401  (registers the environments)
from controllers.suspension import CONTROLLERS, make_controller, needs
from rig.envs.pareto import below_front, passive_front
from rig.envs.policy_run import run_policy
from rig.envs.stepping import BatchStepper

ROAD = "iso8608:class=C,length=500"
STEPS = 500


def best_times(runs: dict[str, Callable[[], None]], clock: Callable[[], float], repeats: int = 5) -> dict[str, float]:
    """The shortest of ``repeats`` timings (s, on ``clock``) of each run, the runs taken in turn, so that a shared
    machine's changing load falls on all of them alike (load only ever slows a run down)."""
    times = {name: [] for name in runs}
    for _ in range(repeats):
        for name, run in runs.items():
            start = clock()
            run()
            times[name].append(clock() - start)
    return {name: min(values) for name, values in times.items()}


def env_speed(copies: int, threads: int, clock: Callable[[], float]) -> None:
    """Env steps per second on ``threads`` threads, timed on ``clock`` (wall: perf_counter; CPU: process_time)."""
    envs = gym.make_vec("FourPoster/ActiveSuspension-v0", num_envs=copies, vectorization_mode="vector_entry_point",
                        road=ROAD, nthread=threads)
    plant = envs.unwrapped.plant
    actions = np.zeros((copies, 1))

    def vector_run():
        envs.reset()
        for _ in range(STEPS):
            envs.step(actions)

    controls = [plant.controls(k, actions) for k in range(STEPS)]
    next_controls = [plant.sample_controls(k + 1, actions) for k in range(STEPS)]
    stepper = BatchStepper(plant.model, copies, threads)

    def stepper_run():
        stepper.reset(plant.sim.static.state, plant.sample_controls(0, actions))
        for k in range(STEPS):
            stepper.advance(controls[k], next_controls[k])

    ctrl = np.concatenate(controls, axis=1)
    datas = [mujoco.MjData(plant.model) for _ in range(threads)]
    initial = np.repeat(plant.sim.static.state[None], copies, axis=0)
    single = gym.make("FourPoster/ActiveSuspension-v0", road=ROAD)

    def single_run():
        single.reset()
        for _ in range(STEPS):
            single.step(np.zeros(1))

    best = best_times({"raw": lambda: rollout.rollout(plant.model, datas, initial, ctrl), "vector": vector_run,
                       "stepper": stepper_run}, clock)
    raw, vector, stepped = (copies * STEPS / best[name] for name in ("raw", "vector", "stepper"))
    one = STEPS / best_times({"single": single_run}, clock, repeats=1)["single"]
    timed = "wall-clock" if clock is time.perf_counter else "CPU time"
    print(f"\n{copies} copies on {threads} thread(s), {timed}, {STEPS} env steps of {plant.substeps} RK4 substeps "
          "each, best of 5, taken in turn")
    print(f"raw mujoco.rollout:   {raw:10.0f} env steps/s")
    print(f"vector env (batch):   {vector:10.0f} env steps/s   ratio {vector / raw:.2f} (target >= 0.8)")
    print(f"  its batch calls alone (substeps + observation forward, no Python): ratio {stepped / raw:.2f}")
    print(f"single env (mj_step): {one:10.0f} env steps/s")


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
    for copies in (64, 256):
        env_speed(copies, 2, time.perf_counter)
        env_speed(copies, 1, time.process_time)  # a shared machine's load does not count
    controller_table()
