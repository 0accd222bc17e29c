"""Online drive control for DriveTracking: the road behind the target, previewed, with feedback on the post.

The target is what the car felt on the road. Per corner, the tyre carries body and wheel, so the road under
it is the wheel's height plus the tyre's dynamic deflection:

    r = z_wheel + (m_body a_body + m_wheel a_wheel) / k_tyre,

with z_wheel the double integral of the target wheel acceleration (leaky below ``corner_hz``, which costs
little in acceleration) and m_body the sprung mass. The controller integrates the target as its preview
window reveals it, and drives

    drive(t) = S^-1 r(t + lead) + integral_gain * integral of (r - post) dt,

``lead`` (s, interpolated between samples; default: the servo's transport delay, the model's input delay and
the hold), S^-1 the inverse of the servo's command lag and position loop (from the rig's
configuration, as derivatives of the previewed road), and an integral feedback on the measured post
displacement for the slow error a model that is off would leave. Actions in m (``physical_actions=True``).

Quarter cars only: a full car's corner forces do not follow from its body's accelerations (its warp is
free); the static share of the sprung mass per corner left 40 % errors.
"""

from __future__ import annotations

import numpy as np

from rig.io.units import STANDARD_GRAVITY
from rig.vehicle.mjcf import INPUT_DELAY_STEPS
from rig.vehicle.rig_config import RigConfig


class PreviewDrive:
    """Feedback + preview drive law for ``FourPoster/DriveTracking-v0``."""

    def __init__(self, env, lead: float | None = None, integral_gain: float = 1.0, corner_hz: float = 0.01):
        plant = env.unwrapped.plant
        if len(plant.corners) != 1:
            raise ValueError("PreviewDrive estimates the road from a quarter car's accelerations; a full car's "
                             "corner forces do not follow from its body accelerations (warp)")
        self.corners, self.rate, self.preview = len(plant.corners), plant.rate, plant.preview
        vehicle = plant.sim.rig.vehicle
        lead = servo_lead(vehicle.rig, plant.sim.rig.timestep, plant.rate) if lead is None else lead
        self.rate_terms = servo_inverse(vehicle.rig)
        self.lead = lead * plant.rate  # samples, fractional
        if not 0 <= self.lead < self.preview - 1:
            raise ValueError(f"lead must be within the target preview (0-{(self.preview - 2) / self.rate:g} s), "
                             f"got {lead}")
        self.integral_gain = integral_gain
        axles = [vehicle.axle(c) for c in plant.corners]
        self.wheel_mass = np.array([a.unsprung_mass for a in axles])
        self.body_mass = plant.sim.static.tyre_force / STANDARD_GRAVITY - self.wheel_mass
        self.tyre_rate = np.array([a.tyre_rate for a in axles])
        self.leak = float(np.exp(-2 * np.pi * corner_hz / plant.rate))
        self.reset()

    def reset(self) -> None:
        n = self.corners
        self.k = 0
        self.road: list[np.ndarray] = [np.zeros(n)]  # road estimate at samples 0, 1, ... as far as seen
        self.last_acc = np.zeros(n)
        self.velocity, self.height = np.zeros(n), np.zeros(n)
        self.integral = np.zeros(n)

    def _extend(self, body_acc: np.ndarray, wheel_acc: np.ndarray) -> None:
        """Integrate one more target sample into the road estimate."""
        dt = 1.0 / self.rate
        velocity = self.leak * self.velocity + dt * (wheel_acc + self.last_acc) / 2
        self.height = self.leak * self.height + dt * (velocity + self.velocity) / 2
        self.velocity, self.last_acc = velocity, wheel_acc
        self.road.append(self.height + (self.body_mass * body_acc + self.wheel_mass * wheel_acc) / self.tyre_rate)

    def _road_at(self, sample: float) -> np.ndarray:
        """Road estimate at a fractional sample (linear between samples; at rest before the start)."""
        sample = max(sample, 0.0)
        whole, share = int(sample), sample % 1.0
        return (1 - share) * self.road[whole] + share * self.road[min(whole + 1, len(self.road) - 1)]

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        n, p = self.corners, self.preview
        post = obs[2 * n:3 * n]
        window = obs[3 * n:].reshape(2 * n, p)  # channels (body then wheel, per corner) x preview samples
        for i in range(len(self.road) - self.k - 1, p):  # samples k + 1 + i not integrated yet
            self._extend(window[:n, i], window[n:, i])
        at = self.k + self.lead
        before, here, after = (self._road_at(at + d) for d in (-1.0, 0.0, 1.0))
        first, second = self.rate_terms
        ahead = (here + first * (after - before) * self.rate / 2
                 + second * (after - 2 * here + before) * self.rate**2)
        self.integral += self.integral_gain * (self.road[self.k] - post) / self.rate
        self.k += 1
        return ahead + self.integral


def servo_lead(rig: RigConfig, timestep: float, rate: float) -> float:
    """The servo's pure delay from drive to post (s): transport delay, the model's input delay
    (rig/vehicle/mjcf.py) and the hold: half a control period, less half a physics step (the actuator's
    history samples the held drive at the start of every step and interpolates between those samples)."""
    return rig.servo_delay + INPUT_DELAY_STEPS * timestep + 0.5 / rate - 0.5 * timestep


def servo_inverse(rig: RigConfig) -> tuple[float, float]:
    """Coefficients (s, s^2) of the first and second derivative that invert the servo's command lag
    (1 + tau s) and position loop (1 + 2 zeta s / omega + s^2 / omega^2), up to the third-order term."""
    tau, zeta, omega = rig.lag_time_constant, rig.loop_damping, 2 * np.pi * rig.loop_frequency
    return tau + 2 * zeta / omega, 2 * zeta * tau / omega + 1 / omega**2
