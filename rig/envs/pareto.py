"""The passive comfort / road-holding front of a car on a road, and how far a controller lies below it.

The front: the car with its dampers scaled (constant coefficients, semi-active env), all settings run as
copies of one vector env. A controller's gain is measured at its own tyre load: the front's a_w
(the best a_w of the passive curve at no more tyre load) against the controller's a_w.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rig.envs.suspension import SemiActiveSuspensionVectorEnv

#: damping scales of the sweep: 0.4-1.0 (the usual range) and softer, so that controllers that load the tyre
#: more than the damper at 0.4 are still compared at their own tyre load
DEFAULT_SCALES = (0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)


@dataclass(frozen=True)
class FrontPoint:
    scale: float                 # damping over the vehicle file's
    metrics: dict[str, float]    # a_w, tyre_load_rms, travel_rms, power_w


def passive_front(scales: Sequence[float] = DEFAULT_SCALES, nthread: int = 0, **env_kwargs) -> list[FrontPoint]:
    """Metrics of the passive car at each damping scale (env_kwargs as the suspension envs take them)."""
    scales = np.asarray(scales, float)
    if scales.size == 0 or np.any(scales <= 0):
        raise ValueError(f"damping scales must be positive, got {list(scales)}")
    env = SemiActiveSuspensionVectorEnv(num_envs=scales.size, nthread=nthread, physical_actions=True,
                                        c_min=0.0, c_max=1e6, **env_kwargs)
    actions = scales[:, None] * env.plant.nominal_damping()[None, :]
    env.reset()
    truncated = np.zeros(scales.size, bool)
    while not truncated.all():
        _, _, _, truncated, infos = env.step(actions)
    return [FrontPoint(float(s), {k: float(infos[k][i]) for k in ("a_w", "tyre_load_rms", "travel_rms", "power_w")})
            for i, s in enumerate(scales)]


def front_comfort(front: Sequence[FrontPoint], tyre_load: float) -> float | None:
    """The best a_w the passive settings reach with a tyre load of at most ``tyre_load`` (the curve through
    the settings, in order of scale, taken piecewise linear); None if every setting loads the tyre more."""
    ordered = sorted(front, key=lambda p: p.scale)
    load = np.array([p.metrics["tyre_load_rms"] for p in ordered])
    comfort = np.array([p.metrics["a_w"] for p in ordered])
    share = np.linspace(0.0, 1.0, 201)[:, None]
    dense_load = (load[:-1] + share * np.diff(load)).ravel() if load.size > 1 else load
    dense_comfort = (comfort[:-1] + share * np.diff(comfort)).ravel() if load.size > 1 else comfort
    inside = dense_load <= tyre_load
    return float(dense_comfort[inside].min()) if inside.any() else None


def below_front(front: Sequence[FrontPoint], metrics: dict[str, float]) -> float | None:
    """How far ``metrics``' a_w lies below the front at its own tyre load, as a fraction of the front's a_w
    there (0.1: 10 % below; negative: above); None where no passive setting holds the road as well."""
    reference = front_comfort(front, metrics["tyre_load_rms"])
    return None if reference is None else 1.0 - metrics["a_w"] / reference
