"""Drive estimation by the linear quarter-car inverse model of Nurhadiyanto's thesis (Eq 5.1).

Per corner, the wheel's equation of motion (Nurhadiyanto's Eq 3.1) solved for the post displacement x_r:

    x_r = (m_t x_t'' + c_s (x_t' - x_b') + (k_s + k_p) (x_t - x_b)) / k_t + x_t          (Eq 5.1)

from the measured wheel (x_t'') and body (x_b'') accelerations above the corner, with velocities and
displacements integrated in the frequency domain (rig/signal/filters.py ``integrate``; the thesis's
cumulative trapezoid drifted and needed a 5 Hz high-pass). A tyre damping c_t in the vehicle file divides
by (k_t + c_t s) instead of k_t; with c_t = 0 this is Eq 5.1 exactly.

The seed compares x_r with the drive; on a servo-hydraulic post the drive also passes through the servo,
so the post displacement is carried back through the rig's servo model (rig/vehicle/rig_config.py): the
position loop on the post mass, loaded by the tyre's dynamic force F = m_t x_t'' + suspension force,

    kp c = kp x_r + kv x_r' + m_p x_r'' + F,     drive(t - delay) = c + tau c',

all per frequency line, and the result limited to the drive band by the inverse's band window.
"""

from __future__ import annotations

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.record import Record
from rig.signal.inverse import band_window
from rig.vehicle.vehicle_file import Vehicle


def inverse_model_drive(vehicle: Vehicle, target: Record, band: tuple[float, float] = ANALYSIS_BAND) -> np.ndarray:
    """Post drives (samples x corners, m) for ``target``'s ``sprung_acc`` and ``unsprung_acc`` (m/s^2),
    on the target's time base."""
    corners = vehicle.corners
    body = target.quantity("sprung_acc", corners)
    wheel = target.quantity("unsprung_acc", corners)
    n, rate = target.n_samples, target.rate
    pad = int(round(1.0 / band[0] * rate))  # rest on both sides: the periodic transform does not wrap
    length = n + 2 * pad
    s = 2j * np.pi * np.fft.rfftfreq(length, 1.0 / rate)[:, None]
    s_safe = np.where(s == 0, 1.0, s)

    def spectrum(values: np.ndarray) -> np.ndarray:
        return np.fft.rfft(np.pad(values, ((pad, pad), (0, 0))), axis=0)

    wheel_acc, body_acc = spectrum(wheel), spectrum(body)
    axles = [vehicle.axle(c) for c in corners]
    m_t, c_s, k_s, k_t, c_t = (np.array([getattr(a, key) for a in axles]) for key in
                               ("unsprung_mass", "damping", "suspension_rate", "tyre_rate", "tyre_damping"))
    relative = (wheel_acc - body_acc) / s_safe**2  # x_t - x_b
    force = m_t * wheel_acc + (c_s * s + k_s) * relative  # tyre's dynamic force on the wheel
    post = wheel_acc / s_safe**2 + force / (k_t + c_t * s)  # x_r, Eq 5.1
    rig = vehicle.rig
    loop = rig.loop_damping_coefficient * s * post + rig.post_mass * s**2 * post
    command = post + (loop + force) / rig.loop_stiffness
    drive = command * (1 + rig.lag_time_constant * s) * np.exp(s * rig.servo_delay)
    drive *= band_window(s.imag[:, 0] / (2 * np.pi), band)[:, None]
    return np.fft.irfft(drive, length, axis=0)[pad:pad + n]
