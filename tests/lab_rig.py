"""A lab quarter-car bench simulated for the tests from its equations: SciPy's ODE solver, neither MuJoCo nor the
project's model builder.

The bench (assets/vehicles/lab_quarter.toml): a body plate (m_s) and a wheel plate (m_u) on linear bearings along
vertical guides, the suspension spring k_s and damping c_s between them, the tyre spring k_t (with c_t) between the
wheel and the base plate, which an actuator moves by the road z_r(t), and a force actuator between body and wheel
that applies k_f F(t), F being what its record says (k_f = 1 when its force constant is right; the force constant
error hides k_f != 1). The body's linear bearing rubs on its guide: F_b tanh(z_s' / v_0) against its motion. The
tyre only pushes. With z from static equilibrium, up positive, and W = (m_s + m_u) g the static tyre load:

    m_s z_s'' = k_s (z_u - z_s) + c_s (z_u' - z_s') + k_f F - F_b tanh(z_s' / v_0)
    m_u z_u'' = -k_s (z_u - z_s) - c_s (z_u' - z_s') - k_f F + T - W
    T = max(0, W + k_t (z_r - z_u) + c_t (z_r' - z_u'))

The road is a logarithmic swept sine (0.5 to 12 Hz); the recorded force is a swept sine on the same sweep, shifted in
phase (correlated with the road, as a controller's force is), plus a random force (40 sines of random phase in
0.5-15 Hz). Encoders quantise the base, wheel and body plates to 0.02 mm (``FL/actuator_disp``, ``FL/unsprung_disp``,
``FL/sprung_disp``); the force (``FL/active_force``) carries 1 % white noise. scipy.integrate.solve_ivp (LSODA)
integrates it. The truth bench's linear parameters are off the vehicle file's by up to 3 %, as the project's
synthetic tests make them.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.integrate import solve_ivp

from rig.io.record import Record
from rig.vehicle.vehicle_file import Vehicle

G = 9.80665
ENCODER_STEP = 0.02e-3  # m per count
FORCE_NOISE = 0.01      # of the force's RMS
LINEAR_ERROR = 0.03     # relative, uniform


@dataclass(frozen=True)
class Bench:
    """The bench's parameters (SI) and what is hidden in it."""

    body: float
    wheel: float
    spring: float
    damping: float
    tyre: float
    tyre_damping: float
    force_constant: float = 1.0      # true force over recorded force
    bearing_friction: float = 0.0    # N, the body bearing's friction force
    friction_velocity: float = 1e-3  # m/s, v_0 of its tanh

    @classmethod
    def of(cls, vehicle: Vehicle, rng: np.random.Generator | None = None, **hidden: float) -> Bench:
        """The vehicle file's bench; with ``rng``, its linear parameters off by up to 3 %; ``hidden`` effects."""
        def off(value: float) -> float:
            return value if rng is None else value * rng.uniform(1 - LINEAR_ERROR, 1 + LINEAR_ERROR)

        axle = vehicle.front
        return cls(off(vehicle.sprung_mass), off(axle.unsprung_mass), off(axle.suspension_rate), off(axle.damping),
                   off(axle.tyre_rate), axle.tyre_damping, **hidden)


@dataclass(frozen=True)
class Excitation:
    """The road (m) and the recorded force (N) as functions of time (s), with the road's rate; scalars in the
    solver, arrays for the record."""

    duration: float
    road_amplitude: float = 1.5e-3   # m
    force_amplitude: float = 1.0     # N, of the swept part
    force_phase: float = 0.8         # rad, of the swept force against the road
    random_force: float = 0.4        # N RMS: 40 sines of random phase at random frequencies in 0.5-15 Hz
    low_hz: float = 0.5
    high_hz: float = 12.0
    seed: int = 0

    @property
    def _sweep(self) -> float:
        return math.log(self.high_hz / self.low_hz) / self.duration

    @cached_property
    def _random(self) -> tuple[np.ndarray, np.ndarray, float]:
        rng = np.random.default_rng(self.seed)
        omega = 2 * np.pi * rng.uniform(self.low_hz, 15.0, 40)
        return omega, rng.uniform(0, 2 * np.pi, 40), self.random_force / 20**0.5

    def ramp(self, t):
        """0 to 1 over the first second (the bench starts at rest)."""
        u = np.clip(t, 0.0, 1.0)
        return u * u * (3 - 2 * u)

    def road(self, t):
        """z_r and z_r' at ``t`` (the ramp's own rate neglected: it is slow against the sweep)."""
        phase = 2 * np.pi * self.low_hz * np.expm1(self._sweep * t) / self._sweep
        omega = 2 * np.pi * self.low_hz * np.exp(self._sweep * t)
        amplitude = self.road_amplitude * self.ramp(t)
        return amplitude * np.sin(phase), amplitude * omega * np.cos(phase)

    def force(self, t):
        """The recorded force F (N) at ``t``."""
        phase = 2 * np.pi * self.low_hz * np.expm1(self._sweep * t) / self._sweep
        omega, shift, amplitude = self._random
        random = amplitude * np.sin(np.multiply.outer(t, omega) + shift).sum(axis=-1)
        return self.ramp(t) * (self.force_amplitude * np.sin(phase + self.force_phase) + random)


