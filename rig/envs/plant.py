"""What the environments need of a plant (``Plant``) and of its running metrics (``Metrics``).

A plant is a settled MuJoCo model with the inputs of an episode: ``CarOnRoad`` (rig/envs/car_on_road.py: the
car on a road with a controller's actuator per corner) and ``RigTracking`` (rig/envs/drive_tracking.py: the
rig with servo posts and a target). ``Episodes`` (rig/envs/episodes.py) steps any plant, for the single and
the vector env alike: the controls of a step are the plant's ``inputs`` with the held actions written into
the ``action_ctrl`` columns; the observation is the ``observed`` quantities per corner, then ``preview``
samples ahead of ``previewed`` per channel; the plant's metrics score each step. What a plant takes from
its simulator (model, rate, corners, substeps) and what follows from its arrays (episode length, sizes,
observation bounds) is written here once; the plants inherit it.
"""

from __future__ import annotations

from typing import Any, Protocol

import mujoco
import numpy as np

from rig.envs.sensing import SensorMap
from rig.sim.simulate import Simulator

#: Bounds of the observation space per observed quantity (SI: far beyond anything a car on a road or a rig
#: reaches, finite for RL libraries).
BOUNDS = {"sprung_acc": 1e4, "unsprung_acc": 1e4, "susp_travel": 10.0, "susp_velocity": 100.0, "actuator_disp": 10.0}


class Metrics(Protocol):
    """Running metrics of ``copies`` runs in lockstep: updated once per sample, scoring it."""

    def reset(self) -> None:
        """Start every copy afresh."""

    def update(self, k: int, sensed: np.ndarray, power: np.ndarray) -> np.ndarray:
        """Add sample ``k``: ``sensed`` (copies, columns) as the plant's SensorMap converts the sensors, ``power``
        (copies, actions) W the controller's actuators deliver; returns the reward per copy."""

    def summary(self) -> Any:
        """The metrics so far: a dataclass of arrays over copies (its fields are the env's ``info``)."""


class Plant(Protocol):
    """A settled model, the inputs of an episode, what is observed and how a step is scored."""

    sim: Simulator
    low: float                   # action bounds in the plant's units (N, N s/m, m)
    high: float
    preview: int                 # samples of ``previewed`` ahead in the observation
    observed: tuple[str, ...]    # contract quantities observed per corner, in this order
    preview_bound: float         # bound of the previewed values in the observation space
    inputs: np.ndarray           # (roads, n_steps * substeps + 1, nu): the controls per substep but the controller's
    previewed: np.ndarray        # (roads, samples, channels): what the preview reads; its samples set the episode
    action_ctrl: np.ndarray      # ctrl index of each action's actuator
    action_ids: np.ndarray       # actuator id of each action's actuator

    @property
    def rest_action(self) -> np.ndarray:
        """The action held before the first step (action_size,)."""

    def new_episode(self, generators: list[np.random.Generator]) -> None:
        """New inputs for an episode, where the plant draws them (one generator per copy)."""

    def new_metrics(self, copies: int, sensors: SensorMap) -> Metrics:
        """Running metrics of ``copies`` runs reading ``sensors``' columns."""

    def extra_quantities(self, k: int, force: np.ndarray) -> dict[str, np.ndarray]:
        """Contract quantities (copies, corners) at sample ``k`` beside the sensors' (the controller's actuator
        forces are ``force``)."""
        return {}

    @property
    def model(self) -> mujoco.MjModel:
        return self.sim.rig.model

    @property
    def rate(self) -> float:
        """Hz: control and sample rate."""
        return self.sim.rig.rate

    @property
    def substeps(self) -> int:
        return self.sim.rig.steps_per_sample

    @property
    def corners(self) -> tuple[str, ...]:
        return self.sim.rig.corners

    @property
    def n_steps(self) -> int:
        """Env steps in an episode: one per sample after the first."""
        return self.previewed.shape[1] - 1

    @property
    def action_size(self) -> int:
        return len(self.action_ctrl)

    @property
    def observation_size(self) -> int:
        return len(self.corners) * len(self.observed) + self.previewed.shape[2] * self.preview

    def observation_bound(self) -> np.ndarray:
        n = len(self.corners)
        return np.concatenate([np.full(n, BOUNDS[q]) for q in self.observed]
                              + [np.full(self.previewed.shape[2] * self.preview, self.preview_bound)])
