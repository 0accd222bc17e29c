"""Fit a car's linear parameters on its frequency response instead of time stepping.

Where the car is linear, a whole record's response is its frequency response times the inputs' spectra: the fit
compares the linearised MuJoCo model's cross-spectra with the posts, H(f) S_uu(f), with the measured S_yu(f)
(Welch's estimates, ``scipy.signal.csd``) at the analysis band's frequencies, and needs no simulation per trial.
The model's response is that of the same MuJoCo model the time-domain fit runs: central differences of
``mj_forward`` give its continuous A, B, C, D at the settled state (inputs: each tyre's road height, fed
height + (c_t / k_t) x its rate as the replay feeds it; outputs: the car channels, formed from the sensors as the
replay forms them), evaluated at z = exp(j 2 pi f h). The input actuators' reading delay, which the replay
compensates by feeding them early, is taken out of the linearised copy. The rest (the least squares, its
bounds and scales, the confidence intervals from the Jacobian) is the time-domain fit's (rig/diagnosis/fitting.py);
the residual counts as the record's 2 B T independent values per channel there too. Written here because no library
linearises a MuJoCo model's input-output map to channels: SciPy gives the spectra and the least squares.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from scipy.optimize import least_squares
from scipy.signal import csd

from rig.causes import FitParameter
from rig.diagnosis.experiment import INFEASIBLE, Experiment
from rig.diagnosis.fitting import FitResult, build, independent_samples
from rig.sim.simulate import Simulator, sensor_responses
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import Vehicle

SEGMENT_SECONDS = 4.0  # s: Welch's segments (0.25 Hz resolution), halved until a record holds eight of them


@dataclass(frozen=True)
class Spectra:
    """A record's spectra at the analysis band's frequencies: cross-spectra of the channels with the posts
    (frequencies x channels x posts) and the channels' power (frequencies x channels), one-sided."""

    frequencies: np.ndarray  # Hz
    inputs: np.ndarray       # frequencies x posts x posts: the posts' cross-spectral matrix S_uu, m^2/Hz
    cross: np.ndarray        # frequencies x channels x posts: S_yu
    power: np.ndarray        # frequencies x channels: S_yy


def measured_spectra(experiment: Experiment) -> Spectra:
    """Welch's spectra of the experiment's compared part: the measured channels against the posts as fed to the
    model."""
    rate, start = experiment.record.rate, experiment.settle
    posts = experiment.posts.quantity("actuator_disp", experiment.corners)[start:]
    channels = np.column_stack([experiment.record[n] for n in experiment.car_channels])[start:]
    segment = int(SEGMENT_SECONDS * rate)
    while segment > 64 and 8 * segment > 2 * len(posts):
        segment //= 2
    f, s_uu = csd(posts[:, None, :], posts[:, :, None], rate, nperseg=segment, axis=0)
    _, s_yu = csd(posts[:, None, :], channels[:, :, None], rate, nperseg=segment, axis=0)
    _, s_yy = csd(channels, channels, rate, nperseg=segment, axis=0)
    keep = (f >= experiment.band[0]) & (f <= experiment.band[1])
    return Spectra(f[keep], s_uu[keep], s_yu[keep], s_yy[keep].real)


def frequency_response(vehicle: Vehicle, experiment: Experiment, frequencies: np.ndarray) -> np.ndarray:
    """The car channels' response to each post's displacement (frequencies x channels x posts; m/s^2 or m per m)
    of ``vehicle`` on ideal posts, linearised at its settled state."""
    sim = Simulator.create(build_model(vehicle, experiment.record.rate, "ideal", None, experiment.longest))
    rig, model = sim.rig, sim.rig.model
    model.actuator_delay[:] = 0.0  # the replay feeds the inputs early by their reading delay: none is left
    a, b, c, d = state_space(model, sim.static.state)
    select = channel_selection(sim, experiment.car_channels)
    lead = 1.0 + sim.tyre_time_constants()[rig.tyre_corner][None, :] * 2j * np.pi * np.asarray(frequencies)[:, None]
    feed = np.zeros((len(frequencies), model.nu, len(rig.corners)), complex)  # tyre inputs per post displacement
    feed[:, rig.tyre_ctrl, rig.tyre_corner] = lead
    identity = np.eye(a.shape[0])
    out = np.empty((len(frequencies), select.shape[0], len(rig.corners)), complex)
    for k, (fk, sk) in enumerate(zip(feed, 2j * np.pi * np.asarray(frequencies))):
        out[k] = select @ ((c @ np.linalg.solve(sk * identity - a, b) + d) @ fk)
    return out


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


def fit_car_frequency(experiment: Experiment, vehicle: Vehicle, params: list[FitParameter],
                      start: np.ndarray | None = None, max_evaluations: int = 30,
                      spectra: Spectra | None = None) -> FitResult:
    """Fit ``params`` (parameters that keep the car linear) to the measured cross-spectra of ``experiment``;
    ``.x`` holds the values, ``.jac`` the Jacobian at them, ``.independent`` the record's independent values, as
    rig/diagnosis/fitting.py ``fit_car`` returns them."""
    spectra = measured_spectra(experiment) if spectra is None else spectra
    x0 = np.array([p.initial for p in params]) if start is None else np.asarray(start, float)
    low, high = np.array([p.low for p in params]), np.array([p.high for p in params])
    sizes = np.array([p.typical or p.high - p.low for p in params])
    posts_power = np.real(np.trace(spectra.inputs, axis1=1, axis2=2))
    scale = np.sqrt(np.mean(spectra.power * posts_power[:, None], axis=0))  # per channel, like fit_car's rms
    worst = -spectra.cross  # an infeasible trial scores as the measured cross-spectra negated, as fit_car's

    def fun(x: np.ndarray) -> np.ndarray:
        try:
            model = np.einsum("fcp,fpq->fcq", frequency_response(build(vehicle, params, x), experiment,
                                                                 spectra.frequencies), spectra.inputs)
        except INFEASIBLE:
            model = worst
        residual = (model - spectra.cross) / scale[None, :, None]
        return np.concatenate([residual.real.ravel(), residual.imag.ravel()])

    result = least_squares(fun, np.clip(x0, low, high), bounds=(low, high), x_scale=sizes,
                           diff_step=[p.relative_step or 0.01 for p in params], max_nfev=max_evaluations,
                           method="trf", ftol=1e-6, xtol=1e-6)
    result = FitResult(result)
    result.independent = independent_samples(experiment, len(experiment.car_channels))
    return result
