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
    operators = DriveOperators(vehicle, corners, target.n_samples, target.rate, band)
    axles = [vehicle.axle(c) for c in corners]
    c_s, k_s = (np.array([getattr(a, key) for a in axles]) for key in ("damping", "suspension_rate"))
    wheel_acc, body_acc = operators.spectrum(wheel), operators.spectrum(body)
    relative = (wheel_acc - body_acc) / operators.s_safe**2  # x_t - x_b
    suspension = (c_s * operators.s + k_s) * relative
    return operators.drive(wheel_acc, suspension)


class DriveOperators:
    """The linear operators of Eq 5.1 through the servo, per corner and frequency line: the drive is
    G_W W + G_T T, W the wheel's acceleration and T the tyre's dynamic force on the wheel, T = m_t W + F_s with F_s
    the suspension's force on the wheel (module docstring)."""

    def __init__(self, vehicle: Vehicle, corners: tuple[str, ...], n: int, rate: float, band: tuple[float, float]):
        self.n, self.pad = n, int(round(1.0 / band[0] * rate))  # rest on both sides: the transform does not wrap
        length = n + 2 * self.pad
        self.length = length
        self.s = 2j * np.pi * np.fft.rfftfreq(length, 1.0 / rate)[:, None]
        self.s_safe = np.where(self.s == 0, 1.0, self.s)
        axles = [vehicle.axle(c) for c in corners]
        self.unsprung = np.array([a.unsprung_mass for a in axles])
        k_t, c_t = (np.array([getattr(a, key) for a in axles]) for key in ("tyre_rate", "tyre_damping"))
        rig = vehicle.rig
        loop = 1 + (rig.loop_damping_coefficient * self.s + rig.post_mass * self.s**2) / rig.loop_stiffness
        servo = (1 + rig.lag_time_constant * self.s) * np.exp(self.s * rig.servo_delay)
        servo = servo * band_window(self.s.imag[:, 0] / (2 * np.pi), band)[:, None]
        self.wheel_gain = loop / self.s_safe**2 * servo                      # G_W
        self.force_gain = (loop / (k_t + c_t * self.s) + 1 / rig.loop_stiffness) * servo  # G_T

    def spectrum(self, values: np.ndarray) -> np.ndarray:
        """The padded record's spectrum (samples x corners)."""
        return np.fft.rfft(np.pad(values, ((self.pad, self.pad), (0, 0))), axis=0)

    def drive(self, wheel_acc: np.ndarray, suspension: np.ndarray, wheel_disp: np.ndarray | None = None
              ) -> np.ndarray:
        """The drive (samples x corners, m) from the spectra of the wheel's acceleration and the suspension's force
        on the wheel; with ``wheel_disp``, the spectrum of the wheel's displacement, G_W W is taken from it (the
        body's displacement plus a measured travel: far less noise at low frequency than W integrated twice)."""
        wheel = self.wheel_gain * (wheel_acc if wheel_disp is None else self.s**2 * wheel_disp)
        spectrum = wheel + self.force_gain * (self.unsprung * wheel_acc + suspension)
        return np.fft.irfft(spectrum, self.length, axis=0)[self.pad:self.pad + self.n]

    def of_force(self, forces: np.ndarray, corner: int) -> np.ndarray:
        """What forces on the wheel (samples x columns, N) of one corner add to its drive (m)."""
        spectrum = self.force_gain[:, corner:corner + 1] * self.spectrum(forces)
        return np.fft.irfft(spectrum, self.length, axis=0)[self.pad:self.pad + self.n]
