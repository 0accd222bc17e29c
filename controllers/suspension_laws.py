"""Suspension controllers for the ActiveSuspension and SemiActiveSuspension environments.

Each controller is a small object with one update law: ``controller(obs) -> action`` in the env's
physical units (``physical_actions=True``: N for a force, N s/m for a damping coefficient), and
``reset()``. They read what the car's sensors give (rig/envs/car_on_road.py: body and wheel acceleration,
travel and travel velocity per corner, compression positive); the body's absolute velocity comes from a
leaky integration of its acceleration (``BodyVelocity``), the wheel's from it and the travel velocity.

Sign conventions: travel velocity tv = v_wheel - v_body; a damper c pushes the body with c tv and the wheel
with -c tv; an active force F > 0 pushes them apart (body up, wheel down).

- ``passive``: the damper scaled (``scale``), a constant coefficient (semi-active env);
- ``skyhook``: semi-active clipped skyhook, c = c_sky (-v_body) / tv within [c_min, c_max];
- ``skyhook_onoff``: c_max when v_body (v_body - v_wheel) > 0, else c_min;
- ``skyhook_active``: the ideal skyhook, F = -c_sky v_body - (c_nominal - c_rel) tv: the sky damper in place of
  the passive one, ``c_rel`` of relative damping kept (active env);
- ``groundhook``: semi-active, c = c_ground v_wheel / tv within the bounds;
- ``hybrid``: alpha x skyhook's coefficient + (1 - alpha) x groundhook's, within the bounds;
- ``lqr``: state feedback from the linearised quarter car (controllers/lqr.py), its gain optimal for the
  force held over each control period, active env.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from controllers.lqr import LqrDesign, lqr_design


@dataclass(frozen=True)
class Context:
    """What a controller knows about its environment: set from ``env.unwrapped.plant``."""

    control: str                 # "force" (active) or "damping" (semi-active)
    rate: float                  # Hz, control rate
    corners: int
    nominal_damping: np.ndarray  # N s/m per corner
    low: float                   # action bounds in N or N s/m
    high: float

    @classmethod
    def of(cls, env) -> Context:
        plant = env.unwrapped.plant
        return cls(plant.control, plant.rate, len(plant.corners), plant.nominal_damping(), plant.low, plant.high)

    def split(self, obs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Body and wheel acceleration (m/s^2), travel (m) and travel velocity (m/s) per corner."""
        n = self.corners
        return obs[:n], obs[n:2 * n], obs[2 * n:3 * n], obs[3 * n:4 * n]


class BodyVelocity:
    """Body velocity (m/s) from its acceleration: trapezoidal integration, leaking below ``corner_hz``."""

    def __init__(self, rate: float, corners: int, corner_hz: float = 0.05):
        self.dt, self.leak = 1.0 / rate, float(np.exp(-2 * np.pi * corner_hz / rate))
        self.corners = corners
        self.reset()

    def reset(self) -> None:
        self.velocity = np.zeros(self.corners)
        self.last = np.zeros(self.corners)

    def __call__(self, acceleration: np.ndarray) -> np.ndarray:
        self.velocity = self.leak * self.velocity + self.dt * (acceleration + self.last) / 2
        self.last = acceleration.copy()
        return self.velocity


class Controller:
    """Base: a law of the observation, with a body-velocity estimate; ``needs`` the env's control kind."""

    needs: str = "damping"

    def __init__(self, context: Context):
        self.require(context)
        self.context = context
        self.body_velocity = BodyVelocity(context.rate, context.corners)

    @classmethod
    def require(cls, context: Context) -> None:
        """Refuse an environment of the wrong control kind."""
        if context.control != cls.needs:
            env = "SemiActiveSuspension" if cls.needs == "damping" else "ActiveSuspension"
            raise ValueError(f"{cls.__name__} needs the {env} environment (control '{cls.needs}')")

    def reset(self) -> None:
        self.body_velocity.reset()

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        body_acc, _, travel, travel_velocity = self.context.split(obs)
        v_body = self.body_velocity(body_acc)
        return self.law(v_body, v_body + travel_velocity, travel, travel_velocity, obs)

    def law(self, v_body, v_wheel, travel, travel_velocity, obs) -> np.ndarray:
        raise NotImplementedError

    def clip(self, coefficient: np.ndarray) -> np.ndarray:
        return np.clip(coefficient, self.context.low, self.context.high)


def _ratio(numerator: np.ndarray, denominator: np.ndarray) -> np.ndarray:
    """numerator / denominator, 0 where the denominator is 0 (no relative motion: any c gives no force)."""
    return np.divide(numerator, denominator, out=np.zeros_like(numerator), where=denominator != 0)


