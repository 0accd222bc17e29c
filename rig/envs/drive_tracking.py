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

import numpy as np

from rig.envs.env import PlantEnv, PlantVectorEnv
from rig.envs.plant import Plant
from rig.envs.sensing import SensorMap
from rig.envs.suspension import DEFAULT_ROAD
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.road.roads import RoadProfile, road_from_spec
from rig.sim.simulate import Simulator
from rig.sim.track import track_run
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import Vehicle, load_vehicle

TRACKED = ("sprung_acc", "unsprung_acc")
OBSERVED = ("sprung_acc", "unsprung_acc", "actuator_disp")  # the tracked quantities first
TARGET_BOUND = 1e4  # m/s^2: bound of the target preview in the observation space


@dataclass
class TrackingSummary:
    rms_error_pct: np.ndarray  # running RMS error in percent of the target's RMS, worst channel, per copy


class TrackingMetrics:
    """Running sums of squared tracking errors per copy and tracked channel."""

    def __init__(self, copies: int, target: np.ndarray, sensors: SensorMap):
        if sensors.names[:len(TRACKED)] != TRACKED:
            raise ValueError(f"the sensor map must give the tracked quantities {TRACKED} first")
        self.target = target
        self.target_rms = np.sqrt(np.mean(target**2, axis=0))
        self.tracked = slice(0, sensors.slice(TRACKED[-1]).stop)  # TRACKED x corners, quantity-major
        self.sums = np.zeros((copies, target.shape[1]))
        self.count = 0  # samples so far: the copies run in lockstep

    def reset(self) -> None:
        self.sums[...] = 0.0
        self.count = 0

    def update(self, k: int, sensed: np.ndarray, power: np.ndarray) -> np.ndarray:
        """Add sample ``k``; the reward: minus the mean over channels of (error / target RMS)²."""
        error = sensed[:, self.tracked] - self.target[k]
        self.sums += error**2
        self.count += 1
        return -np.mean((error / self.target_rms) ** 2, axis=1)

    def summary(self) -> TrackingSummary:
        rms = np.sqrt(self.sums / max(self.count, 1))
        return TrackingSummary(100 * np.max(rms / self.target_rms, axis=1))


@dataclass
class RigTracking(Plant):
    """The settled rig with servo posts and the target it should reproduce."""

    sim: Simulator
    target: np.ndarray      # (samples, channels) SI, channels TRACKED x corners (quantity-major)
    preview: int            # target samples ahead in the observation
    inputs: np.ndarray      # (1, n_steps * substeps + 1, nu): zeros, the post drives (the actions) are all

    observed = OBSERVED
    preview_bound = TARGET_BOUND

    @property
    def previewed(self) -> np.ndarray:
        return self.target[None]

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
    def action_ctrl(self) -> np.ndarray:
        return self.sim.rig.servo_ctrl

    @property
    def action_ids(self) -> np.ndarray:
        return self.sim.rig.servo_ids

    def channel_names(self) -> list[str]:
        return [channel(c, q) for q in TRACKED for c in self.corners]

    def new_episode(self, generators: list[np.random.Generator]) -> None:
        """Every episode tracks the same target."""

    def new_metrics(self, copies: int, sensors: SensorMap) -> TrackingMetrics:
        return TrackingMetrics(copies, self.target, sensors)


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
    inputs = np.zeros((1, sim.control_steps(target.n_samples), sim.rig.model.nu))
    return RigTracking(sim, np.stack([target[n] for n in names], axis=1), int(round(preview * rate)), inputs)


class DriveTrackingEnv(PlantEnv):
    """Online drive control of the rig: actions are post drives in m."""

    def __init__(self, physical_actions: bool = False, **kwargs):
        super().__init__(tracking_plant(**kwargs), not physical_actions)


class DriveTrackingVectorEnv(PlantVectorEnv):
    def __init__(self, num_envs: int = 1, nthread: int = 0, physical_actions: bool = False, **kwargs):
        super().__init__(tracking_plant(**kwargs), num_envs, nthread, not physical_actions)
