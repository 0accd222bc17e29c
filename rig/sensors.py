"""The measurement chain of a vehicle file: per-channel calibration factors and time shifts.

[sensor_gain] and [sensor_delay] (rig/extensions.py) describe the transducers, not the mechanics, so they
are applied to the simulated channels after the run, as the real chain applies them to the real motion.
A delay shifts the channel later in time (cubic interpolation between samples; before the record starts
the first value is held).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import make_interp_spline


def apply_sensor_model(channels: dict[str, np.ndarray], extensions: dict, rate: float) -> dict[str, np.ndarray]:
    """Channels as the vehicle file's sensors would report them (new dict; others pass unchanged)."""
    gains = extensions.get("sensor_gain", {})
    delays = extensions.get("sensor_delay", {})
    unknown = sorted((set(gains) | set(delays)) - set(channels))
    if unknown:
        raise ValueError(f"[sensor_gain]/[sensor_delay] name channels the run does not have: {', '.join(unknown)}")
    out = dict(channels)
    for name, delay in delays.items():
        out[name] = delayed(out[name], delay * rate)
    for name, gain in gains.items():
        out[name] = gain * out[name]
    return out


def delayed(values: np.ndarray, samples: float) -> np.ndarray:
    """``values`` shifted later by a (fractional) number of samples."""
    times = np.clip(np.arange(values.size) - samples, 0, values.size - 1)
    return make_interp_spline(np.arange(values.size), values, k=3)(times)
