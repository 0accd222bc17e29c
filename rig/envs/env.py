"""Gymnasium faces of a plant: ``PlantEnv`` (one copy, ``mj_step`` in a loop) and ``PlantVectorEnv`` (many
copies in MuJoCo's batch, for ``gym.make_vec(..., vectorization_mode="vector_entry_point")``).

Actions are normalized by default (``physical_actions=False``): [-1, 1] maps linearly onto the plant's bounds
(force limit, [c_min, c_max], post stroke), as RL libraries expect and ``check_env`` asks;
``physical_actions=True`` takes them in N, N s/m or m (the controllers of ``controllers/`` use that).

The vector env autoresets as gymnasium's ``SyncVectorEnv`` does by default (``NEXT_STEP``): the step after
the last one resets every copy and returns reward 0. Its copies run in lockstep on one road, so they
truncate together; observations, rewards and infos equal those of ``SyncVectorEnv`` bit for bit.
"""

from __future__ import annotations

from typing import ClassVar

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from rig.envs.episodes import Episodes
from rig.envs.plant import Plant
from rig.envs.stepping import BatchStepper, LoopStepper


def _spaces(plant: Plant, normalized: bool) -> tuple[gym.spaces.Box, gym.spaces.Box]:
    """Action space ([-1, 1], or the plant's bounds in its units) and observation space (the plant's bounds)."""
    shape = (plant.action_size,)
    if normalized:
        action = gym.spaces.Box(-1.0, 1.0, shape, dtype=np.float64)
    else:
        action = gym.spaces.Box(np.full(shape, plant.low, float), np.full(shape, plant.high, float), dtype=np.float64)
    bound = plant.observation_bound()
    return action, gym.spaces.Box(-bound, bound, dtype=np.float64)


class PlantEnv(gym.Env):
    """One copy of a plant as a ``gym.Env``; ``info`` carries the running metrics."""

    metadata: ClassVar[dict] = {"render_modes": []}

    def __init__(self, plant: Plant, normalized: bool = True):
        self.plant = plant
        self.action_space, self.observation_space = _spaces(plant, normalized)
        self.episodes = Episodes(plant, 1, LoopStepper(plant.model), normalized)
        self._started = False

    def reset(self, *, seed: int | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        super().reset(seed=seed)
        self._started = True
        return self.episodes.reset([self.np_random])[0], self._info()

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        if not self._started:
            raise RuntimeError("call reset() before step()")
        obs, reward, truncated = self.episodes.step(np.asarray(action)[None])
        return obs[0], float(reward[0]), False, bool(truncated), self._info()

    def _info(self) -> dict[str, float]:
        return {key: float(value[0]) for key, value in self.episodes.info().items()}


class PlantVectorEnv(VectorEnv):
    """``num_envs`` copies of a plant in one ``mujoco.batch.Batch`` (``nthread`` threads, 0: all CPUs)."""

    metadata: ClassVar[dict] = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, plant: Plant, num_envs: int, nthread: int = 0, normalized: bool = True):
        if num_envs < 1:
            raise ValueError(f"num_envs must be at least 1, got {num_envs}")
        self.plant, self.num_envs = plant, num_envs
        self.single_action_space, self.single_observation_space = _spaces(plant, normalized)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.episodes = Episodes(plant, num_envs, BatchStepper(plant.model, num_envs, nthread), normalized)
        self._autoreset = False
        self._started = False
        self._generators: list[np.random.Generator] | None = None

    def reset(self, *, seed: int | list[int] | None = None, options: dict | None = None) -> tuple[np.ndarray, dict]:
        mask = (options or {}).get("reset_mask")
        if mask is not None and not np.all(mask):
            raise ValueError("the copies run in lockstep on one road: reset them all (no partial reset_mask)")
        super().reset(seed=seed if isinstance(seed, int) or seed is None else seed[0])
        # one generator per copy, seeded as SyncVectorEnv seeds its envs (seed + i), kept between resets
        seeds = [seed + i for i in range(self.num_envs)] if isinstance(seed, int) else seed
        if seeds is not None or self._generators is None:
            self._generators = [seeding.np_random(s)[0] for s in (seeds or [None] * self.num_envs)]
        self._autoreset, self._started = False, True
        return self.episodes.reset(self._generators), self._infos()

    def step(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        if not self._started:
            raise RuntimeError("call reset() before step()")
        done = np.zeros(self.num_envs, bool)
        if self._autoreset:
            self._autoreset = False
            return self.episodes.reset(self._generators), np.zeros(self.num_envs), done, done.copy(), self._infos()
        obs, reward, truncated = self.episodes.step(actions)
        self._autoreset = truncated
        return obs, reward, done, np.full(self.num_envs, truncated), self._infos()

    def _infos(self) -> dict[str, np.ndarray]:
        """Per-copy infos as gymnasium batches them: an array per key and a ``_key`` mask."""
        info = self.episodes.info()
        masks = np.ones((len(info), self.num_envs), bool)  # every copy has every key
        infos: dict[str, np.ndarray] = {}
        for (key, value), mask in zip(info.items(), masks):
            infos[key] = value
            infos[f"_{key}"] = mask
        return infos
