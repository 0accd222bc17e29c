"""Fit a car's linear parameters on its frequency response instead of time stepping.

Where the car stays linear on a record, its channels are its frequency response times the posts' transform: no trial of
a least-squares step needs a simulation. The response is the same MuJoCo model's as the time-domain fit runs: central
differences of ``mj_forward`` give its continuous A, B, C, D at the settled state (inputs: each tyre's road height, fed
height + (c_t / k_t) x its rate as the replay feeds it; outputs: the car channels, formed from the sensors as the replay
forms them), H(j w) = C (j w I - A)^-1 B + D; the input actuators' reading delay, which the replay makes up for by
feeding them early, is taken out of the linearised copy. ``linear_response`` multiplies it with the posts' transform
(zero-padded, so that the circular convolution is the linear one of a car starting at rest) and transforms back, and the
fit is rig/diagnosis/core/fitting.py ``fit_car`` itself with each trial's channels so formed (the same residual, bounds,
scales, steps, secant Jacobian and budget of evaluations, intervals from the Jacobian at the solution): by Parseval's
theorem that is the comparison of the measured and modelled cross-spectra with the posts, weighted by the posts'
spectra, without the bias Welch's averaged estimates have at a car's body modes on a record of 20-30 s (10-40 % below
1.5 Hz, where the spring rates show). ``stays_linear`` decides where it applies: a tyre that lifts off or a stop that is
reached makes the model nonlinear, and the time-domain fit is used. Written here because no library linearises a MuJoCo
model's input-output map to the channels; NumPy and SciPy do the rest.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import mujoco
import numpy as np

from rig.causes import FitParameter
from rig.diagnosis.core.experiment import Experiment, feasible
from rig.diagnosis.core.fitting import FitResult, fit_car
from rig.signal.filters import band_pass
from rig.sim.simulate import Simulator, sensor_responses
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import Vehicle

#: s: the zeros after the record, before its transform, that keep the wrap-around of the model's response (a
#: circular convolution) off the record: a car's slowest mode (about 1 Hz, 20 % damped) has decayed a thousandfold
DECAY_SECONDS = 8.0
#: the largest rms difference, over a channel's rms, between a car's linear response and its time-domain run on a
#: record for the car to count as linear there (a tyre that lifts off, a stop that is reached: 2-3 % on the channels
#: near it); the two differ by under 0.2 % on a car that stays linear (tests/test_frequency_fit.py)
LINEARITY_TOLERANCE = 0.005
#: the diagnosis's note where these fits ran
LINEAR_NOTE = ("the recalibration and the first round's fits of causes that keep the car linear ran on its frequency "
               f"response: the data sheet's car stays linear on the fit data (its linear response within "
               f"{100 * LINEARITY_TOLERANCE:g} % of each channel's rms of its time-domain run); every held-out score "
               "is a time-domain run")


def frequency_response(vehicle: Vehicle, experiment: Experiment, frequencies: np.ndarray) -> np.ndarray:
    """The car channels' response to each post's displacement (frequencies x channels x posts; m/s^2 or m per m)
    of ``vehicle`` on ideal posts, linearised at its settled state."""
    sim = Simulator.create(build_model(vehicle, experiment.record.rate, "ideal", None, experiment.longest))
    rig, model = sim.rig, sim.rig.model
    model.actuator_delay[:] = 0.0  # the replay feeds the inputs early by their reading delay: none is left
    a, b, c, d = state_space(model, sim.static.state)
    select = channel_selection(sim, experiment.car_channels)
    tyres, s = rig.tyre_ctrl, 2j * np.pi * np.asarray(frequencies)
    lead = 1.0 + sim.tyre_time_constants()[rig.tyre_corner][None, :] * s[:, None]  # each tyre's input per post's
    per_tyre = (transfer(select @ c, a, b[:, tyres], s) + (select @ d[:, tyres])[None]) * lead[:, None, :]
    corner_of = np.zeros((len(tyres), len(rig.corners)))
    corner_of[np.arange(len(tyres)), rig.tyre_corner] = 1.0  # dual tyres: two inputs of one post
    return per_tyre @ corner_of


def transfer(c: np.ndarray, a: np.ndarray, b: np.ndarray, s: np.ndarray) -> np.ndarray:
    """C (s I - A)^-1 B at each of the complex frequencies ``s`` (frequencies x outputs x inputs): through A's
    eigenvectors where they are well conditioned, else one solve per frequency (a defective A: a free rigid-body
    motion)."""
    poles, vectors = np.linalg.eig(a)
    if np.linalg.cond(vectors) < 1e8:
        left, right = c @ vectors, np.linalg.solve(vectors, b.astype(complex))
        return np.einsum("mk,fk,kt->fmt", left, 1.0 / (s[:, None] - poles[None, :]), right, optimize=True)
    identity = np.eye(a.shape[0])
    return np.stack([c @ np.linalg.solve(sk * identity - a, b) for sk in s])


def state_space(model: mujoco.MjModel, state: np.ndarray, step: float = 1e-6
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Continuous-time A, B, C, D of ``model`` at the full physics ``state`` (state: joint positions in the tangent
    space, velocities, actuator activations; inputs: the controls; outputs: the sensor data), by central differences
    of ``mj_forward``. MuJoCo's own ``mjd_transitionFD`` gives the discrete matrices of one step, but not for the
    RK4 integrator the models run on; at the models' steps (under a millisecond) RK4 follows the continuous
    equations to well within the measurement noise in the analysis band."""
    data = mujoco.MjData(model)
    nv, na, nu = model.nv, model.na, model.nu

    def evaluate(dx: np.ndarray, du: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        mujoco.mj_setState(model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        mujoco.mj_integratePos(model, data.qpos, dx[:nv], 1.0)
        data.qvel[:] += dx[nv:2 * nv]
        data.act[:] += dx[2 * nv:]
        data.ctrl[:] = du  # the replay's inputs are changes from rest, its controls 0 at rest
        mujoco.mj_forward(model, data)
        return np.concatenate([data.qvel, data.qacc, data.act_dot]), data.sensordata.copy()

    n = 2 * nv + na
    columns = []
    for i in range(n + nu):
        shift = np.zeros(n + nu)
        shift[i] = step
        (rate_up, out_up), (rate_down, out_down) = evaluate(shift[:n], shift[n:]), evaluate(-shift[:n], -shift[n:])
        columns.append((np.concatenate([rate_up, out_up]) - np.concatenate([rate_down, out_down])) / (2 * step))
    jacobian = np.column_stack(columns)
    return jacobian[:n, :n], jacobian[:n, n:], jacobian[n:, :n], jacobian[n:, n:]


def channel_selection(sim: Simulator, names: list[str]) -> np.ndarray:
    """The linear map from sensor data to the named car channels (channels x sensor data), as the replay forms
    them (rig/sim/simulate.py ``sensor_responses``: constants such as gravity and static lengths drop out)."""
    rig, n = sim.rig, sim.rig.model.nsensordata
    corners = len(rig.corners)
    zero = sensor_responses(rig, np.zeros(corners), np.zeros((1, n)), np.zeros(2 * corners))
    unit = sensor_responses(rig, np.zeros(corners), np.eye(n), np.zeros(2 * corners))
    rows = []
    for name in names:
        corner, quantity = name.split("/")
        column = rig.corners.index(corner)
        rows.append(unit[quantity][:, column] - zero[quantity][0, column])
    return np.array(rows)


def linear_response(experiment: Experiment, vehicle: Vehicle) -> np.ndarray:
    """The compared car channels (samples x channels, band-passed, settling samples left out) of ``vehicle`` on the
    experiment's posts, as ``Experiment.simulate_car`` forms them, from its frequency response times the posts'
    transform instead of time stepping (exact for a linear car that starts at rest, as the replay's does). The response
    is formed up to the Nyquist frequency: a record cut from a longer one ends with its posts moving, the zeros after
    it make a step there, and a response cut off above twice the band's top rang back from that step into the record
    (a split's fit part missed its time-domain run by 0.9-1.6 % of a wheel's acceleration, 0.02-0.05 % so)."""
    if experiment.wheel_angles is not None or len(experiment.posts.names) != len(experiment.corners):
        raise ValueError("the frequency-domain fit takes post displacements as the only inputs, not wheel angles or "
                         "actuator forces")
    posts = experiment.posts.quantity("actuator_disp", experiment.corners)
    rate, n = experiment.record.rate, posts.shape[0]
    length = n + int(DECAY_SECONDS * rate)
    frequencies = np.fft.rfftfreq(length, 1 / rate)
    spectrum = np.fft.rfft(posts, length, axis=0)
    response = np.einsum("fcp,fp->fc", frequency_response(vehicle, experiment, frequencies), spectrum)
    channels = np.fft.irfft(response, length, axis=0)[:n]
    return band_pass(channels, rate, experiment.band)[experiment.settle:]


def stays_linear(experiment: Experiment, vehicle: Vehicle) -> bool:
    """Whether ``vehicle`` stays linear on the experiment's posts: its linear response and its time-domain run (one
    simulation, kept by the experiment for the fits that follow) differ by at most LINEARITY_TOLERANCE."""
    try:
        linear = linear_response(experiment, vehicle)
    except ValueError:  # inputs the linear response does not take
        return False
    stepped = experiment.simulate_car([vehicle])[0]
    error = np.sqrt(np.mean((linear - stepped) ** 2, axis=0) / np.maximum(np.mean(stepped**2, axis=0), 1e-300))
    return bool(np.max(error) <= LINEARITY_TOLERANCE)


def linear_trials(experiment: Experiment) -> Callable[[list[Vehicle]], list[np.ndarray]]:
    """A fit's trials on the frequency response (rig/diagnosis/core/fitting.py ``fit_car``'s ``simulate``): each
    vehicle's ``linear_response``; one that no vehicle can be (INFEASIBLE) gets the measured channels negated, as
    ``Experiment.simulate_trials`` gives it."""
    return lambda vehicles: feasible(lambda each: [linear_response(experiment, v) for v in each], vehicles,
                                     -experiment.measured)


def fit_car_frequency(experiment: Experiment, vehicle: Vehicle, params: list[FitParameter],
                      start: np.ndarray | None = None, max_evaluations: int = 8,
                      known: Mapping[int, np.ndarray] | None = None) -> FitResult:
    """Fit ``params`` (parameters that keep the car linear) to the car channels of ``experiment`` as
    rig/diagnosis/core/fitting.py ``fit_car`` does (the same residual, bounds, scales, steps and secant Jacobian,
    intervals from differences at the solution), each trial's channels from ``linear_response``."""
    return fit_car(experiment, vehicle, params, start, max_evaluations, known, linear_trials(experiment))
