"""Copies of one plant run in lockstep through an episode: the logic shared by the single and vector envs.

A plant (``CarOnRoad``, ``RigTracking``) says what the model is, which controls a step applies, what is
observed and how a step is scored; a stepper (rig/envs/stepping.py) advances the copies in C. Env step k
holds the action over the substeps from sample k to sample k + 1 and returns the observation at sample
k + 1; the episode is truncated when the last sample is reached (the road's or the target's end).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rig.envs.stepping import BatchStepper, LoopStepper


class Episodes:
    """``copies`` runs of ``plant`` stepped by ``stepper``; all copies share the step index. Actions are in the
    plant's units (N, N s/m, m) within [plant.low, plant.high], or with ``normalized`` in [-1, 1] mapped
    linearly onto those bounds."""

    def __init__(self, plant: Any, copies: int, stepper: LoopStepper | BatchStepper, normalized: bool = True):
        self.plant, self.copies, self.stepper, self.normalized = plant, copies, stepper, normalized
        self.k = 0
        self.metrics = plant.new_metrics(copies)
        self.actions = np.zeros((copies, plant.action_size))
        self.quantities: dict[str, np.ndarray] = {}

    def reset(self, generators: list[np.random.Generator]) -> np.ndarray:
        """Every copy back at the initial state, on the plant's inputs for a new episode (``generators``: one
        per copy, for a plant that draws them); returns the observations (copies, size) at sample 0."""
        self.plant.new_episode(generators)
        self.k = 0
        ids = np.arange(self.copies)
        self.metrics.reset(ids)
        self.actions = np.repeat(self.plant.rest_action[None], self.copies, axis=0)
        self.stepper.reset(self.plant.sim.static.state, self.plant.sample_controls(0, self.actions))
        return self._observe()[0]

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
        """Hold ``actions`` (copies, action_size) for one control period: observations, rewards, truncated."""
        if self.k >= self.plant.n_steps:
            raise RuntimeError("the episode is over (the end of the road or target was reached): call reset()")
        actions = np.asarray(actions, float).reshape(self.copies, self.plant.action_size)
        if not np.all(np.isfinite(actions)):
            raise ValueError(f"actions must be finite, got {actions}")
        low, high = self.plant.low, self.plant.high
        if self.normalized:
            actions = low + (np.clip(actions, -1.0, 1.0) + 1.0) / 2.0 * (high - low)
        self.actions = np.clip(actions, low, high)
        self.stepper.advance(self.plant.controls(self.k, self.actions),
                             self.plant.sample_controls(self.k + 1, self.actions))
        self.k += 1
        obs, reward = self._observe()
        return obs, reward, self.k >= self.plant.n_steps

    def _observe(self) -> tuple[np.ndarray, np.ndarray]:
        sensordata, force, velocity = self.stepper.outputs()
        ids = self.plant.action_ids
        self.quantities = self.plant.responses(self.k, sensordata, force[:, ids])
        reward = self.plant.update_metrics(self.metrics, self.k, self.quantities, force[:, ids] * velocity[:, ids])
        return self.plant.observe(self.k, self.quantities), reward

    def info(self) -> dict[str, np.ndarray]:
        """Running metrics and the time (s) of the observation, each an array over copies."""
        return {**self.metrics.summary(), "time": np.full(self.copies, self.k / self.plant.rate)}
