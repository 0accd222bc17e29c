"""A suspension controller driven over a road: one episode of the environment its law needs (active or
semi-active), as a record and its ride metrics; the same run as a sweep point; and a set of controllers placed
against the passive comfort / road-holding front (``rig control --sweep``)."""

from __future__ import annotations

from dataclasses import dataclass

from controllers import ControllerError
from controllers.suspension_laws import CONTROLLERS, make_controller, needs
from rig.envs.pareto import FrontPoint, below_front, passive_front
from rig.envs.policy_run import PolicyRun, run_policy
from rig.envs.suspension import ActiveSuspensionEnv, SemiActiveSuspensionEnv
from rig.io.record import Record


@dataclass(frozen=True)
class ActuatorBounds:
    """What the controller may use: the active force limit (N) and the semi-active damping range (N s/m)."""

    force_limit: float = 5000.0
    c_min: float = 1000.0
    c_max: float = 8000.0


def controlled_episode(spec: str, bounds: ActuatorBounds, env_kwargs: dict) -> PolicyRun:
    """One episode under the controller ``spec`` (``NAME[:k=v,...]``); ``env_kwargs`` as the suspension
    environments take them (vehicle, road, speed, duration, rate)."""
    try:
        if needs(spec) == "force":
            env = ActiveSuspensionEnv(force_limit=bounds.force_limit, physical_actions=True, **env_kwargs)
        else:
            env = SemiActiveSuspensionEnv(c_min=bounds.c_min, c_max=bounds.c_max, physical_actions=True, **env_kwargs)
        controller = make_controller(spec, env)
    except ValueError as err:  # bad controller, bounds or road
        raise ControllerError(str(err)) from None
    controller.reset()
    metadata = {"vehicle": env_kwargs["vehicle"].name, "test": "track", "speed": f"{env_kwargs['speed']:g} m/s",
                "road": getattr(env_kwargs["road"], "provenance", env_kwargs["road"]), "controller": spec}
    return run_policy(env, controller, metadata)


def sweep_episode(spec: str, bounds: ActuatorBounds, vehicle, road, speed: float, duration: float | None,
                  rate: float) -> tuple[dict[str, float], Record]:
    """A sweep point under a controller: its metrics and record (rig/sweep/evaluate.py's ``controller``)."""
    env_kwargs = {"vehicle": vehicle, "road": road, "speed": speed, "duration": duration, "rate": rate}
    run = controlled_episode(spec, bounds, env_kwargs)
    return run.metrics, run.record


@dataclass(frozen=True)
class FrontComparison:
    """Controllers against the passive front: the front, each controller's metrics and its gain below the
    front at its own tyre load (None: no passive setting holds the road as well), and the controllers left
    out with the reason (the LQR is designed for quarter cars only)."""

    front: list[FrontPoint]
    metrics: dict[str, dict[str, float]]
    below_front: dict[str, float | None]
    left_out: dict[str, str]


def compare_with_front(spec: str, run: PolicyRun, bounds: ActuatorBounds, env_kwargs: dict) -> FrontComparison:
    """Run the passive front and every other controller with its defaults, and place them all with ``spec``'s
    own ``run`` against the front."""
    front = passive_front(**env_kwargs)
    metrics, left_out = {}, {}
    for name in CONTROLLERS:
        if name == "passive":
            continue
        try:
            metrics[name] = controlled_episode(name, bounds, env_kwargs).metrics
        except ControllerError as err:
            left_out[name] = str(err)
    metrics[spec] = run.metrics
    return FrontComparison(front, metrics, {n: below_front(front, m) for n, m in metrics.items()}, left_out)
