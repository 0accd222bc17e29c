"""``FourPoster/ActiveSuspension-v0`` and ``FourPoster/SemiActiveSuspension-v0``: a car on a road (as ``rig
track``) with a force actuator or a controllable damper at every corner (rig/envs/car_on_road.py).

Arguments (both): ``vehicle`` (built-in name, file or Vehicle), ``road`` (spec as ``rig track --road``, or a
RoadProfile), ``speed`` (m/s), ``duration`` (s; default: the road's end), ``rate`` (Hz: control and
sample rate, >= 256 for the Wk weighting), ``preview`` (s of road ahead in the observation),
``travel_limit`` (m), ``reward_weights`` (dict of RewardWeights' fields), ``random_road`` (an iso8608 spec
without a seed: a new road each episode, its seed drawn from the env's random generator, so that
``reset(seed=...)`` picks the roads), ``physical_actions`` (rig/envs/env.py:
actions in N or N s/m instead of [-1, 1]). Active: ``force_limit`` (N). Semi-active: ``c_min``, ``c_max`` (N s/m).
Observation per corner: body and wheel acceleration (m/s^2), travel and travel velocity (m, m/s, compression
positive), then the road preview (m).
"""

from __future__ import annotations

from rig.envs.car_on_road import CarOnRoad, car_on_road
from rig.envs.env import PlantEnv, PlantVectorEnv
from rig.envs.ride_metrics import RewardWeights
from rig.road.roads import RoadProfile, road_from_spec
from rig.vehicle.vehicle_file import Vehicle, load_vehicle

DEFAULT_ROAD = "iso8608:class=C,length=500"


def suspension_plant(control: str, low: float, high: float, vehicle: str | Vehicle = "proton_x_quarter",
                     road: str | RoadProfile = DEFAULT_ROAD, speed: float = 20.0, duration: float | None = None,
                     rate: float = 512.0, preview: float = 0.0, travel_limit: float = 0.08,
                     reward_weights: dict | None = None, random_road: bool = False) -> CarOnRoad:
    """The plant of a suspension env from its arguments (see the module docstring)."""
    vehicle = vehicle if isinstance(vehicle, Vehicle) else load_vehicle(vehicle)
    if random_road and not (isinstance(road, str) and road.startswith("iso8608:") and "seed=" not in road):
        raise ValueError("random_road needs an iso8608 road spec without a seed (each episode draws one), "
                         f"got {road!r}")
    profile = road if isinstance(road, RoadProfile) else road_from_spec(road)
    return car_on_road(vehicle, profile, speed, duration, rate, control, low, high, preview, travel_limit,
                       RewardWeights(**(reward_weights or {})), road if random_road else None)


def _force_bounds(force_limit: float) -> tuple[float, float]:
    if not force_limit > 0:
        raise ValueError(f"force_limit must be positive (N), got {force_limit}")
    return -force_limit, force_limit


class ActiveSuspensionEnv(PlantEnv):
    """Active suspension: the action is each corner's actuator force in N (positive extends), |F| <= force_limit."""

    def __init__(self, force_limit: float = 3000.0, physical_actions: bool = False, **kwargs):
        super().__init__(suspension_plant("force", *_force_bounds(force_limit), **kwargs), not physical_actions)


class ActiveSuspensionVectorEnv(PlantVectorEnv):
    def __init__(self, num_envs: int = 1, force_limit: float = 3000.0, nthread: int = 0,
                 physical_actions: bool = False, **kwargs):
        super().__init__(suspension_plant("force", *_force_bounds(force_limit), **kwargs), num_envs, nthread,
                         not physical_actions)


class SemiActiveSuspensionEnv(PlantEnv):
    """Semi-active suspension: the action is each corner's damping coefficient in [c_min, c_max] N s/m."""

    def __init__(self, c_min: float = 200.0, c_max: float = 8000.0, physical_actions: bool = False, **kwargs):
        super().__init__(suspension_plant("damping", c_min, c_max, **kwargs), not physical_actions)


class SemiActiveSuspensionVectorEnv(PlantVectorEnv):
    def __init__(self, num_envs: int = 1, c_min: float = 200.0, c_max: float = 8000.0, nthread: int = 0,
                 physical_actions: bool = False, **kwargs):
        super().__init__(suspension_plant("damping", c_min, c_max, **kwargs), num_envs, nthread, not physical_actions)
