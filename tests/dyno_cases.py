"""Damper dynamometer tests generated from known force laws, written for the tests (not the code under test).

A test programme as a lab runs it: sine tests at six peak speeds and triangle (constant-speed) tests at three, all
at a 25 mm amplitude, three cycles each, one record per test, sampled at 1 kHz; the triangle's reversals are
rounded over 15 % of a half period (raised-cosine velocity), as a servo-hydraulic dyno rounds them. The damper's
temperature rises linearly by 20 degC over the programme. Each law is written out here in closed form; a damper in
series with a stiffness is integrated by SciPy's LSODA (F' = k (x' - g(F)), g the law's inverse by interpolation
on a fine table), from the quasi-static force. Noise: 1 % of each channel's RMS on displacement and force (white,
Gaussian), 0.05 degC on temperature.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from rig.io.record import Record

RATE = 1000.0                    # Hz
AMPLITUDE = 0.025                # m
SINE_SPEEDS = (0.05, 0.1, 0.2, 0.4, 0.7, 1.0)  # m/s, peak
TRIANGLE_SPEEDS = (0.1, 0.3, 0.6)               # m/s, plateau
CYCLES = 3
ROUNDING = 0.15                  # share of a triangle's half period spent reversing
FINE = 10                        # the generator's own grid: this many points per record sample
T_START, T_RISE, T_REF = 25.0, 20.0, 35.0       # degC
UNITS = {"damper/displacement": "m", "damper/force": "N", "damper/temperature": "degC"}

#: known laws, damper level (N s/m, N s^2/m^2, m/s, N, N/m, 1/degC): one per form, and one of everything
LAWS = {
    "linear": {"c": 2500.0},
    "asymmetric": {"c_rebound": 3500.0, "c_compression": 1500.0},
    "quadratic": {"c0": 1500.0, "cn": 1500.0},
    "quadratic_asymmetric": {"c0_rebound": 2000.0, "cn_rebound": 2000.0, "c0_compression": 800.0,
                             "cn_compression": 900.0},
    "digressive": {"c_low_rebound": 6000.0, "c_high_rebound": 1500.0, "knee_rebound": 0.25,
                   "c_low_compression": 3000.0, "c_high_compression": 800.0, "knee_compression": 0.2},
    "linear+preload": {"c": 2500.0, "preload": 150.0},
    "asymmetric+series": {"c_rebound": 3500.0, "c_compression": 1500.0, "series_rate": 4e5},
    "quadratic+temperature": {"c0": 1500.0, "cn": 1500.0, "temperature_drift": -0.004},
    "digressive+preload+series+temperature": {
        "c_low_rebound": 6000.0, "c_high_rebound": 1500.0, "knee_rebound": 0.25, "c_low_compression": 3000.0,
        "c_high_compression": 800.0, "knee_compression": 0.2, "preload": 150.0, "series_rate": 6e5,
        "temperature_drift": -0.004},
}
#: a damper whose force lags its law by 25 ms (oil and gas compressibility) with the seals' friction (hysteresis)
LAGGING = {"c_low_rebound": 6000.0, "c_high_rebound": 1500.0, "knee_rebound": 0.25, "c_low_compression": 3000.0,
           "c_high_compression": 800.0, "knee_compression": 0.2, "preload": 150.0, "lag_time": 0.025,
           "friction": 120.0, "friction_reach": 0.001}


def law_force(p: dict, v: np.ndarray) -> np.ndarray:
    """The base law's force (N, positive resisting extension) at extension rate v (m/s), in closed form."""
    v = np.asarray(v, dtype=float)
    if "c" in p:
        return p["c"] * v
    if "c_rebound" in p:
        return np.where(v > 0, p["c_rebound"], p["c_compression"]) * v
    if "c0" in p:
        return p["c0"] * v + p["cn"] * v * np.abs(v)
    if "c0_rebound" in p:
        return np.where(v > 0, p["c0_rebound"] * v + p["cn_rebound"] * v ** 2,
                        p["c0_compression"] * v - p["cn_compression"] * v ** 2)
    kr, kc = p["knee_rebound"], p["knee_compression"]
    rebound = np.where(v < kr, p["c_low_rebound"] * v, p["c_low_rebound"] * kr + p["c_high_rebound"] * (v - kr))
    compression = np.where(v > -kc, p["c_low_compression"] * v,
                           -p["c_low_compression"] * kc + p["c_high_compression"] * (v + kc))
    return np.where(v > 0, rebound, compression)


