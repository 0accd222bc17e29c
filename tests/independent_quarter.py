"""An independent quarter car on a servo post, written from the equations for the tests: neither MuJoCo nor the
project's model builder, and any spring and damper law (functions of compression and its rate), so that laws no
cause of the vocabulary is can be hidden in it.

With z from the static equilibrium, up positive, compression x = z_w - z_b and its rate v:

    m_b z_b'' = F_s(x) + F_d(v)                       (beyond the static load, which the spring carries)
    m_w z_w'' = -F_s(x) - F_d(v) + T - W_w,          T = max(0, W + k_t (p - z_w))   (the tyre only pushes)
    m_p p''   = k_p (c - p) - c_p p' + S - T - m_p g (the post: position loop on its mass, static feed-forward S)
    tau c'    = drive(t - delay) - c                  (the servo's command lag)

W the static tyre load (body and wheel), W_w the wheel's weight; the servo's parameters are the vehicle file's
``[rig]``. Integrated by the classic RK4 of tests/independent_rig.py (``rk4_samples``) at two steps per sample, the
drive by a cubic spline at the half steps. Records carry what a rig measures with white noise of ``noise`` of each
channel's RMS: the drive (exact), the post's displacement, the body and wheel accelerations, the travel and the
tyre force; the truth's masses, spring rate, damping and tyre rate are off the vehicle file's by up to 3 %.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from independent_rig import rk4_samples
from scipy.interpolate import CubicSpline

from rig.io.record import Record

G = 9.80665
Law = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class QuarterTruth:
    """The truth quarter car (SI): masses, tyre rate, the suspension's laws (force on the body, up, beyond the
    static load: ``spring(x)``, ``damper(v)``) and the servo post's parameters."""

    body: float
    wheel: float
    tyre: float
    spring: Law
    damper: Law
    post_mass: float
    lag: float
    delay: float
    loop_stiffness: float
    loop_damping: float

    @classmethod
    def of(cls, vehicle, spring: Callable[[float], Law], damper: Callable[[float], Law],
           rng: np.random.Generator | None = None, error: float = 0.03) -> QuarterTruth:
        """The vehicle file's quarter car with its linear values off by up to ``error`` (with ``rng``): ``spring``
        and ``damper`` make the laws from the (perturbed) spring + parasitic rate and damping."""
        def off(value: float) -> float:
            return value if rng is None else float(value * rng.uniform(1 - error, 1 + error))

        axle, rig = vehicle.front, vehicle.rig
        return cls(off(vehicle.sprung_mass), off(axle.unsprung_mass), off(axle.tyre_rate),
                   spring(off(axle.suspension_rate)), damper(off(axle.damping)), rig.post_mass, rig.lag_time_constant,
                   rig.servo_delay, rig.loop_stiffness, rig.loop_damping_coefficient)

    def derivative(self, s: np.ndarray, drive: float) -> tuple[np.ndarray, dict]:
        zb, vb, zw, vw, p, vp, c = s
        x, v = zw - zb, vw - vb
        suspension = float(self.spring(np.array(x)) + self.damper(np.array(v)))
        load = (self.body + self.wheel) * G
        tyre = max(0.0, load + self.tyre * (p - zw))
        ab = suspension / self.body
        aw = (-suspension + tyre - load) / self.wheel
        ap = (self.loop_stiffness * (c - p) - self.loop_damping * vp + load - tyre) / self.post_mass
        dc = (drive - c) / self.lag if self.lag > 0 else 0.0
        info = {"sprung_acc": ab, "unsprung_acc": aw, "susp_travel": x, "actuator_disp": p, "tyre_force": tyre}
        return np.array([vb, ab, vw, aw, vp, ap, dc]), info

    def run(self, drive: np.ndarray, rate: float, substeps: int = 2) -> dict[str, np.ndarray]:
        """Channels (SI) at the sample times for the post drive ``drive`` (m) at ``rate`` Hz, from rest."""
        h = 1.0 / (rate * substeps)
        n = drive.size
        spline = CubicSpline(np.arange(n) / rate, drive)
        times = np.arange(2 * (n - 1) * substeps + 1) * h / 2 - self.delay
        delayed = np.where(times < 0, 0.0, spline(np.clip(times, 0, None)))
        samples = rk4_samples(self.derivative, np.zeros(7), delayed, substeps, h)
        return {k: np.array([info[k] for info in samples]) for k in samples[0]}


def quarter_record(truth: QuarterTruth, drive: np.ndarray, rate: float, rng: np.random.Generator,
                   noise: float = 0.02) -> Record:
    """A measured quarter-car rig test (corner FL): the drive as played, the rest with white noise."""
    channels = {"FL/drive": drive}
    for quantity, values in truth.run(drive, rate).items():
        channels[f"FL/{quantity}"] = values + noise * np.std(values) * rng.standard_normal(values.size)
    return Record(rate, channels, metadata={"test": "rig", "source": "independent quarter car (tests/"
                                                                     "independent_quarter.py)"})
