"""``FourPoster/DriveTracking-v0``: online drive control of the rig, the counterpart of drive iteration.

The car stands on the four-poster with servo posts (rig/vehicle/mjcf.py: the drive reaches the post through
the servo's delay, lag and position loop). The action is each post's drive in m (within the stroke),
held over the control period; the target is the record a track run of the same vehicle over the road
gives (or a given target record): body and wheel accelerations per corner. Observation per corner: body
and wheel acceleration (m/s^2) and post displacement (m), then the target's next ``preview`` s of every
tracked channel. Reward: minus the mean over tracked channels of (error / the channel's RMS)², the squared
error over the target's mean square (a target channel that is zero throughout is refused). ``info``: running
RMS error in percent of the target RMS, worst channel (``rms_error_pct``).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rig.envs.env import PlantEnv, PlantVectorEnv
from rig.envs.suspension import DEFAULT_ROAD
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.road.roads import RoadProfile, road_from_spec
from rig.sim.simulate import Simulator, sensor_responses
from rig.sim.track import track_run
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import Vehicle, load_vehicle

TRACKED = ("sprung_acc", "unsprung_acc")
OBSERVED = ("sprung_acc", "unsprung_acc", "actuator_disp")
BOUNDS = {"sprung_acc": 1e4, "unsprung_acc": 1e4, "actuator_disp": 10.0}  # SI, finite for RL libraries


class TrackingMetrics:
    """Running sums of squared tracking errors per copy and tracked channel."""

    def __init__(self, copies: int, target_rms: np.ndarray):
        self.target_rms = target_rms
        self.sums = np.zeros((copies, target_rms.size))
        self.count = np.zeros(copies)

    def reset(self, ids: np.ndarray) -> None:
        self.sums[ids] = 0.0
        self.count[ids] = 0

    def summary(self) -> dict[str, np.ndarray]:
        """Running RMS error in percent of the target's RMS, worst channel, per copy."""
        rms = np.sqrt(self.sums / np.maximum(self.count, 1)[:, None])
        return {"rms_error_pct": 100 * np.max(rms / self.target_rms, axis=1)}


@dataclass
class RigTracking:
    """The settled rig with servo posts and the target it should reproduce."""

    sim: Simulator
    target: np.ndarray      # (samples, channels) SI, channels TRACKED x corners (quantity-major)
    preview: int            # target samples ahead in the observation

    @property
    def model(self) -> mujoco.MjModel:
        return self.sim.rig.model

    @property
    def rate(self) -> float:
        return self.sim.rig.rate

    @property
    def corners(self) -> tuple[str, ...]:
        return self.sim.rig.corners

    @property
    def substeps(self) -> int:
        return self.sim.rig.steps_per_sample

    @property
    def n_steps(self) -> int:
        return self.target.shape[0] - 1

    @property
    def action_size(self) -> int:
        return len(self.corners)

    @property
    def low(self) -> float:
        return -self.sim.rig.vehicle.rig.stroke

    @property
    def high(self) -> float:
        return self.sim.rig.vehicle.rig.stroke

    @property
    def rest_action(self) -> np.ndarray:
        return np.zeros(self.action_size)

    @property
    def action_ids(self) -> np.ndarray:
        return self.sim.rig.servo_ids

    @property
    def observation_size(self) -> int:
        return len(self.corners) * len(OBSERVED) + self.target.shape[1] * self.preview

    def observation_bound(self) -> np.ndarray:
        n = len(self.corners)
        return np.concatenate([np.full(n, BOUNDS[q]) for q in OBSERVED]
                              + [np.full(n * self.preview, BOUNDS[q]) for q in TRACKED])

    def channel_names(self) -> list[str]:
        return [channel(c, q) for q in TRACKED for c in self.corners]

    def new_episode(self, generators: list[np.random.Generator]) -> None:
        """Every episode tracks the same target."""

    def controls(self, k: int, actions: np.ndarray) -> np.ndarray:
        ctrl = np.zeros((actions.shape[0], self.substeps, self.model.nu))
        ctrl[:, :, self.sim.rig.servo_ctrl] = actions[:, None, :]
        return ctrl

    def sample_controls(self, k: int, actions: np.ndarray) -> np.ndarray:
        return self.controls(k, actions)[:, 0]

    def responses(self, k: int, sensordata: np.ndarray, force: np.ndarray) -> dict[str, np.ndarray]:
        """Contract quantities (copies, corners) from sensor data; the servo forces are ``actuator_force`` already."""
        return sensor_responses(self.sim.rig, self.sim.static.suspension_length, sensordata)

    def observe(self, k: int, quantities: dict[str, np.ndarray]) -> np.ndarray:
        parts = [quantities[q] for q in OBSERVED]
        if self.preview:
            ahead = np.arange(k + 1, k + 1 + self.preview).clip(max=self.target.shape[0] - 1)
            parts.append(np.broadcast_to(self.target[ahead].T.ravel(), (parts[0].shape[0], self.target[ahead].size)))
        return np.concatenate(parts, axis=1)

    def new_metrics(self, copies: int) -> TrackingMetrics:
        return TrackingMetrics(copies, np.sqrt(np.mean(self.target**2, axis=0)))

    def update_metrics(self, metrics: TrackingMetrics, k: int, quantities: dict[str, np.ndarray],
                       power: np.ndarray) -> np.ndarray:
        achieved = np.concatenate([quantities[q] for q in TRACKED], axis=1)
        error = achieved - self.target[k]
        metrics.sums += error**2
        metrics.count += 1
        return -np.mean((error / metrics.target_rms) ** 2, axis=1)


def tracking_plant(vehicle: str | Vehicle = "proton_x_quarter", road: str | RoadProfile = DEFAULT_ROAD,
                   speed: float = 20.0, duration: float | None = None, rate: float = 512.0, preview: float = 0.25,
                   target: Record | None = None) -> RigTracking:
    """The rig and its target: ``target`` (a record with the TRACKED channels at ``rate``) or the track run
    of ``vehicle`` over ``road`` at ``speed`` m/s for ``duration`` s."""
    vehicle = vehicle if isinstance(vehicle, Vehicle) else load_vehicle(vehicle)
    if target is None:
        road = road if isinstance(road, RoadProfile) else road_from_spec(road)
        target = track_run(vehicle, road, speed, duration, rate).record
    if target.rate != rate:
        raise RecordError(f"target is sampled at {target.rate:g} Hz, the environment runs at {rate:g} Hz")
    names = [channel(c, q) for q in TRACKED for c in vehicle.corners]
    missing = [n for n in names if n not in target]
    if missing:
        raise RecordError(f"target has no channel(s) {', '.join(missing)}")
    if not preview >= 0:
        raise ValueError(f"preview must be >= 0 s, got {preview}")
    flat = [n for n in names if not np.any(target[n])]
    if flat:
        raise RecordError(f"target channel(s) {', '.join(flat)} are zero throughout: the tracking error is scaled "
                          "by each channel's RMS")
    sim = Simulator.create(build_model(vehicle, rate, "servo"))
    return RigTracking(sim, np.stack([target[n] for n in names], axis=1), int(round(preview * rate)))


class DriveTrackingEnv(PlantEnv):
    """Online drive control of the rig: actions are post drives in m."""

    def __init__(self, physical_actions: bool = False, **kwargs):
        super().__init__(tracking_plant(**kwargs), not physical_actions)


class DriveTrackingVectorEnv(PlantVectorEnv):
    def __init__(self, num_envs: int = 1, nthread: int = 0, physical_actions: bool = False, **kwargs):
        super().__init__(tracking_plant(**kwargs), num_envs, nthread, not physical_actions)