def motions(rate: float = RATE) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
    """(name, time, displacement, velocity) of each test on the generator's fine grid (``FINE`` x ``rate``)."""
    fine = FINE * rate
    out = []
    for speed in SINE_SPEEDS:
        frequency = speed / (2 * np.pi * AMPLITUDE)
        t = np.arange(round(CYCLES / frequency * rate) * FINE) / fine
        out.append((f"sine_{speed:g}", t, AMPLITUDE * np.sin(2 * np.pi * frequency * t),
                    speed * np.cos(2 * np.pi * frequency * t)))
    for speed in TRIANGLE_SPEEDS:
        half = 2 * AMPLITUDE / speed
        t = np.arange(round(2 * CYCLES * half * rate) * FINE) / fine
        phase = (t / half) % 1.0  # position within the current half period, which runs one way
        way = np.where((t // half) % 2 == 0, 1.0, -1.0)
        edge = np.minimum(phase, 1.0 - phase) / (ROUNDING / 2)  # 0 at a reversal, 1 where the plateau starts
        v = speed * way * np.sin(0.5 * np.pi * np.clip(edge, 0.0, 1.0))
        x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1])) / fine])
        out.append((f"triangle_{speed:g}", t, x - 0.5 * (x.max() + x.min()), v))
    return out


def true_force(p: dict, t: np.ndarray, x: np.ndarray, v: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The law's force along a motion: algebraic, or through a series stiffness by integrating F' = k (x' - g(F)),
    or lagged and with a friction's hysteresis (``lagged_force``)."""
    preload = p.get("preload", 0.0)
    if "lag_time" in p:
        return lagged_force(p, t, v, scale) - preload
    if "series_rate" not in p:
        return scale * law_force(p, v) - preload
    k = p["series_rate"]
    grid = np.linspace(-20.0, 20.0, 400001)  # m/s: the law tabulated, to invert it by interpolation
    table = law_force(p, grid)

    def rhs(s, state):
        factor = np.interp(s, t, scale)
        damper_speed = np.interp((state[0] + preload) / factor, table, grid)
        return [k * (np.interp(s, t, v) - damper_speed)]

    start = scale[0] * law_force(p, v[0]) - preload
    solution = solve_ivp(rhs, (t[0], t[-1]), [start], method="LSODA", t_eval=t, rtol=1e-9, atol=1e-6,
                         max_step=2e-3)
    return solution.y[0]


def lagged_force(p: dict, t: np.ndarray, v: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """The law's force through a first-order lag, tau F_l' = f(v) - F_l, plus Dahl's friction in time,
    F_f' = (F_c / x_f) v (1 - F_f sgn(v) / F_c), integrated together by SciPy's LSODA from the quasi-static force and
    no friction (the closed forms the fit uses, rig/diagnosis/dyno/damper_dynamics.py, are not used here)."""
    tau, friction, reach = p["lag_time"], p["friction"], p["friction_reach"]

    def rhs(s, state):
        speed = np.interp(s, t, v)
        target = np.interp(s, t, scale) * law_force(p, speed)
        return [(target - state[0]) / tau, friction / reach * speed * (1.0 - state[1] * np.sign(speed) / friction)]

    start = [scale[0] * law_force(p, v[0]), 0.0]
    solution = solve_ivp(rhs, (t[0], t[-1]), start, method="LSODA", t_eval=t, rtol=1e-8, atol=1e-6, max_step=1e-3)
    return solution.y[0] + solution.y[1]


def dyno_records(p: dict, seed: int = 0, noise: float = 0.01, rate: float = RATE,
                 displacement_noise: float | None = None) -> list[tuple[str, Record]]:
    """The programme's records for law ``p``: (name, Record) with displacement, force and temperature; ``noise`` of
    each channel's RMS (the displacement's ``displacement_noise`` where given)."""
    rng = np.random.default_rng(seed)
    tests = motions(rate)
    total = sum(t[-1] for _, t, _, _ in tests)
    elapsed, out = 0.0, []
    for name, t, x, v in tests:
        temperature = T_START + T_RISE * (elapsed + t) / total
        elapsed += t[-1]
        scale = 1.0 + p.get("temperature_drift", 0.0) * (temperature - T_REF)
        force = true_force(p, t, x, v, scale)
        pick = slice(None, None, FINE)
        x, force, temperature = x[pick], force[pick], temperature[pick]
        stroke_noise = noise if displacement_noise is None else displacement_noise
        channels = {"damper/displacement": x + stroke_noise * np.std(x) * rng.standard_normal(x.size),
                    "damper/force": force + noise * np.std(force) * rng.standard_normal(x.size),
                    "damper/temperature": temperature + 0.05 * rng.standard_normal(x.size)}
        out.append((name, Record(rate, channels, dict(UNITS), {"test": "dyno", "motion": name})))
    return out
