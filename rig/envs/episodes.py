"""Copies of one plant run in lockstep through an episode: the logic shared by the single and vector envs.

A plant (rig/envs/plant.py: ``CarOnRoad``, ``RigTracking``) says what the model is, which controls a step
applies, what is observed and how a step is scored; a stepper (rig/envs/stepping.py) advances the copies in
C. Env step k holds the action over the substeps from sample k to sample k + 1 and returns the observation
at sample k + 1; the episode is truncated when the last sample is reached (the road's or the target's end).

A step costs a fixed number of array operations over all copies, whatever their number (no Python per
copy): the controls are the plant's inputs with the actions written in; the sensors are converted in one
gather (rig/envs/sensing.py); the metrics update all copies at once. The contract quantities of the last
observation (``quantities``) are put together only when asked for.
"""

from __future__ import annotations

import numpy as np

from rig.envs.plant import Plant
from rig.envs.sensing import SensorMap
from rig.envs.stepping import BatchStepper, LoopStepper

_ONE, _MINUS_ONE = np.array(1.0), np.array(-1.0)


def _as_slice(indices: np.ndarray) -> slice | np.ndarray:
    """``indices`` as a slice where they are consecutive (a view, not a copy, when indexing), else as they are."""
    indices = np.asarray(indices)
    if indices.size and np.array_equal(indices, np.arange(indices[0], indices[0] + indices.size)):
        return slice(int(indices[0]), int(indices[0]) + indices.size)
    return indices


class Episodes:
    """``copies`` runs of ``plant`` stepped by ``stepper``; all copies share the step index. Actions are in the
    plant's units (N, N s/m, m) within [plant.low, plant.high], or with ``normalized`` in [-1, 1] mapped
    linearly onto those bounds. (Actions are clipped with ``fmin`` and ``fmax``, as ``np.clip`` for the finite
    actions that are accepted, and faster.)"""

    def __init__(self, plant: Plant, copies: int, stepper: LoopStepper | BatchStepper, normalized: bool = True):
        self.plant, self.copies, self.stepper, self.normalized = plant, copies, stepper, normalized
        self.sensors = SensorMap.of(plant.sim, plant.observed)
        self.metrics = plant.new_metrics(copies, self.sensors)
        self.k, self.n_steps = 0, plant.n_steps
        self.actions = np.zeros((copies, plant.action_size))
        self._action_ctrl, self._action_ids = _as_slice(plant.action_ctrl), _as_slice(plant.action_ids)
        self._observed = slice(0, len(plant.observed) * len(plant.corners))
        self._controls = np.empty((copies, plant.substeps + 1, plant.model.nu))
        self._sensed = np.zeros((copies, len(self.sensors.columns)))
        # action bounds as 0-d arrays (numpy converts a Python float at every call); (high - low) / 2 is exact,
        # so (a + 1) * ((high - low) / 2) is (a + 1) / 2 * (high - low) bit for bit
        self._bounds = np.array(float(plant.low)), np.array(float(plant.high))
        self._half_range = np.array((plant.high - plant.low) / 2)
        self._force = np.zeros((copies, plant.action_size))

    def reset(self, generators: list[np.random.Generator]) -> np.ndarray:
        """Every copy back at the initial state, on the plant's inputs for a new episode (``generators``: one
        per copy, for a plant that draws them); returns the observations (copies, size) at sample 0."""
        self.plant.new_episode(generators)
        self.k, self.n_steps = 0, self.plant.n_steps
        self.metrics.reset()
        self.actions = np.repeat(self.plant.rest_action[None], self.copies, axis=0)
        self.stepper.reset(self.plant.sim.static.state, self._held_controls()[:, 0])
        return self._observe()[0]

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
        """Hold ``actions`` (copies, action_size) for one control period: observations, rewards, truncated."""
        plant = self.plant
        if self.k >= self.n_steps:
            raise RuntimeError("the episode is over (the end of the road or target was reached): call reset()")
        actions = np.asarray(actions, float).reshape(self.copies, plant.action_size)
        if not np.isfinite(actions).all():
            raise ValueError(f"actions must be finite, got {actions}")
        low, high = self._bounds
        if self.normalized:  # low + (clip(a, -1, 1) + 1) / 2 * (high - low), in place
            actions = np.fmin(np.fmax(actions, _MINUS_ONE), _ONE)
            np.add(actions, _ONE, out=actions)
            np.multiply(actions, self._half_range, out=actions)
            np.add(actions, low, out=actions)
            self.actions = np.fmin(np.fmax(actions, low, out=actions), high, out=actions)
        else:
            actions = np.fmax(actions, low)  # a new array: the caller's is left as it is
            self.actions = np.fmin(actions, high, out=actions)
        self.stepper.advance(self._held_controls())
        self.k += 1
        obs, reward = self._observe()
        return obs, reward, self.k >= self.n_steps

    def _held_controls(self) -> np.ndarray:
        """Controls (copies, substeps + 1, nu) of step k's substeps and of the substep after it (which the
        sensors at the step's end see), the actions held over all of them."""
        n, ctrl = self.plant.substeps, self._controls
        ctrl[...] = self.plant.inputs[:, self.k * n:(self.k + 1) * n + 1]
        ctrl[:, :, self._action_ctrl] = self.actions[:, None, :]
        return ctrl

    def _observe(self) -> tuple[np.ndarray, np.ndarray]:
        sensordata, force, velocity = self.stepper.outputs()
        self._sensed = sensed = self.sensors.convert(sensordata)
        self._force = force = force[:, self._action_ids].copy()
        reward = self.metrics.update(self.k, sensed, force * velocity[:, self._action_ids])
        return self._observation(sensed), reward

    def _observation(self, sensed: np.ndarray) -> np.ndarray:
        """The observed quantities per corner, then ``preview`` samples ahead of each previewed channel."""
        observed = sensed[:, self._observed]
        preview = self.plant.preview
        if not preview:
            return observed.copy()
        previewed = self.plant.previewed
        ahead = np.arange(self.k + 1, self.k + 1 + preview).clip(max=previewed.shape[1] - 1)
        window = previewed[:, ahead].transpose(0, 2, 1).reshape(previewed.shape[0], -1)  # channel-major
        return np.concatenate([observed, np.broadcast_to(window, (self.copies, window.shape[1]))], axis=1)

    @property
    def quantities(self) -> dict[str, np.ndarray]:
        """Contract quantities (copies, corners) at the last observation: the sensors', then the plant's."""
        return {**self.sensors.quantities(self._sensed), **self.plant.extra_quantities(self.k, self._force)}

    def info(self) -> dict[str, np.ndarray]:
        """Running metrics and the time (s) of the observation, each an array over copies."""
        return {**vars(self.metrics.summary()), "time": np.full(self.copies, self.k / self.plant.rate)}
