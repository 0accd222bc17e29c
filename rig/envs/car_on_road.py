"""The car driven over a road with a controller's actuator at every corner: the suspension environments' plant.

The model is the track run's (rig/sim/track.py: the road under each tyre at the speed, on ideal posts),
with one actuator per corner added to the MJCF, so that its force stays inside ``mj_step``:

- ``force`` (active suspension): a ``general`` actuator on the suspension tendon (body to hub), in
  parallel with spring and damper; the action is its force in N, positive pushing body and wheel apart
  (it lowers the travel, compression positive), bounded by ``force_limit``;
- ``damping`` (semi-active): the damper's linear coefficient becomes the action: an actuator on the
  damper tendon with affine gain, F = -c x extension rate, c in [c_min, c_max] N s/m; it only dissipates.

The road enters as in a track run (the same per-substep tyre inputs), so a zero force reproduces
``rig track`` bit for bit. With ``random_spec`` (an ISO 8608 spec without a seed) every copy drives over a
new road each episode, its seed drawn from the copy's random generator. The action is held over each control period
(zero-order hold) and acts from the substep it is taken at on: never earlier.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from rig.elements.tendons import damper_of
from rig.envs.plant import Plant
from rig.envs.ride_metrics import RewardWeights, RideMetrics
from rig.envs.sensing import SensorMap
from rig.road.roads import RoadError, RoadProfile, road_from_spec
from rig.sim.simulate import Simulator
from rig.sim.track import check_speed, wheel_road_heights
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import Vehicle

CONTROLS = ("force", "damping")
#: Observed quantities per corner, in this order (then the optional road preview).
OBSERVED = ("sprung_acc", "unsprung_acc", "susp_travel", "susp_velocity")
ROAD_BOUND = 1e4  # m: bound of the road preview in the observation space


@dataclass
class CarOnRoad(Plant):
    """A settled car-on-road model with its controller actuators, and the road's inputs for one episode."""

    vehicle: Vehicle
    control: str
    low: float                    # action bound (N or N s/m)
    high: float
    sim: Simulator
    heights: np.ndarray           # (roads, samples, corners) m: road under each tyre at the sample times
    inputs: np.ndarray            # (roads, n_steps * substeps + 1, nu): the road's tyre inputs per substep; one
                                  # road for every copy, or one per copy
    action_ctrl: np.ndarray       # ctrl index of each corner's controller actuator
    action_ids: np.ndarray        # actuator id of each corner's controller actuator
    preview: int                  # road samples ahead in the observation
    travel_limit: float           # m: travel beyond it is penalised
    weights: RewardWeights
    speed: float                  # m/s
    duration: float               # s
    random_spec: str | None = None  # ISO 8608 spec without a seed: a new road per copy and episode

    observed = OBSERVED
    preview_bound = ROAD_BOUND

    @property
    def previewed(self) -> np.ndarray:
        """The road under each tyre (roads, samples, corners)."""
        return self.heights

    @property
    def rest_action(self) -> np.ndarray:
        """The action before the first step: no force, or the nominal damping."""
        rest = np.zeros(self.action_size) if self.control == "force" else self.nominal_damping()
        return np.clip(rest, self.low, self.high)

    def new_metrics(self, copies: int, sensors: SensorMap) -> RideMetrics:
        return RideMetrics(self.rate, self.sim.static.tyre_force, copies, self.travel_limit, self.weights, sensors)

    def nominal_damping(self) -> np.ndarray:
        """The vehicle file's linear damping per corner (N s/m)."""
        return np.array([self.vehicle.axle(c).damping for c in self.corners])

    def new_episode(self, generators: list[np.random.Generator]) -> None:
        """With ``random_spec``, a new road for each copy, its seed drawn from the copy's generator."""
        if self.random_spec is not None:
            self.drive_over([road_from_spec(f"{self.random_spec},seed={int(g.integers(2**31))}") for g in generators])

    def drive_over(self, roads: list[RoadProfile]) -> None:
        """Set the road inputs: one road for every copy, or one per copy."""
        heights = [wheel_road_heights(self.vehicle, road, self.speed, self.duration, self.rate) for road in roads]
        self.heights = np.stack([np.stack([h[c] for c in self.corners], axis=-1) for h in heights])
        self.inputs = self.sim.controls(self.heights)

    def extra_quantities(self, k: int, force: np.ndarray) -> dict[str, np.ndarray]:
        """The road under each tyre and ``control_force``, the controller actuators' forces (copies, corners)."""
        road = np.empty(force.shape)
        road[...] = self.heights[:, k]
        return {"road": road, "control_force": force}


def car_on_road(vehicle: Vehicle, road: RoadProfile, speed: float, duration: float | None, rate: float,
                control: str, low: float, high: float, preview_s: float = 0.0, travel_limit: float = 0.08,
                weights: RewardWeights | None = None, random_spec: str | None = None) -> CarOnRoad:
    """Build and settle the model with ``control`` actuators bounded by [low, high]; the road's inputs as
    ``track_run`` makes them (default duration: until the front axle reaches the road's end). ``random_spec``:
    see CarOnRoad."""
    if control not in CONTROLS:
        raise ValueError(f"control must be one of {', '.join(CONTROLS)}, got {control!r}")
    if not (np.isfinite(low) and np.isfinite(high) and low < high):
        raise ValueError(f"action bounds must be finite with low < high, got [{low}, {high}]")
    if control == "damping" and low < 0:
        raise ValueError(f"a semi-active damper only dissipates: c_min must be >= 0 N s/m, got {low}")
    if not travel_limit > 0:
        raise ValueError(f"travel_limit must be positive (m), got {travel_limit}")
    if not preview_s >= 0:
        raise RoadError(f"road preview must be >= 0 s, got {preview_s}")
    check_speed(speed)
    duration = road.length / speed if duration is None else duration
    rig = build_model(vehicle, rate, "ideal", extend=lambda spec: _add_actuators(spec, vehicle, control, low, high))
    action_ids = np.array([rig.model.actuator(f"{c}/control").id for c in rig.corners])
    plant = CarOnRoad(vehicle, control, float(low), float(high), Simulator.create(rig), np.zeros(0), np.zeros(0),
                      rig.model.actuator_ctrladr[action_ids].astype(int), action_ids, int(round(preview_s * rate)),
                      float(travel_limit), weights or RewardWeights(), float(speed), float(duration), random_spec)
    plant.drive_over([road])
    return plant


def _add_actuators(spec: mujoco.MjSpec, vehicle: Vehicle, control: str, low: float, high: float) -> None:
    for corner in vehicle.corners:
        tendon = f"car.{corner}/suspension" if control == "force" else damper_of(spec, f"car.{corner}").name
        actuator = spec.add_actuator(name=f"{corner}/control", target=tendon)
        actuator.trntype = mujoco.mjtTrn.mjTRN_TENDON
        actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        actuator.ctrlrange = [low, high]
        if control == "force":
            actuator.gainprm[0] = 1.0
        else:  # F = (0 + 0 * length - 1 * velocity) * c: the damper's linear part, c from the action
            actuator.gaintype = mujoco.mjtGain.mjGAIN_AFFINE
            actuator.gainprm[:3] = [0.0, 0.0, -1.0]
            damping = spec.tendon(tendon).damping
            spec.tendon(tendon).damping = [0.0, *damping[1:]]