class Passive(Controller):
    def __init__(self, context: Context, scale: float = 1.0):
        super().__init__(context)
        damping = scale * context.nominal_damping
        if not np.all((damping >= context.low) & (damping <= context.high)):
            raise ValueError(f"passive:scale={scale:g} asks for {', '.join(f'{c:.0f}' for c in damping)} N s/m, "
                             f"outside the damper's range [{context.low:g}, {context.high:g}] N s/m (c_min, c_max)")
        self.scale = scale

    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        return self.scale * self.context.nominal_damping


class Skyhook(Controller):
    def __init__(self, context: Context, c_sky: float = 6000.0):
        super().__init__(context)
        self.c_sky = c_sky

    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        return self.clip(_ratio(-self.c_sky * v_body, travel_velocity))


class SkyhookOnOff(Controller):
    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        on = v_body * (v_body - v_wheel) > 0
        return np.where(on, self.context.high, self.context.low)


class SkyhookActive(Controller):
    """The ideal skyhook: the actuator cancels the passive damper down to ``c_rel`` (N s/m, relative damping
    kept for the wheel) and adds the sky damper on the body."""

    needs = "force"

    def __init__(self, context: Context, c_sky: float = 6000.0, c_rel: float = 1000.0):
        super().__init__(context)
        self.c_sky, self.c_rel = c_sky, c_rel

    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        return self.clip(-self.c_sky * v_body + (self.c_rel - self.context.nominal_damping) * travel_velocity)


class Groundhook(Controller):
    def __init__(self, context: Context, c_ground: float = 3000.0):
        super().__init__(context)
        self.c_ground = c_ground

    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        return self.clip(_ratio(self.c_ground * v_wheel, travel_velocity))


class Hybrid(Controller):
    def __init__(self, context: Context, c_sky: float = 6000.0, c_ground: float = 3000.0, alpha: float = 0.7):
        super().__init__(context)
        if not 0.0 <= alpha <= 1.0:
            raise ValueError(f"alpha must lie in [0, 1], got {alpha}")
        self.c_sky, self.c_ground, self.alpha = c_sky, c_ground, alpha

    def law(self, v_body, v_wheel, travel, travel_velocity, obs):
        sky = np.maximum(_ratio(-self.c_sky * v_body, travel_velocity), 0.0)
        ground = np.maximum(_ratio(self.c_ground * v_wheel, travel_velocity), 0.0)
        return self.clip(self.alpha * sky + (1 - self.alpha) * ground)


class Lqr(Controller):
    """u = -K x on the linearised quarter car; x = (body, wheel) heights over the road and their velocities.

    Heights over the road are not measured: they follow from the measured accelerations through the
    linear model itself, a = A_vp p + A_vv v + B u_previous (the action held up to the observation).
    """

    needs = "force"

    def __init__(self, context: Context, design: LqrDesign):
        super().__init__(context)
        self.design = design
        self.previous = np.zeros(1)

    def reset(self) -> None:
        super().reset()
        self.previous = np.zeros(1)

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        body_acc, wheel_acc, _, travel_velocity = self.context.split(obs)
        v_body = self.body_velocity(body_acc)
        velocity = np.concatenate([v_body, v_body + travel_velocity])
        d = self.design
        heights = np.linalg.solve(d.a[2:, :2], np.concatenate([body_acc, wheel_acc]) - d.a[2:, 2:] @ velocity
                                  - d.b[2:] @ self.previous)
        self.previous = self.clip(-d.gain @ np.concatenate([heights, velocity]))
        return self.previous


#: name -> controller class (the CLI's --controller NAME)
CONTROLLERS = {"passive": Passive, "skyhook": Skyhook, "skyhook_onoff": SkyhookOnOff, "skyhook_active": SkyhookActive,
               "groundhook": Groundhook, "hybrid": Hybrid, "lqr": Lqr}


def parse_controller(spec: str) -> tuple[str, dict[str, float]]:
    """``NAME[:k=v,...]`` -> (name, parameters); unknown names and malformed parameters are refused."""
    name, _, rest = spec.partition(":")
    if name not in CONTROLLERS:
        raise ValueError(f"unknown controller '{name}' (known: {', '.join(CONTROLLERS)})")
    params = {}
    for item in filter(None, rest.split(",")):
        key, sep, value = item.partition("=")
        try:
            params[key.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep:
            raise ValueError(f"controller '{spec}': '{item}' is not key=number")
    return name, params


def make_controller(spec: str, env) -> Controller:
    """The controller ``NAME[:k=v,...]`` for ``env`` (made with ``physical_actions=True``)."""
    name, params = parse_controller(spec)
    context = Context.of(env)
    CONTROLLERS[name].require(context)
    try:
        if name == "lqr":
            return Lqr(context, lqr_design(env.unwrapped.plant, sampled=True, **params))
        return CONTROLLERS[name](context, **params)
    except TypeError as err:
        raise ValueError(f"controller '{spec}': {err}") from None


def needs(spec: str) -> str:
    """The control kind ('damping' or 'force') the controller of ``spec`` needs."""
    return CONTROLLERS[parse_controller(spec)[0]].needs
