"""The suspension's travel where no record measures it: what the neuro form (controllers/neuro_inverse.py) learns its
spring on and feeds it, from the accelerations, the post's own displacement and the load balance.

Integrated twice, the wheel's acceleration less the body's gives the travel above a few tenths of a hertz, but its
white noise grows as f^-2 below (0.4-0.5 mm RMS in 0.5-1 Hz at 1 % noise on the independent large-event car, against
0.9 mm of travel there), and nothing below the integral's lower edge ``low`` is seen at all: there the car settles
where the asymmetric damper's mean force and the spring's balance (an asymmetric damper pumps the car down or up by
millimetres, and a cubic spring's force depends on where it sits). Two estimates bring back what the integral
misses:

- **the post** (training only: a rig record measures its posts' displacement x_r, ``actuator_disp``): the tyre's
  equilibrium puts the wheel at x_t = x_r - T / (k_t + c_t s), T the tyre's dynamic load m_t a_t + F_s (F_s the
  suspension's force on the wheel, from the law learned so far), and the travel is x_t less the body's displacement
  (its acceleration integrated twice: the body's noise is a fifth of the wheel's). This carries the travel below
  ``CROSSOVER``; above it the integrated accelerations do (complementary weights 1 / (1 + (f / f_c)^4) and their
  complement: the law's error over k_t grows with the damper's force, the integral's noise falls as f^-2). A target
  measured on the road has no post, so a target's travel takes the next estimate alone.
- **the load balance**, below ``low``: the body does not accelerate on average, so the slow part of each corner's
  suspension force (the learned law at the travel and its rate) equals the slow part of the corner's sprung mass
  times its acceleration. The slow travel that makes it so is found by Newton steps on the law (the law's mean
  slope; a law through zero at the car's rest, as the travel is measured from it).

The law comes from the travel and the travel from the law: the neuro form is fitted, the travel estimated with it,
the form fitted again (``ROUNDS``). Measured on the independent large-event car at 1 % noise (the training run's
travel against the simulator's, RMS): 1.4-1.8 mm integrated twice, 0.35-0.45 mm so (0.11-0.14 mm against 0.40-0.43
mm in 0.5-1 Hz); its mean, the dampers pumping the car 4.7-5.6 mm down, within 0.2 mm. On the target, which has no
post, only the slow travel is gained: its noise in 0.5-1 Hz stays the integral's. Written here: a few lines of
NumPy FFT on records padded with rest.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import integrate
from rig.vehicle.ride_model import corner_sprung_mass
from rig.vehicle.vehicle_file import Vehicle

CROSSOVER = 2.0       # Hz: below, the post's estimate of the travel; above, the integrated accelerations'
ROUNDS = 3            # fits of the law on the travel estimated with the previous one
NEWTON_STEPS = 10     # on the load balance, at most
NEWTON_TOLERANCE = 1e-7  # m: a step that moves the slow travel less ends them
SLOPE_STEP = 1e-4     # m: the law's slope by this difference

#: the suspension's force on the body (samples x corners, N, zero at rest) at travel x and rate v (samples x corners)
Law = Callable[[np.ndarray, np.ndarray], np.ndarray]


def integrated_travel(record: Record, corners: tuple[str, ...], low: float) -> tuple[np.ndarray, np.ndarray]:
    """The travel (m) and its rate (m/s), the wheel's acceleration less the body's integrated from ``low`` Hz."""
    relative = record.quantity("unsprung_acc", corners) - record.quantity("sprung_acc", corners)
    return integrate(relative, record.rate, low, 2, pad=True), integrate(relative, record.rate, low, 1, pad=True)


def has_post(record: Record, corners: tuple[str, ...]) -> bool:
    """Whether the record measures every corner's post displacement."""
    return all(channel(c, "actuator_disp") in record for c in corners)


