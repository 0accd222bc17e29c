"""One episode of an environment under a policy, as a contract record and its metrics (``rig control``)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np

from rig.io.channels import channel
from rig.io.record import Record


@dataclass
class PolicyRun:
    record: Record               # every quantity the env tracks, per corner, at the control rate (SI)
    metrics: dict[str, float]    # the env's running metrics at the end (info)
    model: mujoco.MjModel | None = field(default=None, repr=False)  # the plant's model...
    qpos: np.ndarray | None = field(default=None, repr=False)       # ...and its joint positions per sample


def run_policy(env, policy: Callable[[np.ndarray], np.ndarray], metadata: dict[str, str] | None = None) -> PolicyRun:
    """Reset ``env`` (a PlantEnv, possibly wrapped) and step it with ``policy(obs) -> action`` to the end."""
    episodes = env.unwrapped.episodes
    obs, info = env.reset()
    samples = {q: [v[0].copy()] for q, v in episodes.quantities.items()}
    data = getattr(episodes.stepper, "data", None)  # one copy stepped in Python: its joint positions too
    qpos = [] if data is None else [data.qpos.copy()]
    truncated = False
    while not truncated:
        obs, _, terminated, truncated, info = env.step(policy(obs))
        truncated = truncated or terminated
        for q, v in episodes.quantities.items():
            samples[q].append(v[0].copy())
        if data is not None:
            qpos.append(data.qpos.copy())
    plant = env.unwrapped.plant
    channels = {channel(c, q): np.array(values)[:, i] for q, values in samples.items()
                for i, c in enumerate(plant.corners)}
    return PolicyRun(Record(plant.rate, channels, metadata=dict(metadata or {})),
                     {k: v for k, v in info.items() if k != "time"}, plant.model if qpos else None,
                     np.array(qpos) if qpos else None)
