"""The cores left to the rollouts (rig/sim/cores.py): MuJoCo's profiler clock off while rollouts run, and put back when
the last one ends; the physics bit for bit the same; BLAS on one thread through a diagnosis."""

from __future__ import annotations

import threading

import mujoco
import numpy as np
from mujoco import rollout
from threadpoolctl import threadpool_info

from rig.sim import cores
from rig.sim.cores import clock_off, one_blas_thread
from rig.sim.simulate import Simulator, run_batch
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle


def _callback() -> int | None:
    return cores._time_callback().value


def test_the_bindings_clock_is_found_cleared_and_put_back():
    installed = _callback()
    assert installed is not None, "MuJoCo's Python bindings install a profiler clock when they load"
    with clock_off():
        assert _callback() is None
    assert _callback() == installed


def test_the_clock_comes_back_only_when_the_last_rollout_ends():
    installed = _callback()
    first_in, second_in, first_may_leave = threading.Event(), threading.Event(), threading.Event()
    seen = {}

    def first():
        with clock_off():
            first_in.set()
            second_in.wait(5)
            first_may_leave.wait(5)
        seen["after first"] = _callback()

    thread = threading.Thread(target=first)
    thread.start()
    first_in.wait(5)
    with clock_off():
        second_in.set()
        first_may_leave.set()
        thread.join(5)
        seen["second still running"] = _callback()
    assert seen == {"after first": None, "second still running": None}
    assert _callback() == installed


def test_the_physics_is_the_same_with_the_clock_off():
    sim = Simulator.create(build_model(load_vehicle("proton_x"), 512.0, "ideal", longest=2e-3))
    rng = np.random.default_rng(3)
    inputs = np.cumsum(rng.normal(0.0, 2e-4, (1, 1024, 4)), axis=1)
    inputs -= inputs[:, :1]
    ctrl = sim.controls(inputs)
    timed_states, timed_sensors = rollout.rollout(sim.rig.model, mujoco.MjData(sim.rig.model),
                                                  sim.static.state[None], ctrl)
    ours = run_batch([sim], inputs, nthread=1)
    with clock_off():
        states, sensors = rollout.rollout(sim.rig.model, mujoco.MjData(sim.rig.model), sim.static.state[None], ctrl)
    assert np.array_equal(states, timed_states) and np.array_equal(sensors, timed_sensors)
    steps, nq = sim.rig.steps_per_sample, sim.rig.model.nq  # run_batch's rollout, with the clock off
    assert np.array_equal(ours["qpos"][0, 1:], timed_states[0, steps - 1::steps, 1:1 + nq][:1023])


def test_blas_runs_on_one_thread_inside_and_as_before_after():
    def blas_threads() -> list[int]:
        return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]

    before = blas_threads()
    assert one_blas_thread(blas_threads)() == [1] * len(before)
    assert blas_threads() == before
