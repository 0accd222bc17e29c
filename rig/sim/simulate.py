"""Run whole tests on the rig model: inputs at the record rate in, contract responses out.

One call simulates a batch of runs (several drives, and/or variants of one model with other
parameters) with ``mujoco.rollout``: every step runs in C, on all threads, with no Python work per
step. Inputs are samples of continuous signals: they are interpolated (cubic spline) to the steps, and
every input actuator reads them from a history buffer, which MuJoCo interpolates (cubic) at each RK4
stage: the input runs continuously through a step instead of being held (a held input biased the wheel
velocity by (omega h)^2 / 2 of the road velocity), and a sensor at a sample time sees the input at
exactly that time.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout
from scipy.interpolate import BSpline, make_interp_spline

from rig.errors import RigError
from rig.io.units import STANDARD_GRAVITY
from rig.sim.cores import clock_off
from rig.vehicle.mjcf import CLOCK_SENSOR, INPUT_DELAY_STEPS, RigModel
from rig.vehicle.statics import STATE_SPEC, StaticState, settle


class SimulationError(RigError, RuntimeError):
    """The simulation became unstable or MuJoCo warned; nothing is returned from such a run."""


@dataclass
class Simulator:
    """A settled rig model, ready to run batches of inputs. Build with ``Simulator.create``."""

    rig: RigModel
    static: StaticState

    @classmethod
    def create(cls, rig: RigModel) -> Simulator:
        return cls(rig=rig, static=settle(rig))

    def read_inputs(self, inputs: np.ndarray, interpolation: str = "cubic") -> tuple[np.ndarray, np.ndarray | None]:
        """Per-sample inputs (batch, samples, corners) read where the steps' controls read them (``controls``): their
        values and, with ideal posts, their rates (per sample)."""
        times = self._control_times(inputs.shape[1])
        spline = input_spline(inputs, interpolation)
        return spline(times), None if self.rig.posts == "servo" else spline(times, 1)

    def control_steps(self, n_samples: int) -> int:
        """How many steps' controls a record of ``n_samples`` samples gives: one per step, the last sample's too."""
        return (n_samples - 1) * self.rig.steps_per_sample + 1

    def _control_times(self, n_samples: int) -> np.ndarray:
        """Where step k's control reads the inputs, in samples: INPUT_DELAY_STEPS ahead, the last sample held."""
        steps = self.rig.steps_per_sample
        return np.minimum((np.arange(self.control_steps(n_samples)) + INPUT_DELAY_STEPS) / steps, n_samples - 1)

    def controls(self, inputs: np.ndarray, interpolation: str = "cubic",
                 wheel_angles: np.ndarray | None = None, forces: np.ndarray | None = None,
                 read: tuple[np.ndarray, np.ndarray | None] | None = None, out: np.ndarray | None = None
                 ) -> np.ndarray:
        """Per-step controls (batch, steps, nu) from per-sample inputs (batch, samples, corners) in m.

        Servo posts: the input is the post drive. Ideal posts: the input is the post (road) height,
        fed to the tyre as height + (ct/kt) * its rate, so that tyre damping sees the post velocity.
        ``wheel_angles`` (batch, samples, corners) in rad turn the wheels that can turn (rig/vehicle/mjcf.py):
        their spin servos get angle + (kv/kp) * its rate, so they follow it without lag; without them those
        wheels stand still, as on a rig. ``forces`` (batch, samples, corners) in N are the actuator forces between
        body and wheel (``active_force``: on the body, up positive), interpolated like the inputs; without them, 0.
        Input actuators read their control INPUT_DELAY_STEPS late (rig/vehicle/mjcf.py), so step k carries
        the input at t_k + INPUT_DELAY_STEPS h; the last sample is held beyond the end. ``read``: the inputs as
        ``read_inputs`` reads them, where they are read already (variants of a model on the same inputs). ``out``:
        zeros (batch, steps, nu) to write the controls into (a batch's rows of a larger array), returned.
        """
        rig = self.rig
        n_batch, n_samples, _ = inputs.shape
        times = self._control_times(n_samples)
        values, rates = read or self.read_inputs(inputs, interpolation)
        ctrl = np.zeros((n_batch, times.size, rig.model.nu)) if out is None else out
        if rig.posts == "servo":
            ctrl[:, :, rig.servo_ctrl] = values
        else:
            heights = values + self.tyre_time_constants() * rates * rig.rate
            ctrl[:, :, rig.tyre_ctrl] = heights[..., rig.tyre_corner]
        if wheel_angles is not None and rig.spin_corners:
            angles = input_spline(np.asarray(wheel_angles, float)[..., self.spin_columns()], "cubic")
            ctrl[:, :, rig.spin_ctrl] = angles(times) + rig.spin_lead * angles(times, 1) * rig.rate
        if forces is not None:
            ctrl[:, :, rig.active_ctrl] = input_spline(np.asarray(forces, float), interpolation)(times)
        return ctrl

    def spin_columns(self) -> list[int]:
        """Columns of the turning wheels in per-corner arrays."""
        return [self.rig.corners.index(c) for c in self.rig.spin_corners]

    def rolling_state(self, wheel_angles: np.ndarray) -> np.ndarray:
        """The static state with the turning wheels already rolling as ``wheel_angles`` (samples x corners, rad)
        start: each hinge at the first angle and rate, its servo's input history the angle's line before it,
        so the run starts in steady rolling, without a spin-up."""
        rig, model = self.rig, self.rig.model
        data = mujoco.MjData(model)
        mujoco.mj_setState(model, data, self.static.state, STATE_SPEC)
        spline = input_spline(np.asarray(wheel_angles, float)[None][..., self.spin_columns()], "cubic")
        angle, rate = spline(0.0)[0], spline(0.0, 1)[0] * rig.rate
        data.qpos[rig.spin_qpos], data.qvel[rig.spin_dof] = angle, rate
        h = model.opt.timestep
        for i, actuator in enumerate(rig.spin_ids):
            n = int(model.actuator_history[actuator, 0])
            # the buffer's times; step k's control carries the input INPUT_DELAY_STEPS ahead
            stamps = -h * np.arange(n, 0, -1)
            values = angle[i] + rate[i] * (stamps + INPUT_DELAY_STEPS * h + rig.spin_lead[i])
            mujoco.mj_initCtrlHistory(model, data, int(actuator), stamps, values.reshape(n, 1))
        state = np.empty_like(self.static.state)
        mujoco.mj_getState(model, data, state, STATE_SPEC)
        return state

    def tyre_time_constants(self) -> np.ndarray:
        """ct/kt per corner in s."""
        axles = [self.rig.vehicle.axle(c) for c in self.rig.corners]
        return np.array([a.tyre_damping / a.tyre_rate for a in axles])

    def run(self, inputs: np.ndarray, nthread: int | None = None, interpolation: str = "cubic",
            wheel_angles: np.ndarray | None = None, forces: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Simulate inputs (batch, samples, corners) or (samples, corners) in m on this model (``forces``: N,
        shaped alike, the actuator forces between body and wheel)."""
        return run_batch([self], inputs, nthread, interpolation, wheel_angles, forces)


def run_batch(sims: Sequence[Simulator], inputs: np.ndarray, nthread: int | None = None,
              interpolation: str = "cubic", wheel_angles: np.ndarray | None = None,
              forces: np.ndarray | None = None, qpos: bool = True) -> dict[str, np.ndarray | None]:
    """Simulate a batch; returns quantity -> (batch, samples, corners) arrays in SI, and "qpos" ->
    (batch, samples, nq) joint positions at the sample times (for animation; None with ``qpos=False``: the rollout
    then keeps no states, 111 numbers a step on proton_x, only the sensors, and the check of the runs reads their time
    from the model's clock sensor).

    ``sims`` holds one simulator for all runs, or one per run (variants of one model: same structure,
    other parameters). ``inputs`` is (batch, samples, corners) in m at the models' record rate; a quantity of no
    corner (``vehicle_channels``: a truck's ``seat_acc``) is (batch, samples, 1).
    ``interpolation`` is how the signal runs between samples: 'cubic' (spline, for sampled continuous
    signals) or 'linear' (straight lines, as profile standards such as ASTM E1926 define them).
    ``wheel_angles`` (shaped like ``inputs``, rad) turn the wheels that can turn, from steady rolling at the start.
    ``forces`` (shaped like ``inputs``, N) push each body up and its wheel down through the corners' force actuators
    (``active_force``).
    """
    inputs = np.asarray(inputs, dtype=float)
    if inputs.ndim == 2:
        inputs = inputs[None]
    if wheel_angles is not None:
        wheel_angles = np.asarray(wheel_angles, float).reshape(inputs.shape)
    if forces is not None:
        forces = np.asarray(forces, float).reshape(inputs.shape)
    n_batch = inputs.shape[0]
    if len(sims) not in (1, n_batch):
        raise ValueError(f"need one simulator or one per run, got {len(sims)} for {n_batch} runs")
    if len(sims) == 1:
        sims = list(sims) * n_batch
    first = sims[0]
    rig = first.rig
    if len({id(s) for s in sims}) == 1:
        ctrl = first.controls(inputs, interpolation, wheel_angles, forces)
    else:  # variants: ideal posts feed each tyre its own ct/kt x the road's rate
        turning = [None] * n_batch if wheel_angles is None else wheel_angles[:, None]
        pushing = [None] * n_batch if forces is None else forces[:, None]
        shared = first.read_inputs(inputs[:1], interpolation) if all(
            np.array_equal(inputs[0], x) for x in inputs[1:]) else None  # a fit's variants: read once
        ctrl = np.zeros((n_batch, first.control_steps(inputs.shape[1]), rig.model.nu))  # written in place:
        for i, (s, x) in enumerate(zip(sims, inputs)):  # a law's ramps make nu 264, 32 MB a run on proton_x
            s.controls(x[None], interpolation, turning[i], pushing[i], shared, out=ctrl[i:i + 1])
    models = [s.rig.model for s in sims]
    if wheel_angles is not None and rig.spin_corners:
        initial = np.stack([s.rolling_state(a) for s, a in zip(sims, wheel_angles)])
    else:
        initial = np.stack([s.static.state for s in sims])
    threads = max(1, min(nthread or len(os.sched_getaffinity(0)), n_batch))  # the cores this process may use
    datas = [mujoco.MjData(rig.model) for _ in range(threads)]
    states, sensors = _rollout(models, datas, initial, ctrl, qpos)
    _check(rig, states, sensors, datas)
    out = _responses(sims, sensors[:, ::rig.steps_per_sample], inputs, interpolation)
    out["qpos"] = None
    if qpos:  # joint positions at the sample times (state k is after step k + 1; the first sample is the initial state)
        at_samples = states[:, rig.steps_per_sample - 1::rig.steps_per_sample, 1:1 + rig.model.nq]
        out["qpos"] = np.concatenate([initial[:, None, 1:1 + rig.model.nq], at_samples[:, : inputs.shape[1] - 1]],
                                     axis=1)
    return out


def _rollout(models: list[mujoco.MjModel], datas: list[mujoco.MjData], initial: np.ndarray, ctrl: np.ndarray,
             states: bool) -> tuple[np.ndarray | None, np.ndarray]:
    """MuJoCo's rollout of every run, its profiler clock off (nothing reads its stage timers: rig/sim/cores.py): the
    states (None unless ``states``) and the sensor data at every step."""
    with clock_off():
        if states:
            return rollout.rollout(models if len(set(map(id, models))) > 1 else models[0], datas, initial, ctrl)
        sensors = np.empty((*ctrl.shape[:2], models[0].nsensordata))
        rollout.rollout(models, datas, np.ascontiguousarray(initial), np.ascontiguousarray(ctrl), skip_checks=True,
                        nstep=ctrl.shape[1], sensordata=sensors)  # no state array: the rollout then copies none
        return None, sensors


def input_spline(inputs: np.ndarray, interpolation: str = "cubic") -> BSpline:
    """The continuous signal behind sampled inputs (batch, samples, corners), as a function of time in samples.

    'cubic' by default, not straight lines: linear interpolation between samples acts as a low-pass
    filter (sinc^2: -1.1 % at 30 Hz from 512 Hz samples), which shows up in every FRF.
    """
    degrees = {"cubic": 3, "linear": 1}
    if interpolation not in degrees:
        raise ValueError(f"interpolation must be one of {', '.join(degrees)}, got {interpolation!r}")
    return make_interp_spline(np.arange(inputs.shape[1]), inputs, k=degrees[interpolation], axis=1)


def _check(rig: RigModel, states: np.ndarray | None, sensors: np.ndarray, datas: list[mujoco.MjData]) -> None:
    """Refuse a run that became unstable: values not finite, or time that stopped (MuJoCo's rollout repeats a
    warned run's last outputs to its end, and clears the warnings of each run a thread starts), or a warning."""
    time = sensors[:, :, rig.sensor_adr[CLOCK_SENSOR]] if states is None else states[:, :, 0]
    if not np.all(np.isfinite(sensors if states is None else states)) or np.any(np.diff(time, axis=1) <= 0):
        raise SimulationError("the simulation became unstable (state not finite or time stopped advancing); "
                              "check the vehicle parameters and the drive")
    for data in datas:
        warned = [mujoco.mjtWarning(i).name for i, w in enumerate(data.warning) if w.number]
        if warned:
            raise SimulationError(f"MuJoCo warned during the run: {', '.join(warned)}")


def sensor_responses(rig: RigModel, suspension_length: np.ndarray, sensors: np.ndarray,
                     heights: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Contract quantities -> (..., corners) arrays in SI from sensor data (..., nsensordata); travel from the
    static ``suspension_length`` (m, broadcast against (..., corners)). Posts' channels with servo posts. With the
    static ``heights`` (m, (..., 2 x corners): body sites, then hubs; StaticState.heights), the displacements from
    static ``sprung_disp`` and ``unsprung_disp`` (up positive)."""

    def column(name: str, offset: int = 0) -> np.ndarray:
        return sensors[..., [rig.sensor_adr[name.format(c)] + offset for c in rig.corners]]

    out = {
        "sprung_acc": column("car.{}/sprung_acc", 2) - STANDARD_GRAVITY,  # framelinacc includes gravity
        "unsprung_acc": column("car.{}/unsprung_acc", 2) - STANDARD_GRAVITY,
        "susp_travel": suspension_length - column("car.{}/suspension_length"),
        "susp_velocity": -column("car.{}/suspension_rate"),  # compression positive, like travel
        "tyre_force": rig.tyre_forces(sensors),
    }
    if rig.posts == "servo":
        out["actuator_disp"] = column("{}/actuator_disp")
        out["actuator_force"] = column("{}/actuator_force")
    if heights is not None:
        n = len(rig.corners)
        out["sprung_disp"] = column("car.{}/body_height", 2) - heights[..., :n]
        out["unsprung_disp"] = column("car.{}/hub_height", 2) - heights[..., n:]
    return out


#: quantities of no corner a model may have -> their channel: a truck cab's seat point
VEHICLE_CHANNELS = {"seat_acc": "cab/seat_acc"}


def vehicle_channels(rig: RigModel, sensors: np.ndarray) -> dict[str, np.ndarray]:
    """Quantities that belong to no corner, where the model has them (``seat_acc``: a truck's seat point, m/s^2,
    gravity removed), as (..., 1) arrays, beside the corners' (..., corners)."""
    name = "car.cab/seat_acc"
    if name not in rig.sensor_adr:
        return {}
    return {"seat_acc": sensors[..., rig.sensor_adr[name] + 2, None] - STANDARD_GRAVITY}


def _responses(sims: Sequence[Simulator], sensors: np.ndarray, inputs: np.ndarray,
               interpolation: str) -> dict[str, np.ndarray]:
    rig = sims[0].rig
    static_length = np.stack([s.static.suspension_length for s in sims])[:, None, :]
    out = sensor_responses(rig, static_length, sensors, np.stack([s.static.heights for s in sims])[:, None, :])
    out.update(vehicle_channels(rig, sensors))
    if rig.posts != "servo":
        post_mass = np.array([s.rig.vehicle.rig.post_mass for s in sims])[:, None, None]
        post_acc = input_spline(inputs, interpolation)(np.arange(inputs.shape[1]), 2) * rig.rate**2
        out["actuator_disp"] = inputs.copy()
        out["actuator_force"] = out["tyre_force"] + post_mass * (STANDARD_GRAVITY + post_acc)
    return out