def estimated_travel(vehicle: Vehicle, record: Record, low: float, law: Law, post: bool) -> np.ndarray:
    """The travel (samples x corners, m) with the law ``law``: the integrated accelerations, below CROSSOVER the
    post's estimate where ``post`` (module docstring), and the load balance's slow travel below ``low``."""
    corners = vehicle.corners
    x, v = integrated_travel(record, corners, low)
    if post:
        x = _blend(post_travel(vehicle, record, low, law(x, v)), x, record.rate, CROSSOVER, low)
    return x + slow_travel(vehicle, record, low, law, x, v)


def post_travel(vehicle: Vehicle, record: Record, low: float, force: np.ndarray) -> np.ndarray:
    """The travel (m) from the post's displacement, the tyre's equilibrium under the wheel's dynamic load (m_t a_t
    and the suspension's ``force`` on the body, samples x corners, N) and the body's displacement, from ``low`` Hz."""
    corners, rate = vehicle.corners, record.rate
    axles = [vehicle.axle(c) for c in corners]
    k_t, c_t, m_t = (np.array([getattr(a, key) for a in axles]) for key in ("tyre_rate", "tyre_damping",
                                                                           "unsprung_mass"))
    load = m_t * record.quantity("unsprung_acc", corners) + force
    n, pad = record.n_samples, int(round(rate / low))
    s = 2j * np.pi * np.fft.rfftfreq(n + 2 * pad, 1.0 / rate)[:, None]
    deflection = np.fft.irfft(np.fft.rfft(np.pad(load, ((pad, pad), (0, 0))), axis=0) / (k_t + c_t * s),
                              n + 2 * pad, axis=0)[pad:pad + n]
    body = integrate(record.quantity("sprung_acc", corners), rate, low, 2, pad=True)
    return record.quantity("actuator_disp", corners) - body - deflection


def slow_travel(vehicle: Vehicle, record: Record, low: float, law: Law, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The travel below ``low`` Hz (samples x corners, m) that balances the slow part of the law's force at x plus
    it against the slow part of each corner's sprung mass times its acceleration (module docstring)."""
    rate = record.rate
    mass = np.array([corner_sprung_mass(vehicle, c) for c in vehicle.corners])
    inertia = _below(mass * record.quantity("sprung_acc", vehicle.corners), rate, low)
    slow = np.zeros_like(x)
    for _ in range(NEWTON_STEPS):
        force = law(x + slow, v)
        slope = np.mean(law(x + slow + SLOPE_STEP, v) - force, axis=0) / SLOPE_STEP
        step = (_below(force, rate, low) - inertia) / np.where(slope > 0, slope, np.inf)
        slow = slow - step
        if np.max(np.abs(step)) < NEWTON_TOLERANCE:
            break
    return slow


def _spectra(values: np.ndarray, rate: float, low: float) -> tuple[np.ndarray, np.ndarray, int]:
    """The spectrum of ``values`` padded with rest for 1 / low s at each end, its frequencies (Hz) and the pad."""
    pad = int(round(rate / low))
    spectrum = np.fft.rfft(np.pad(values, ((pad, pad), (0, 0))), axis=0)
    return spectrum, np.fft.rfftfreq(values.shape[0] + 2 * pad, 1.0 / rate), pad


def _below(values: np.ndarray, rate: float, low: float) -> np.ndarray:
    """What of ``values`` (samples x channels) lies below ``low`` Hz."""
    spectrum, frequency, pad = _spectra(values, rate, low)
    spectrum[frequency >= low] = 0.0
    return np.fft.irfft(spectrum, values.shape[0] + 2 * pad, axis=0)[pad:pad + values.shape[0]]


def _blend(slow: np.ndarray, fast: np.ndarray, rate: float, crossover: float, low: float) -> np.ndarray:
    """``slow`` below ``crossover`` Hz and ``fast`` above (complementary weights), nothing below ``low`` Hz."""
    a, frequency, pad = _spectra(slow, rate, low)
    b = _spectra(fast, rate, low)[0]
    weight = (1.0 / (1.0 + (frequency / crossover) ** 4))[:, None]
    spectrum = np.where(frequency[:, None] >= low, weight * a + (1.0 - weight) * b, 0.0)
    return np.fft.irfft(spectrum, slow.shape[0] + 2 * pad, axis=0)[pad:pad + slow.shape[0]]