def simulate(bench: Bench, excitation: Excitation, rate: float) -> dict[str, np.ndarray]:
    """The bench's true motion at the record's sample times: road, wheel and body (m from static), and the recorded
    force (N)."""
    b, e = bench, excitation
    weight = (b.body + b.wheel) * G

    def derivatives(t, y):
        z_s, v_s, z_u, v_u = y
        z_r, v_r = e.road(t)
        suspension = b.spring * (z_u - z_s) + b.damping * (v_u - v_s)
        tyre = max(0.0, weight + b.tyre * (z_r - z_u) + b.tyre_damping * (v_r - v_u))
        friction = b.bearing_friction * math.tanh(v_s / b.friction_velocity)
        push = b.force_constant * e.force(t)
        return [v_s, (suspension + push - friction) / b.body, v_u, (tyre - weight - suspension - push) / b.wheel]

    time = np.arange(int(round(e.duration * rate))) / rate
    solution = solve_ivp(derivatives, (0.0, time[-1]), [0.0, 0.0, 0.0, 0.0], method="LSODA", t_eval=time,
                         rtol=1e-7, atol=1e-10)
    if not solution.success:
        raise RuntimeError(f"the bench's ODE failed: {solution.message}")
    return {"road": e.road(time)[0], "wheel": solution.y[2], "body": solution.y[0], "force": e.force(time)}


def record_of(motion: dict[str, np.ndarray], rate: float, rng: np.random.Generator) -> Record:
    """What the bench's DAQ records: encoder counts (0.02 mm) of the three plates in m, the force with noise."""
    def encoder(z):
        return np.round(z / ENCODER_STEP) * ENCODER_STEP

    force = motion["force"] + FORCE_NOISE * np.std(motion["force"]) * rng.standard_normal(motion["force"].size)
    return Record(rate, {"FL/actuator_disp": encoder(motion["road"]), "FL/unsprung_disp": encoder(motion["wheel"]),
                         "FL/sprung_disp": encoder(motion["body"]), "FL/active_force": force},
                  metadata={"vehicle": "lab_quarter", "test": "rig", "source": "lab bench simulated for the tests"})


def lab_records(vehicle: Vehicle, seed: int, duration: float = 40.0, holdout: float = 20.0, rate: float = 500.0,
                **hidden: float) -> tuple[Record, Record, Bench]:
    """A measured and a held-out record of the bench of ``vehicle`` with its linear parameters off by up to 3 % and
    the ``hidden`` effects (Bench's fields), and the truth bench."""
    rng = np.random.default_rng(seed)
    bench = Bench.of(vehicle, rng, **hidden)
    records = [record_of(simulate(bench, Excitation(length, seed=seed + i), rate), rate, rng)
               for i, length in enumerate((duration, holdout))]
    return records[0], records[1], bench


def with_bench(vehicle: Vehicle, bench: Bench) -> Vehicle:
    """``vehicle`` with the bench's linear parameters (nothing hidden): the exact linear model of the bench."""
    axle = dataclasses.replace(vehicle.front, unsprung_mass=bench.wheel, spring_rate=bench.spring, parasitic_rate=0.0,
                               damping=bench.damping, tyre_rate=bench.tyre, tyre_damping=bench.tyre_damping)
    return dataclasses.replace(vehicle, sprung_mass=bench.body, front=axle)
